#!/usr/bin/env bash
# The footprint of chapter N outside its folder: the files that the commits
# adding it changed, other than its own folder, docs, READMEs and snapshots.
# A chapter that lands as a plug-in shows its registry line and little else.
#
# The commits adding chapter N are those from the first that adds a file of
# chapter N (in chapters/NN_*/, or src/chapters/chNN_* before chapters were
# folders) up to, not including, the first that adds a file of chapter N+1;
# for the last chapter, up to HEAD. `--until REV` ends the range at REV
# (included) instead.
#
# Usage: scripts/chapter-footprint.sh N [--until REV] [--commits]
#   --commits also lists the commits of the range.
# Prints one file a line, then "N files outside chapters/NN_*/ in C commits".
set -euo pipefail

usage() {
    echo "usage: $0 N [--until REV] [--commits]" >&2
    exit 2
}

[[ $# -ge 1 && $1 =~ ^[0-9]+$ ]] || usage
number=$((10#$1))
shift
until=""
list_commits=false
while [[ $# -gt 0 ]]; do
    case $1 in
    --until)
        [[ $# -ge 2 ]] || usage
        until=$2
        shift 2
        ;;
    --commits)
        list_commits=true
        shift
        ;;
    *) usage ;;
    esac
done

cd "$(git rev-parse --show-toplevel)"
padded=$(printf '%02d' "$number")
next=$(printf '%02d' $((number + 1)))

# The first commit adding a file of chapter `$1` (two digits), if any.
first_adding() {
    git log --reverse --diff-filter=A --format=%H -- "chapters/$1_*" "src/chapters/ch$1_*" |
        awk 'NR == 1'
}

start=$(first_adding "$padded")
if [[ -z $start ]]; then
    echo "no commit adds a file of chapter $number (chapters/${padded}_*/)" >&2
    exit 1
fi
# The history up to the range's end, oldest first (by commit date), cut
# from `start` to the commit before the next chapter's first.
head=HEAD
stop=""
if [[ -n $until ]]; then
    head=$(git rev-parse --verify --quiet "$until^{commit}") || {
        echo "--until $until: not a commit" >&2
        exit 1
    }
else
    stop=$(first_adding "$next")
fi
if [[ $stop == "$start" ]]; then
    # Chapters N and N+1 came in one commit: that commit is chapter N's.
    commits=$start
else
    commits=$(git rev-list --reverse "$head" |
        awk -v start="$start" -v stop="$stop" '
            $0 == stop { done = 1 }
            $0 == start { inside = 1 }
            inside && !done { print }')
fi
if [[ -z $commits ]]; then
    echo "chapter $number's first commit is not in the history of $head" >&2
    exit 1
fi
count=$(printf '%s\n' "$commits" | grep -c . || true)

if $list_commits; then
    printf '%s\n' "$commits" | while read -r commit; do
        git log -1 --format='%h %s' "$commit"
    done
    echo
fi

files=$(printf '%s\n' "$commits" | while read -r commit; do
    git diff-tree --no-commit-id --name-only -r --root "$commit"
done | sort -u |
    grep -v -E "^chapters/${padded}_[^/]*/|^src/chapters/ch${padded}_|^docs/|(^|/)README\.md$|^snapshots/" ||
    true)

if [[ -n $files ]]; then
    printf '%s\n' "$files"
fi
outside=$(printf '%s\n' "$files" | grep -c . || true)
echo "$outside files outside chapters/${padded}_*/ in $count commits"
