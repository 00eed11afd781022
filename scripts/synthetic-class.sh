#!/usr/bin/env bash
# A synthetic class for `raylab grade`, and what grading it costs.
#
# Makes CLASS_DIR with STUDENTS folders of hand-ins at the lessons' sizes
# (what `raylab render --chapter N` writes), one of four
# kinds in turn: every chapter right; every odd chapter wrong (the previous
# chapter's image handed in for it); chapters 4 on missing; and hostile
# (the right images, plus a FIFO, a symbolic link out of the folder, a
# folder named chapter-2.png, a PNG whose header declares 16384x2441 pixels
# and a file named with a terminal escape). Then, unless --make-only, it
# grades the class with /usr/bin/time and prints the wall time and the peak
# resident memory, and checks the gradebook CSV (--gradebook) it wrote: a
# row per student, each kind's total what it should be.
#
# Usage: scripts/synthetic-class.sh STUDENTS CLASS_DIR [--make-only]
#   The images are hard links to one render per chapter, made once, so a class of
#   500 takes a few megabytes of disk. CLASS_DIR is emptied first.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [[ $# -lt 2 ]]; then
    echo "usage: $0 STUDENTS CLASS_DIR [--make-only]" >&2
    exit 2
fi
students=$1
class=$2
make_only=${3:-}
# RAYLAB_BIN: a raylab already built (the release build otherwise).
raylab=${RAYLAB_BIN:-}
if [[ -z $raylab ]]; then
    cargo build --release --quiet --manifest-path "$root/Cargo.toml"
    raylab="${CARGO_TARGET_DIR:-$root/target}/release/raylab"
fi
# As many chapters as this raylab's registry lists, one a line.
chapters=$("$raylab" chapters | wc -l)

rm -rf "$class"
mkdir -p "$class"
renders="$class/../$(basename "$class")-renders"
rm -rf "$renders"
mkdir -p "$renders"
for chapter in $(seq 1 $chapters); do
    "$raylab" render --chapter "$chapter" -o "$renders/chapter-$chapter.png" >/dev/null 2>&1
done
# A 116-byte-header PNG that declares 16384x2441: chapter 1's image with
# its IHDR size (and CRC) rewritten.
python3 - "$renders/chapter-1.png" "$renders/huge.png" <<'EOF'
import struct, sys, zlib
data = bytearray(open(sys.argv[1], "rb").read())
ihdr = data[12:29]
patched = b"IHDR" + struct.pack(">II", 16384, 2441) + bytes(ihdr[12:17])
data[12:29] = patched
data[29:33] = struct.pack(">I", zlib.crc32(patched) & 0xFFFFFFFF)
open(sys.argv[2], "wb").write(bytes(data))
EOF

for index in $(seq 1 "$students"); do
    student="$class/$(printf 'student-%04d' "$index")"
    mkdir "$student"
    case $((index % 4)) in
    0)
        for chapter in $(seq 1 $chapters); do
            ln "$renders/chapter-$chapter.png" "$student/chapter-$chapter.png"
        done
        ;;
    1)
        for chapter in $(seq 1 $chapters); do
            from=$chapter
            if ((chapter % 2 == 1 && chapter > 1)); then from=$((chapter - 1)); fi
            ln "$renders/chapter-$from.png" "$student/chapter-$chapter.png"
        done
        ;;
    2)
        for chapter in 1 2 3; do
            ln "$renders/chapter-$chapter.png" "$student/chapter-$chapter.png"
        done
        ;;
    3)
        for chapter in $(seq 3 $chapters); do
            ln "$renders/chapter-$chapter.png" "$student/chapter-$chapter.png"
        done
        ln "$renders/huge.png" "$student/chapter-1.png"
        mkfifo "$student/chapter-4.png.fifo"
        ln -s /etc/passwd "$student/chapter-5.png.link"
        mkdir "$student/chapter-2.png"
        touch "$student/$(printf 'notes-\033[2J.txt')"
        ;;
    esac
done

if [[ $make_only == --make-only ]]; then
    echo "made $students students in $class"
    exit 0
fi
status=0
/usr/bin/time -f '%e s wall, %M KB peak resident' \
    "$raylab" grade "$class" --gradebook "$class.gradebook.csv" --force \
    >/dev/null 2>"$class.time" || status=$?
tail -1 "$class.time"
echo "grade exited $status (1: some students fail, as they should)"

# The gradebook: the header, then one row per student whose total is their
# kind's: every chapter; the even ones and chapter 1; chapters 1 to 3; and
# chapters 3 on (the hostile kind's chapter 1 is refused, its 2 a folder).
python3 - "$class.gradebook.csv" "$students" "$chapters" <<'CHECK'
import csv, sys
path, students, chapters = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rows = list(csv.reader(open(path, newline="")))
header, rows = rows[0], rows[1:]
assert header[:5] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section"], header
assert header[5:] == [f"raylab chapter {n}" for n in range(1, chapters + 1)] + [f"raylab total ({chapters})"], header
assert len(rows) == students, f"{len(rows)} rows for {students} students"
expected = {0: chapters, 1: 1 + chapters // 2, 2: 3, 3: chapters - 2}
for row in rows:
    index = int(row[0].removeprefix("student-"))
    scores = [int(cell) for cell in row[5:5 + chapters]]
    assert int(row[-1]) == sum(scores) == expected[index % 4], (row, expected[index % 4])
print(f"gradebook: {len(rows)} students, {chapters} chapters, each total as expected: {path}")
CHECK
