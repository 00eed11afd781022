//! `raylab grade` on a folder of real renders: one matching the committed
//! snapshot, one at another size (its reference is rendered), one at another
//! depth (fails), one corrupted, the rest missing, and odd files beside.

use crate::common;
use common::{raylab, stderr, stdout};

use std::path::{Path, PathBuf};

use base64::Engine as _;

/// The number of chapters: a class folder is graded against all of them.
const LAST: u8 = raylab::chapters::LAST_CHAPTER;

fn snapshots() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("snapshots")
}

fn render(
    chapter: u8,
    width: u32,
    height: u32,
    tweak: impl FnOnce(&mut raylab::RenderSettings),
) -> raylab::Rendered {
    let scene = raylab::builtin::scene(chapter).expect("built-in scene");
    let mut settings = raylab::RenderSettings {
        width,
        height,
        ..scene.render
    };
    tweak(&mut settings);
    raylab::render(&scene, chapter, &settings, None).expect("renders")
}

fn save(path: &Path, image: &raylab::Rendered) {
    raylab::output::write_png(path, image.width, image.height, &image.rgb).expect("write PNG");
}

/// Every `data:image/png;base64,` image in the report, decoded.
fn inlined_images(html: &str) -> Vec<image::RgbImage> {
    html.split("src=\"data:image/png;base64,")
        .skip(1)
        .map(|rest| {
            let data = &rest[..rest.find('"').expect("closing quote")];
            let bytes = base64::engine::general_purpose::STANDARD
                .decode(data)
                .expect("valid base64");
            image::load_from_memory(&bytes).expect("a PNG").to_rgb8()
        })
        .collect()
}

#[test]
fn a_mixed_folder_is_graded_and_reported() {
    let dir = tempfile::tempdir().expect("temp dir");
    let students = dir.path().join("class");
    std::fs::create_dir(&students).expect("mkdir");
    // Chapter 1 at the snapshot's size: compared with the committed PNG.
    save(
        &students.join("chapter-1.png"),
        &render(1, 160, 120, |_| {}),
    );
    // Chapter 2 at another size: the reference is rendered at 64x48.
    let chapter_2 = render(2, 64, 48, |_| {});
    save(&students.join("chapter-2.png"), &chapter_2);
    // Chapter 6 with one bounce instead of five: fails.
    let shallow = render(6, 64, 48, |s| s.max_depth = 1);
    save(&students.join("chapter-6.png"), &shallow);
    // Chapter 4 cut short.
    save(&students.join("chapter-4.png"), &render(4, 64, 48, |_| {}));
    let bytes = std::fs::read(students.join("chapter-4.png")).expect("read");
    std::fs::write(students.join("chapter-4.png"), &bytes[..bytes.len() / 3]).expect("write");
    // Things that are not a chapter's render.
    std::fs::write(students.join("notes.txt"), "hello").expect("write");
    std::fs::create_dir(students.join("drafts")).expect("mkdir");
    std::fs::write(students.join("chapter-99.png"), &bytes).expect("write");
    std::fs::write(students.join("chapter-x.png"), &bytes).expect("write");
    std::fs::write(students.join("chapter-3.PNG"), &bytes).expect("write");

    let against = snapshots();
    let against = against.to_str().expect("UTF-8 path");
    let out = raylab(&["grade", "class", "--against", against], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    let row = |chapter: u8| -> String {
        md.lines()
            .find(|line| line.starts_with(&format!("| {chapter} |")))
            .unwrap_or_else(|| panic!("no row for chapter {chapter} in:\n{md}"))
            .to_string()
    };
    let row_1 = row(1);
    assert!(
        row_1.contains("| 160x120 | 0 | 0.0000 | 0.0000 | inf |"),
        "{row_1}"
    );
    assert!(row_1.contains("| PASS |"), "{row_1}");
    assert!(row_1.ends_with("snapshots/chapter-1.png |"), "{row_1}");
    let row_2 = row(2);
    assert!(row_2.contains("| 64x48 | 0 |"), "{row_2}");
    assert!(row_2.contains("| PASS |"), "{row_2}");
    assert!(
        row_2.contains("built-in scene rendered at 64x48") && row_2.contains("is 160x120"),
        "{row_2}"
    );
    // Chapter 6's figures, computed here from the two renders.
    let reference_6 = render(6, 64, 48, |_| {});
    let diffs: Vec<u8> = shallow
        .rgb
        .iter()
        .zip(&reference_6.rgb)
        .map(|(a, b)| a.abs_diff(*b))
        .collect();
    let max = *diffs.iter().max().expect("pixels");
    let over = diffs.chunks(3).filter(|p| p.iter().any(|&d| d > 2)).count();
    let row_6 = row(6);
    assert!(
        row_6.contains(&format!("| 64x48 | {max} |")),
        "{row_6} (max {max})"
    );
    assert!(
        row_6.contains(&format!("| {over} (")),
        "{row_6} (over {over})"
    );
    assert!(row_6.contains("| **FAIL** |"), "{row_6}");
    assert!(
        md.contains(&format!(
            "Missing: chapter-3.png (chapter-3.PNG: the extension must be .png in lower case), chapter-5.png, chapter-7.png, chapter-8.png, {}",
            (9..=LAST)
                .map(|n| format!("chapter-{n}.png"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
        "{md}"
    );
    assert!(md.contains("- chapter-4.png: corrupted PNG"), "{md}");
    for ignored in [
        "- chapter-3.PNG: the extension must be .png in lower case",
        "- chapter-99.png: there is no chapter 99",
        "- chapter-x.png: not named chapter-N.png",
        "- drafts: a folder",
        "- notes.txt: not a .png file",
    ] {
        assert!(md.contains(ignored), "{ignored:?} not in:\n{md}");
    }
    assert!(
        md.contains(&format!(
            "**2 of {LAST} chapters pass** (3 compared, {} missing, 1 unreadable)",
            LAST - 4
        )),
        "{md}"
    );

    // The report is self-contained: every image is inlined, nothing is linked.
    let report = students.join("report.html");
    let html = std::fs::read_to_string(&report).expect("report written");
    assert!(
        !html.contains("http")
            && html.matches("src=\"").count() == html.matches("src=\"data:").count(),
        "no external resources"
    );
    let images = inlined_images(&html);
    assert_eq!(
        images.len(),
        9,
        "student, reference and heatmap for 3 chapters"
    );
    assert_eq!(
        images[3].as_raw(),
        &chapter_2.rgb,
        "chapter 2's student image"
    );
    assert_eq!(
        images[4].as_raw(),
        &chapter_2.rgb,
        "chapter 2's rendered reference"
    );
    assert_eq!(
        images[7].as_raw(),
        &reference_6.rgb,
        "chapter 6's rendered reference"
    );
    let heatmap_6 = &images[8];
    assert_eq!(heatmap_6.width(), 64);
    assert!(heatmap_6.height() > 48, "the heatmap carries its legend");
    for needle in [
        "Chapter 6 <span class=\"badge\">FAIL</span>",
        "Chapter 1 <span class=\"badge\">PASS</span>",
        "<td>inf dB</td>",
        "<code>chapter-4.png</code>: corrupted PNG",
        "<code>notes.txt</code>: not a .png file",
        "chapter-7.png",
    ] {
        assert!(html.contains(needle), "{needle:?} not in the report");
    }

    // Grading again does not list the report itself among the ignored files.
    let again = raylab(&["grade", "class", "--against", against], dir.path());
    assert_eq!(stdout(&again), md);
}

#[test]
fn a_complete_correct_folder_passes() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::create_dir(dir.path().join("class")).expect("mkdir");
    for chapter in 1..=raylab::chapters::LAST_CHAPTER {
        save(
            &dir.path().join(format!("class/chapter-{chapter}.png")),
            &render(chapter, 48, 36, |_| {}),
        );
    }
    let report = dir.path().join("out").join("grade.html");
    std::fs::create_dir(dir.path().join("out")).expect("mkdir");
    let out = raylab(
        &[
            "grade",
            "class",
            "--against",
            snapshots().to_str().expect("UTF-8"),
            "--report",
            report.to_str().expect("UTF-8"),
        ],
        dir.path(),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}{}",
        stdout(&out),
        stderr(&out)
    );
    let md = stdout(&out);
    assert!(
        md.contains(&format!(
            "**{LAST} of {LAST} chapters pass** ({LAST} compared, 0 missing, 0 unreadable)"
        )),
        "{md}"
    );
    assert!(!md.contains("Ignored"), "{md}");
    let html = std::fs::read_to_string(&report).expect("report");
    assert_eq!(inlined_images(&html).len(), 3 * LAST as usize);
    assert!(!dir.path().join("class/report.html").exists());
}

#[test]
fn a_tiny_hand_in_is_not_graded() {
    // At 4x3 the reference would be rendered at 4x3 too, and an image that
    // small is easy to match: it is listed as unreadable, not passed.
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    std::fs::create_dir(&class).expect("mkdir");
    save(&class.join("chapter-7.png"), &render(7, 4, 3, |_| {}));
    let out = raylab(&["grade", "class"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    assert!(
        md.contains(&format!("0 compared, {} missing, 1 unreadable", LAST - 1)),
        "{md}"
    );
    assert!(md.contains("too small to grade: 4x3"), "{md}");
}

#[test]
fn a_hand_in_at_a_size_of_its_own_is_not_graded() {
    // Its reference would be rendered at the size the student chose: a
    // class handing in a size each would cost a render each. A small size,
    // the lesson's and an --against image's are graded.
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    std::fs::create_dir(&class).expect("mkdir");
    let odd = render(1, 200, 150, |_| {});
    save(&class.join("chapter-1.png"), &odd);
    save(&class.join("chapter-2.png"), &render(2, 150, 120, |_| {}));
    let out = raylab(&["grade", "class"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    assert!(
        md.contains(&format!("1 compared, {} missing, 1 unreadable", LAST - 2)),
        "{md}"
    );
    assert!(
        md.contains("not graded at 200x150: references are made at the lesson's size, 640x480"),
        "{md}"
    );
    assert!(md.contains("raylab render --chapter 1"), "{md}");
    // The instructor's own image of that size is the reference.
    let against = dir.path().join("mine");
    std::fs::create_dir(&against).expect("mkdir");
    save(&against.join("chapter-1.png"), &odd);
    let out = raylab(&["grade", "class", "--against", "mine"], dir.path());
    let md = stdout(&out);
    assert!(
        md.contains(&format!("2 compared, {} missing, 0 unreadable", LAST - 2)),
        "{md}"
    );
}

#[test]
fn errors_exit_2_and_write_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::create_dir(dir.path().join("class")).expect("mkdir");
    save(
        &dir.path().join("class/chapter-1.png"),
        &render(1, 32, 24, |_| {}),
    );
    for (args, message) in [
        (vec!["grade", "absent"], "absent: not a folder"),
        (
            vec!["grade", "class", "--against", "nowhere"],
            "--against nowhere: not a folder",
        ),
        (
            vec!["grade", "class", "--report", "no/such/folder/r.html"],
            "--report no/such/folder/r.html: the folder no/such/folder does not exist",
        ),
        (
            // The report over a hand-in would destroy it.
            vec!["grade", "class", "--report", "class/chapter-1.png"],
            "that is an input",
        ),
    ] {
        let out = raylab(&args, dir.path());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stdout(&out));
        let text = stderr(&out);
        assert!(
            text.starts_with("error: ") && text.contains(message),
            "{text}"
        );
    }
    assert!(!dir.path().join("class/report.html").exists());
    let hand_in = image::open(dir.path().join("class/chapter-1.png")).expect("still a PNG");
    assert_eq!((hand_in.width(), hand_in.height()), (32, 24));
}

/// `grade` must not follow symbolic links out of the folder (a link to
/// someone's correct image would be graded PASS and embedded in the report;
/// a link to /etc/passwd would be read) nor block on a FIFO. A link is listed
/// as refused and never read or shown; a FIFO or a device is unreadable,
/// without blocking; a FIFO in the --against folder falls back to a render.
#[cfg(unix)]
#[test]
fn links_fifos_and_devices_among_hand_ins_are_refused_unread() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let against = dir.path().join("against");
    std::fs::create_dir(&class).expect("mkdir");
    std::fs::create_dir(&against).expect("mkdir");
    // A correct image outside the folder, which would pass chapter 8.
    let private = dir.path().join("private.png");
    save(&private, &render(8, 32, 24, |_| {}));
    std::os::unix::fs::symlink(&private, class.join("chapter-8.png")).expect("symlink");
    std::os::unix::fs::symlink("/etc/passwd", class.join("chapter-7.png")).expect("symlink");
    std::os::unix::fs::symlink("/dev/zero", class.join("notes.txt")).expect("symlink");
    common::make_fifo(&class.join("chapter-5.png"));
    // A real hand-in, whose reference in --against is a FIFO.
    save(&class.join("chapter-1.png"), &render(1, 32, 24, |_| {}));
    common::make_fifo(&against.join("chapter-1.png"));

    let out = common::raylab_unblocked(&["grade", "class", "--against", "against"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    assert!(
        md.contains(&format!("1 compared, {} missing, 3 unreadable", LAST - 4)),
        "{md}"
    );
    assert!(
        md.contains("- chapter-8.png: refused: a symbolic link; a hand-in must be a regular file inside the folder"),
        "{md}"
    );
    assert!(
        md.contains("- chapter-7.png: refused: a symbolic link"),
        "{md}"
    );
    assert!(
        md.contains("chapter-5.png: is a FIFO (named pipe), not a regular file"),
        "{md}"
    );
    assert!(md.contains("- notes.txt: refused: a symbolic link"), "{md}");
    assert!(md.contains("is a FIFO"), "{md}");
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    // Only chapter 1's three images: nothing of the linked image.
    assert_eq!(inlined_images(&html).len(), 3);
    assert!(!html.contains("root:"), "nothing of /etc/passwd");
}

/// Names are escaped for each output: Markdown escapes in the summary (a
/// hand-in named `<img src=x onerror=alert(2)>` must not become markup
/// where the summary is pasted), no terminal control characters on stdout,
/// HTML escapes in the report.
#[test]
fn hostile_names_are_escaped_in_markdown_terminal_and_html() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    std::fs::create_dir(&class).expect("mkdir");
    std::fs::write(class.join("<img src=x onerror=alert(2)>"), "x").expect("write");
    std::fs::write(class.join("\u{1b}[2J\u{1b}]0;pwned\u{7}.png"), "x").expect("write");
    std::fs::write(class.join("a*b_[c](d)`e`.png"), "x").expect("write");
    let out = raylab(&["grade", "class"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    assert!(!md.replace("\\<", "").contains('<'), "an unescaped <: {md}");
    assert!(md.contains("\\<img src=x onerror=alert(2)\\>"), "{md}");
    assert!(md.contains("a\\*b\\_\\[c\\](d)\\`e\\`.png"), "{md}");
    assert!(!md.contains('\u{1b}') && !md.contains('\u{7}'), "{md:?}");
    // The terminal's escapes first (ESC, BEL), then Markdown's (`[`, and
    // the backslash, so that the Markdown shows `\u{1b}`).
    assert!(
        md.contains("\\\\u{1b}\\[2J\\\\u{1b}\\]0;pwned\\\\u{7}.png"),
        "{md}"
    );
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    assert!(!html.contains("<img src=x"), "raw markup in the report");
    assert!(html.contains("&lt;img src=x onerror=alert(2)&gt;"));
}

/// Chapter 1 as a student might break it in raylab's own reference: every ray is tested mirrored in the horizon, so
/// the floor is drawn in the sky. A raylab rebuilt with it has this as its
/// "reference" chapters.
struct FloorInTheSky;

impl raylab::Chapters for FloorInTheSky {
    fn intersect_plane(
        plane: &raylab::Plane,
        ray: &raylab::Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<f32> {
        let mirrored = raylab::Ray::new(
            ray.origin,
            raylab::Vec3::new(ray.dir.x, -ray.dir.y, ray.dir.z),
        );
        <raylab::Reference as raylab::Chapters>::intersect_plane(plane, &mirrored, t_min, t_max)
    }
}

fn render_with<C: raylab::Chapters>(chapter: u8, width: u32, height: u32) -> raylab::Rendered {
    let scene = raylab::builtin::scene(chapter).expect("built-in scene");
    let settings = raylab::RenderSettings {
        width,
        height,
        ..scene.render
    };
    raylab::render_with::<C>(&scene, chapter, &settings, None).expect("renders")
}

/// Grades `class` as a raylab built with the chapters `C` would.
fn grade_as<C: raylab::Chapters>(class: &Path) -> raylab::grade::Grade {
    raylab::grade::grade_with(
        class,
        &mut raylab::grade::References::<C>::new(None),
        raylab::diff::Criteria::default(),
        None,
    )
    .expect("grades")
}

/// A false PASS to rule out: a student breaks chapter 1 in their raylab
/// checkout, rebuilds, renders and grades with that same raylab. Its
/// reference chapters are the student's code, so a reference rendered with
/// them would match the hand-in bit for bit (PASS, max difference 0). The
/// hand-in fails at the shipped size, and at any other size the modified
/// chapters are caught before they render a reference.
#[test]
fn a_hand_in_from_modified_reference_chapters_never_passes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    std::fs::create_dir(&class).expect("mkdir");
    let hand_in = class.join("chapter-1.png");
    let broken = render_with::<FloorInTheSky>(1, 160, 120);
    assert_ne!(
        broken.rgb,
        render_with::<raylab::Reference>(1, 160, 120).rgb,
        "the planted bug changes the picture"
    );

    // (a) At 640x480, `raylab render`'s default size: refused.
    save(&hand_in, &render_with::<FloorInTheSky>(1, 640, 480));
    let grade = grade_as::<FloorInTheSky>(&class);
    assert!(
        grade.graded.iter().all(|g| g.chapter != 1),
        "chapter 1 graded against the student's own code: {:?}",
        grade
            .graded
            .first()
            .map(|g| (&g.reference_source, g.passes()))
    );
    let refused = grade
        .unreadable
        .iter()
        .find(|u| u.chapter == 1)
        .expect("chapter 1 listed as not graded");
    assert!(
        refused.reason.contains(
            "this raylab's chapters differ from the shipped references; grade at 160x120 or \
             use an unmodified raylab"
        ),
        "{}",
        refused.reason
    );
    assert!(!grade.all_pass());

    // (b) At 160x120: compared with the shipped image, and fails.
    save(&hand_in, &broken);
    let grade = grade_as::<FloorInTheSky>(&class);
    let graded = grade
        .graded
        .iter()
        .find(|g| g.chapter == 1)
        .expect("chapter 1 graded");
    assert!(!graded.passes(), "{:?}", graded.comparison.metrics);
    assert!(graded.comparison.metrics.max > 0);
    assert!(
        graded.reference_source.contains("shipped"),
        "{}",
        graded.reference_source
    );

    // The same hand-ins from unmodified chapters pass, graded by them.
    save(&hand_in, &render_with::<raylab::Reference>(1, 640, 480));
    let grade = grade_as::<raylab::Reference>(&class);
    assert_eq!(grade.passed(), 1, "{:?}", grade.unreadable);
    assert!(
        grade.graded[0]
            .reference_source
            .contains("rendered at 640x480")
    );
}

/// `raylab grade CLASS/`: one folder per student, one report and one CSV.
/// A linked student's folder is refused unread; a hostile folder name is
/// escaped everywhere and defused in the CSV.
#[test]
fn a_class_is_graded_into_one_report_and_a_csv() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    for student in ["alice", "bob", "<i>eve", "=SUM(1+1)"] {
        std::fs::create_dir_all(class.join(student)).expect("mkdir");
    }
    // alice: everything right, at 48x36.
    for chapter in 1..=raylab::chapters::LAST_CHAPTER {
        save(
            &class.join(format!("alice/chapter-{chapter}.png")),
            &render(chapter, 48, 36, |_| {}),
        );
    }
    // bob: chapter 1 at the shipped size, chapter 6 with one bounce.
    save(
        &class.join("bob/chapter-1.png"),
        &render(1, 160, 120, |_| {}),
    );
    save(
        &class.join("bob/chapter-6.png"),
        &render(6, 48, 36, |s| s.max_depth = 1),
    );
    std::fs::write(class.join("<i>eve/chapter-2.png"), "not a PNG").expect("write");
    // mallory's folder is a link to alice's: never followed.
    #[cfg(unix)]
    std::os::unix::fs::symlink(class.join("alice"), class.join("mallory")).expect("symlink");
    std::fs::write(class.join("notes.txt"), "x").expect("write");

    let out = raylab(&["grade", "class"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    let line = |student: &str| -> String {
        md.lines()
            .find(|line| line.starts_with(&format!("| {student} |")))
            .unwrap_or_else(|| panic!("no row for {student} in:\n{md}"))
            .to_string()
    };
    let all = raylab::chapters::LAST_CHAPTER;
    assert!(
        line("alice").ends_with(&format!("| {all} of {all} pass |")),
        "{md}"
    );
    let bob = line("bob");
    assert!(
        bob.starts_with("| bob | pass | missing | missing | missing | missing | **fail** |"),
        "{bob}"
    );
    assert!(line("\\<i\\>eve").contains("| unreadable |"), "{md}");
    #[cfg(unix)]
    assert!(
        line("mallory")
            .contains("refused: a symbolic link; a student's folder must be a real folder"),
        "{md}"
    );
    assert!(md.contains("- notes.txt: not a student's folder"), "{md}");
    assert!(md.contains("**1 of "), "{md}");

    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV written");
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(
        rows[0],
        "student,chapter,status,max,mean,rmse,psnr_db,pixels_over,percent_over,size,detail"
    );
    assert!(
        csv.contains(
            "alice,3,pass,0,0.000000,0.000000,inf,0,0.0000,48x36,\"built-in scene rendered at 48x36"
        ),
        "{csv}"
    );
    assert!(
        csv.contains("bob,1,pass,0,0.000000,0.000000,inf,0,0.0000,160x120,raylab's shipped reference snapshots/chapter-1.png"),
        "{csv}"
    );
    assert!(csv.contains("bob,6,fail,"), "{csv}");
    assert!(csv.contains("bob,2,missing,"), "{csv}");
    assert!(csv.contains("<i>eve,2,unreadable,"), "{csv}");
    // A spreadsheet would run this name as a formula without the quote.
    assert!(csv.contains("'=SUM(1+1),1,missing,"), "{csv}");
    #[cfg(unix)]
    assert!(csv.contains("mallory,all,refused,"), "{csv}");
    assert_eq!(
        csv.lines().filter(|l| l.starts_with("alice,")).count(),
        usize::from(raylab::chapters::LAST_CHAPTER),
        "one row per chapter"
    );

    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    assert!(!html.contains("<i>eve"), "a name became markup");
    assert!(html.contains("&lt;i&gt;eve"));
    assert!(!html.contains("http"));
    // Images only for the failing chapter: bob's chapter 6.
    let images = inlined_images(&html);
    assert_eq!(
        images.len(),
        3,
        "student, reference and heatmap of bob's chapter 6"
    );
    assert_eq!((images[0].width(), images[0].height()), (48, 36));

    // Grading again lists neither the report nor the CSV.
    let again = raylab(&["grade", "class"], dir.path());
    assert_eq!(stdout(&again), md);
}

/// The class-scale findings: an unreadable student folder refuses that
/// student alone; a PNG declaring 40 million pixels is refused from its
/// header; a misnamed file is named where its chapter is missing; names
/// with escapes, bidirectional overrides and bytes that are not UTF-8 reach
/// the CSV and the HTML as visible escapes, different names differently.
#[test]
fn a_class_survives_hostile_folders_and_names() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    for student in ["alice", "locked", "\u{1b}]0;owned\u{7}", "gnp.\u{202e}exe"] {
        std::fs::create_dir_all(class.join(student)).expect("mkdir");
    }
    let right = render(1, 48, 36, |_| {});
    save(&class.join("alice/chapter-1.png"), &right);
    save(
        &class.join("alice/Chapter-3.PNG"),
        &render(3, 48, 36, |_| {}),
    );
    // A real PNG whose header is rewritten to declare 16384x2441.
    let mut bytes =
        raylab::output::encode_png(right.width, right.height, &right.rgb).expect("encodes");
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(16384u32.to_be_bytes());
    ihdr.extend(2441u32.to_be_bytes());
    ihdr.extend(&bytes[24..29]);
    let crc = common::crc32(&ihdr);
    bytes[12..29].copy_from_slice(&ihdr);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(class.join("alice/chapter-2.png"), &bytes).expect("write");
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        for name in [&b"a\xff"[..], &b"a\xfe"[..]] {
            std::fs::create_dir(class.join(std::ffi::OsStr::from_bytes(name))).expect("mkdir");
        }
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(class.join("locked"), std::fs::Permissions::from_mode(0o000))
            .expect("chmod");
    }
    let started = std::time::Instant::now();
    let out = as_without_read_override(&["grade", "class"], dir.path());
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(class.join("locked"), std::fs::Permissions::from_mode(0o755))
            .expect("chmod back");
    }
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV written");
    assert!(csv.contains("locked,all,refused,"), "{csv}");
    assert!(
        csv.contains("alice,2,unreadable,,,,,,,,too large to grade: 16384x2441"),
        "{csv}"
    );
    assert!(
        started.elapsed() < std::time::Duration::from_secs(120),
        "the 40-megapixel reference was not rendered"
    );
    assert!(
        csv.contains(
            "alice,3,missing,,,,,,,,no chapter-3.png (Chapter-3.PNG: the extension must be .png in lower case)"
        ),
        "{csv}"
    );
    assert!(
        !csv.contains('\u{1b}') && !csv.contains('\u{202e}'),
        "{csv}"
    );
    assert!(csv.contains("\\u{1b}]0;owned\\u{7},1,missing"), "{csv}");
    assert!(csv.contains("gnp.\\u{202e}exe,"), "{csv}");
    #[cfg(unix)]
    {
        assert!(csv.contains("a\\xff,"), "{csv}");
        assert!(csv.contains("a\\xfe,"), "{csv}");
    }
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    assert!(!html.contains('\u{202e}') && !html.contains('\u{1b}'));
    assert!(html.contains("Chapter-3.PNG: the extension must be .png in lower case"));
    let md = stdout(&out);
    assert!(!md.contains('\u{202e}') && !md.contains('\u{1b}'), "{md}");
}

/// Students' folders whose names differ only by characters that show as
/// nothing (`alice`, `alice` + a zero-width space, `ali` + a soft hyphen +
/// `ce`, and a byte-order mark, directional marks, a line separator) are
/// told apart in the summary, the CSV and the HTML: each such character is
/// a visible escape, and none is written as it is (a line separator would
/// split the summary's Markdown row).
#[test]
fn names_that_differ_by_invisible_characters_look_different() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let invisible = [
        '\u{200b}', '\u{ad}', '\u{feff}', '\u{200f}', '\u{61c}', '\u{2028}',
    ];
    let students = [
        "alice".to_string(),
        "alice\u{200b}".to_string(),
        "ali\u{ad}ce".to_string(),
        "\u{feff}alice".to_string(),
        "alice\u{200f}".to_string(),
        "alice\u{61c}".to_string(),
        "alice\u{2028}| pass |".to_string(),
    ];
    for student in &students {
        std::fs::create_dir_all(class.join(student)).expect("mkdir");
    }
    let out = raylab(&["grade", "class"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV written");
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    for (what, text) in [("summary", &md), ("CSV", &csv), ("HTML", &html)] {
        assert!(!text.contains(invisible), "{what}: {text:?}");
    }
    for shown in [
        "alice\\u{200b}",
        "ali\\u{ad}ce",
        "\\u{feff}alice",
        "alice\\u{200f}",
        "alice\\u{61c}",
        "alice\\u{2028}",
    ] {
        assert!(csv.contains(shown), "{shown} in {csv}");
        assert!(html.contains(shown), "{shown} in the HTML");
    }
    // Every row of the summary's table is one line: 7 students, 7 rows.
    let rows = md
        .lines()
        .filter(|line| line.starts_with("| ali") || line.starts_with("| \\"))
        .count();
    assert_eq!(rows, students.len(), "{md}");
}

/// Students' folders whose names would look alike though every character
/// shows (`jos\u{e9}` composed and decomposed, `alice` with a Cyrillic
/// `\u{430}`, a trailing space, non-breaking, ideographic and braille
/// blank spaces) are spelled out in the summary, the CSV and the HTML, and
/// one student's job finds its student by the folder's own name.
#[test]
fn names_that_would_look_alike_are_spelled_out() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let students = [
        ("jos\u{e9}", "jos\\u{e9}"),
        ("jose\u{301}", "jose\\u{301}"),
        ("alice", "alice"),
        ("\u{430}lice", "\\u{430}lice"),
        ("alice ", "alice\\u{20}"),
        ("bo b", "bo\\u{20}b"),
        ("bo\u{a0}b", "bo\\u{a0}b"),
        ("bo\u{3000}b", "bo\\u{3000}b"),
        ("bo\u{2800}b", "bo\\u{2800}b"),
    ];
    for (student, _) in &students {
        std::fs::create_dir_all(class.join(student)).expect("mkdir");
    }
    let out = raylab(&["grade", "class"], dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV written");
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    for (_, shown) in &students {
        // Markdown doubles a backslash to show it.
        let row = format!("| {} |", shown.replace('\\', "\\\\"));
        assert!(md.contains(&row), "{row} in {md}");
        assert!(
            csv.lines().any(|line| line.starts_with(shown)),
            "{shown} in {csv}"
        );
        assert!(html.contains(shown), "{shown} in the HTML");
    }
    for (name, _) in &students[..2] {
        assert!(!md.contains(name), "{name:?} written as it is: {md}");
    }
    let out = raylab(
        &[
            "grade",
            "class",
            "--student",
            "alice ",
            "--result",
            "alice.json",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let result: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("alice.json")).expect("result written"),
    )
    .expect("a result is JSON");
    assert_eq!(result["student"]["name"], "alice\\u{20}", "{result}");
}

/// Runs raylab as [`raylab`] does, but where the tests run as root (CI),
/// without the capabilities that let root read any folder (util-linux's
/// `setpriv` drops them from the bounding set), so that a `chmod 000`
/// folder is unreadable to it as to any instructor.
fn as_without_read_override(args: &[&str], dir: &Path) -> std::process::Output {
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        return raylab(args, dir);
    }
    std::process::Command::new("setpriv")
        .arg("--bounding-set=-dac_override,-dac_read_search")
        .arg(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("setpriv (util-linux) runs raylab")
}

/// A class graded as one job per student (with GNU parallel where it is
/// installed, else one after another in reverse order), then merged, gives
/// the same report and CSV as one run over the class; a student whose job
/// wrote nothing is refused as "no result".
#[test]
fn jobs_per_student_merge_into_the_report_of_one_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    for student in ["ann", "bob", "cy", "\u{1b}[31mred"] {
        std::fs::create_dir_all(class.join(student)).expect("mkdir");
    }
    // A name that is not UTF-8, and one that only looks like it.
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        std::fs::create_dir(class.join(std::ffi::OsStr::from_bytes(b"a\xff"))).expect("mkdir");
        std::fs::create_dir(class.join("a\\xff")).expect("mkdir");
    }
    for chapter in [1, 2] {
        save(
            &class.join(format!("ann/chapter-{chapter}.png")),
            &render(chapter, 48, 36, |_| {}),
        );
    }
    save(
        &class.join("bob/chapter-6.png"),
        &render(6, 48, 36, |s| s.max_depth = 1),
    );
    std::fs::write(class.join("cy/chapter-2.png"), "not a PNG").expect("write");

    let once = raylab(&["grade", "class"], dir.path());
    assert_eq!(once.status.code(), Some(1), "{}", stderr(&once));
    let report = std::fs::read(class.join("report.html")).expect("report");
    let csv = std::fs::read(class.join("grades.csv")).expect("CSV");
    std::fs::remove_file(class.join("report.html")).expect("rm");
    std::fs::remove_file(class.join("grades.csv")).expect("rm");

    let results = dir.path().join("results");
    std::fs::create_dir(&results).expect("mkdir");
    let binary = env!("CARGO_BIN_EXE_raylab");
    // Every student folder's name, as the file system has it, in a shuffled
    // order (cy before ann).
    let mut names: Vec<std::ffi::OsString> = std::fs::read_dir(&class)
        .expect("read")
        .flatten()
        .filter(|entry| entry.path().is_dir())
        .map(|entry| entry.file_name())
        .collect();
    names.sort();
    names.reverse();
    let parallel = std::process::Command::new("parallel")
        .args(["--version"])
        .output()
        .is_ok_and(|out| out.status.success());
    if parallel {
        // As docs/instructors.md: NUL-separated names, results by job number.
        let mut child = std::process::Command::new("parallel")
            .args([
                "-0",
                "--jobs",
                "2",
                binary,
                "grade",
                "class",
                "--student",
                "{}",
                "--result",
                "results/{#}.json",
            ])
            .current_dir(dir.path())
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("parallel runs");
        {
            use std::io::Write;
            let mut stdin = child.stdin.take().expect("stdin");
            for name in &names {
                stdin
                    .write_all(name.as_encoded_bytes())
                    .expect("write a name");
                stdin.write_all(b"\0").expect("write");
            }
        }
        let ran = child.wait_with_output().expect("parallel ends");
        // Exit 1 per failing student, as they should; parallel adds them up.
        assert!(
            ran.status
                .code()
                .is_some_and(|code| code <= names.len() as i32),
            "{ran:?}"
        );
    } else {
        eprintln!("jobs_per_student_merge: no GNU parallel here; the jobs run one by one");
        for (index, name) in names.iter().enumerate() {
            let result = format!("results/{index}.json");
            let out = common::command(&["grade", "class", "--result", &result], dir.path())
                .arg("--student")
                .arg(name)
                .output()
                .expect("runs");
            assert!(
                out.status.code().is_some_and(|code| code <= 1),
                "{}",
                stderr(&out)
            );
        }
    }
    let merged = raylab(&["grade", "class", "--merge", "results"], dir.path());
    assert_eq!(merged.status.code(), Some(1), "{}", stderr(&merged));
    assert_eq!(stdout(&merged), stdout(&once));
    assert_eq!(std::fs::read(class.join("grades.csv")).expect("CSV"), csv);
    assert!(
        std::fs::read(class.join("report.html")).expect("report") == report,
        "the merged report differs from one run's"
    );

    // Jobs graded with other options do not merge: every option is in the
    // result file, and the error names the one that differs.
    let stricter = raylab(
        &["grade", "class", "--merge", "results", "--threshold", "5"],
        dir.path(),
    );
    assert_eq!(stricter.status.code(), Some(2), "{}", stderr(&stricter));
    assert!(
        stderr(&stricter).contains("graded with other --threshold/--allow"),
        "{}",
        stderr(&stricter)
    );
    let references = dir.path().join("references");
    std::fs::create_dir(&references).expect("mkdir");
    save(
        &references.join("chapter-1.png"),
        &render(1, 48, 36, |_| {}),
    );
    let against = raylab(
        &[
            "grade",
            "class",
            "--merge",
            "results",
            "--against",
            "references",
        ],
        dir.path(),
    );
    assert_eq!(against.status.code(), Some(2), "{}", stderr(&against));
    assert!(
        stderr(&against).contains("graded with other --against"),
        "{}",
        stderr(&against)
    );

    // Without cy's result, cy is refused; a result twice is an error.
    let result_of = |student: &str| {
        std::fs::read_dir(&results)
            .expect("read")
            .flatten()
            .map(|entry| entry.path())
            .find(|path| {
                std::fs::read_to_string(path)
                    .is_ok_and(|text| text.contains(&format!("\"name\":\"{student}\"")))
            })
            .expect("a result")
    };
    std::fs::remove_file(result_of("cy")).expect("rm");
    let partial = raylab(&["grade", "class", "--merge", "results"], dir.path());
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV");
    assert!(
        csv.contains("cy,all,refused,,,,,,,,no result"),
        "{csv}{}",
        stderr(&partial)
    );
    std::fs::copy(result_of("ann"), results.join("ann-again.json")).expect("copy");
    let twice = raylab(&["grade", "class", "--merge", "results"], dir.path());
    assert_eq!(twice.status.code(), Some(2));
    assert!(
        stderr(&twice).contains("two results for ann"),
        "{}",
        stderr(&twice)
    );
}

/// A fake student workspace: a Cargo project whose binary ignores its
/// arguments, runs `body` and exits (the real `check` prints its table and
/// exits 0, 1 or 2).
pub(crate) fn fake_workspace(class: &Path, student: &str, body: &str) -> PathBuf {
    // Laid out as `raylab new` lays a workspace out (its main.rs, its one
    // dependency called raylab), so that grade takes it as one; the
    // "raylab" is a stand-in crate whose `cli::main_with` runs `body`, so
    // that nothing of the real raylab is built.
    let folder = class.join(student);
    let package = format!("student-{}", student.to_lowercase());
    std::fs::create_dir_all(folder.join("src")).expect("mkdir");
    std::fs::create_dir_all(folder.join("stand-in/src")).expect("mkdir");
    std::fs::write(
        folder.join("Cargo.toml"),
        format!(
            "[package]\nname = \"{package}\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\n\
             [dependencies]\nraylab = {{ path = \"stand-in\" }}\n\n[workspace]\n"
        ),
    )
    .expect("write");
    std::fs::write(
        folder.join("stand-in/Cargo.toml"),
        "[package]\nname = \"raylab\"\nversion = \"0.1.0\"\nedition = \"2021\"\n",
    )
    .expect("write");
    std::fs::write(
        folder.join("stand-in/src/lib.rs"),
        format!(
            "#![allow(dead_code)]\npub mod cli {{\n    pub fn main_with<T>() -> i32 {{\n        \
             super::main();\n        0\n    }}\n}}\n{body}"
        ),
    )
    .expect("write");
    std::fs::write(folder.join("src/lib.rs"), "pub struct Mine;\n").expect("write");
    std::fs::write(
        folder.join("src/main.rs"),
        format!(
            "fn main() {{\n    std::process::exit(raylab::cli::main_with::<{}::Mine>())\n}}\n",
            package.replace('-', "_")
        ),
    )
    .expect("write");
    folder
}

/// A fake student binary that writes the verdict file `check
/// --verdict-file F` asks for: one verdict record per `(chapter, status,
/// passes, not_started)`, then the closing record when `complete`, and
/// prints `printed`.
fn verdict_writer(verdicts: &[(u8, &str, bool, bool)], complete: bool, printed: &str) -> String {
    let mut records = String::new();
    for &(chapter, status, passes, not_started) in verdicts {
        let record = serde_json::json!({"verdict": {
            "chapter": chapter, "status": status, "passes": passes, "robust": passes,
            "not_started": not_started, "error": false,
            "text": format!("chapter {chapter}: {status}\n"),
            "row": format!("{chapter}        {status}\n"),
        }});
        records.push_str(&format!("{record}\n"));
    }
    if complete {
        records.push_str("\"end\"\n");
    }
    format!(
        "fn main() {{\n    let args: Vec<String> = std::env::args().collect();\n    \
         let at = args.iter().position(|a| a == \"--verdict-file\").unwrap();\n    \
         std::fs::write(&args[at + 1], {records:?}).unwrap();\n    println!({printed:?});\n}}\n"
    )
}

/// `raylab grade --code CLASS/` judges each workspace itself: a binary that
/// does not answer raylab's questions gets no verdict, whatever it writes
/// (a forged verdict file of the old protocol, with its closing record),
/// prints (a passing table) or exits with (0); the build and the answers
/// are killed past the time limit, with everything they started.
#[cfg(unix)]
#[test]
fn code_mode_takes_no_verdict_from_the_students_process_and_has_a_time_limit() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let table = |rows: &str, code: i32| {
        format!(
            "fn main() {{\n    println!(\"chapter  status       cases   robustness   image\\n{rows}\");\n    eprintln!(\"the student's own words\");\n    std::process::exit({code});\n}}\n"
        )
    };
    // The verdict file of the old protocol, forged: every chapter a pass,
    // and the closing record.
    fake_workspace(
        &class,
        "ada",
        &verdict_writer(
            &[(1, "pass", true, false), (2, "pass", true, false)],
            true,
            "",
        ),
    );
    // A passing table printed and exit 0.
    fake_workspace(&class, "hal", &table("1 pass\\n2 pass", 0));
    fake_workspace(&class, "dee", "fn main() { this is not Rust }\n");
    fake_workspace(&class, "eli", &table("error: cannot read the scene", 2));
    // A child in a session of its own (out of the process group), then a
    // wait past the time limit.
    let sleeper = fake_workspace(
        &class,
        "fay",
        "fn main() {\n    std::process::Command::new(\"setsid\").args([\"sleep\", \"3617\"]).spawn().unwrap();\n    eprintln!(\"started\");\n    std::thread::sleep(std::time::Duration::from_secs(3600));\n}\n",
    );
    std::fs::create_dir(class.join("gus")).expect("mkdir");
    // Built beforehand, so that the time limit falls while the binary runs
    // (a build past the limit would be killed the same way).
    // Into its own target/, where grading builds each workspace whatever
    // CARGO_TARGET_DIR says.
    let built = common::cargo()
        .args(["build", "--release", "--offline", "--quiet"])
        .current_dir(&sleeper)
        .env("CARGO_TARGET_DIR", sleeper.join("target"))
        .status()
        .expect("cargo build");
    assert!(built.success());

    // fay's target/ is the test's own build: trusted, so that it is not
    // built again within the time limit.
    let mut args = vec![
        "grade",
        "--code",
        "class",
        "--timeout",
        "5",
        "--trust-targets",
    ];
    let unsandboxed = sandbox_or_skip(
        "code_mode_takes_no_verdict_from_the_students_process_and_has_a_time_limit",
    );
    let sandboxed = unsandboxed.is_empty();
    args.extend(unsandboxed);
    let mut command = common::command(&args, dir.path());
    command.env("CARGO_TARGET_DIR", dir.path().join("shared-target"));
    let out = common::output_or_blocked(command);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let md = stdout(&out);
    for (student, verdict) in [
        ("ada", "error"),
        ("hal", "error"),
        ("dee", "build error"),
        ("eli", "error"),
        ("fay", "timed out"),
        ("gus", "refused: not a workspace: no Cargo.toml"),
    ] {
        let row = format!("| {student} | {verdict}");
        assert!(md.contains(&row), "{row:?} not in:\n{md}");
    }
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV");
    for student in ["ada", "hal", "eli"] {
        assert!(csv.contains(&format!("{student},all,error,")), "{csv}");
    }
    assert!(csv.contains("does not answer raylab's questions"), "{csv}");
    assert!(csv.contains("dee,all,build error,"), "{csv}");
    assert!(csv.contains("fay,all,timed out,"), "{csv}");
    // What the students' binaries printed is shown, as theirs, and
    // counted for nothing: no row passes.
    assert!(csv.contains("the student's own words"), "{csv}");
    assert!(!csv.contains(",all,pass,"), "{csv}");
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    assert!(html.contains("timed out after 5 s"), "{html}");

    // What the student's binary started died with the run, even a child
    // that left the process group: the sandbox's pid namespace ends whole.
    // Unsandboxed, only the process group is killed, and a child in a
    // session of its own lives on (killed here, so that it does not).
    if sandboxed {
        assert_eq!(
            running("sleep\x003617"),
            0,
            "the setsid child outlived the run"
        );
    } else {
        let _ = std::process::Command::new("pkill")
            .args(["-f", "sleep 3617"])
            .status();
    }
}

/// `[]` where bubblewrap makes sandboxes here; else `["--no-sandbox"]`
/// and a note that `test` ran unsandboxed (scripts/test.sh installs
/// bubblewrap where it can; a machine may forbid user namespaces).
/// A `target/` that no run of raylab's left, holding a binary built from
/// other sources than the workspace's (dated back to before that build),
/// is emptied before the build: cargo would take that binary for up to
/// date, and raylab would judge code the student did not hand in.
#[test]
fn a_target_built_from_other_sources_is_not_run() {
    if !sandbox_or_skip("a_target_built_from_other_sources_is_not_run").is_empty() {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let sleeps = "fn main() {\n    std::thread::sleep(std::time::Duration::from_secs(3600));\n}\n";
    let forger = fake_workspace(&class, "forger", sleeps);
    let built = common::cargo()
        .args(["build", "--profile", "dev", "--offline", "--quiet"])
        .current_dir(&forger)
        .env("CARGO_TARGET_DIR", forger.join("target"))
        .status()
        .expect("cargo build");
    assert!(built.success());
    // The sources handed in: a binary that exits at once, dated as the
    // built ones were.
    let lib = forger.join("stand-in/src/lib.rs");
    let dated = std::fs::metadata(&lib)
        .and_then(|meta| meta.modified())
        .expect("a time");
    let text = std::fs::read_to_string(&lib).expect("read");
    std::fs::write(&lib, text.replace(sleeps, "fn main() {}\n")).expect("write");
    std::fs::File::options()
        .write(true)
        .open(&lib)
        .and_then(|file| file.set_modified(dated))
        .expect("date");
    let mut command = common::command(
        &[
            "grade",
            "--code",
            "class",
            "--build-profile",
            "dev",
            "--timeout",
            "60",
        ],
        dir.path(),
    );
    command.env("XDG_CACHE_HOME", dir.path().join("cache"));
    let out = common::output_or_blocked(command);
    let md = stdout(&out);
    assert!(md.contains("| forger | error"), "{md}{}", stderr(&out));
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV");
    assert!(
        csv.contains("exited with status 0 before it said hello"),
        "{csv}"
    );
}

fn sandbox_or_skip(test: &str) -> Vec<&'static str> {
    let works = std::process::Command::new("bwrap")
        .args([
            "--ro-bind",
            "/",
            "/",
            "--unshare-all",
            "--die-with-parent",
            "true",
        ])
        .output()
        .is_ok_and(|out| out.status.success());
    if works {
        return Vec::new();
    }
    eprintln!(
        "{test}: SKIPPED the sandbox: bubblewrap is missing or cannot make a sandbox here \
         (apt-get install bubblewrap); running unsandboxed"
    );
    vec!["--no-sandbox"]
}

/// How many live processes have `marker` in their command line (its
/// arguments joined by NUL bytes).
fn running(marker: &str) -> usize {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return 0;
    };
    entries
        .flatten()
        .filter(|entry| {
            let status = std::fs::read_to_string(entry.path().join("status")).unwrap_or_default();
            let zombie = status
                .lines()
                .any(|line| line.starts_with("State:") && line.contains('Z'));
            !zombie
                && std::fs::read(entry.path().join("cmdline"))
                    .is_ok_and(|line| String::from_utf8_lossy(&line).contains(marker))
        })
        .count()
}

/// A hostile workspace under `grade --code`: its build script and its
/// binary write outside the workspace (the binary inside it too), connect
/// to a port on the grader's machine, start a `setsid` child and allocate
/// 50 GB. Nothing is written outside (nor, by the binary, inside), no
/// connection arrives, nothing is left running, and the student is marked
/// (an error: the allocation aborts the binary before it answers).
#[cfg(target_os = "linux")]
#[test]
fn a_hostile_workspace_is_contained_by_the_sandbox() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let outside = dir.path().join("outside");
    std::fs::create_dir(&outside).expect("mkdir");
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("listen");
    listener.set_nonblocking(true).expect("non-blocking");
    let port = listener.local_addr().expect("address").port();
    let written = |name: &str| outside.join(name).display().to_string();
    let mallory = fake_workspace(
        &class,
        "mallory",
        &format!(
            "fn main() {{\n    let _ = std::fs::write({main:?}, \"x\");\n    \
             let _ = std::fs::write(\"in-the-workspace\", \"x\");\n    \
             let _ = std::net::TcpStream::connect((\"127.0.0.1\", {port}));\n    \
             let _ = std::process::Command::new(\"setsid\").args([\"sleep\", \"3619\"]).spawn();\n    \
             eprintln!(\"reached the allocation\");\n    \
             let hoard = vec![1u8; 50 << 30];\n    println!(\"{{}}\", hoard[12345]);\n}}\n",
            main = written("from-main"),
        ),
    );
    std::fs::write(
        mallory.join("build.rs"),
        format!(
            "fn main() {{ let _ = std::fs::write({:?}, \"x\"); }}\n",
            written("from-build-script")
        ),
    )
    .expect("write");
    if !sandbox_or_skip("a_hostile_workspace_is_contained_by_the_sandbox").is_empty() {
        return;
    }
    let out = raylab(
        &["grade", "--code", "class", "--timeout", "120"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV");
    assert!(csv.contains("mallory,all,error,"), "{csv}");
    // It ran, and its 50 GB allocation aborted it (status 134, SIGABRT)
    // before it answered anything.
    assert!(
        csv.contains("exited with status 134 before it said hello"),
        "the binary never ran: {csv}"
    );
    // Answering, the binary may write nothing, its workspace included.
    assert!(!mallory.join("in-the-workspace").exists());
    let escaped: Vec<_> = std::fs::read_dir(&outside)
        .expect("read")
        .flatten()
        .collect();
    assert!(
        escaped.is_empty(),
        "written outside the workspace: {escaped:?}"
    );
    assert!(
        matches!(listener.accept(), Err(error) if error.kind() == std::io::ErrorKind::WouldBlock),
        "a connection came out of the sandbox"
    );
    assert_eq!(
        running("sleep\x003619"),
        0,
        "the setsid child outlived the run"
    );
}

/// `grade --code` reports chapter files that are alike: a copy with its
/// names changed and its functions reordered, and a renamed copy of the
/// answer key, but not two independent solutions.
#[cfg(unix)]
#[test]
fn code_mode_reports_copied_chapters() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let passing = verdict_writer(&[(1, "pass", true, false)], true, "");
    let sphere_file = format!(
        "src/chapters/{}.rs",
        raylab::chapters::chapter(2).expect("chapter 2").module()
    );
    let answer_key = raylab::workspace::files("x", Path::new("/raylab"), true)
        .expect("the answer key")
        .get(&sphere_file)
        .expect("chapter 2")
        .to_string();
    let renamed_key = answer_key
        .replace("oc", "offset")
        .replace("near", "first")
        .replace("far", "second")
        .replace("roots", "pair");
    let quadratic = "use raylab::{Ray, Sphere};\n\
        pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {\n\
            let oc = ray.origin - sphere.center();\n    let a = ray.dir.dot(ray.dir);\n\
            let half_b = oc.dot(ray.dir);\n\
            let c = oc.dot(oc) - sphere.radius() * sphere.radius();\n\
            let discriminant = half_b * half_b - a * c;\n\
            if discriminant < 0.0 { return None; }\n\
            let root = discriminant.sqrt();\n    let near = (-half_b - root) / a;\n\
            if near > t_min && near < t_max { return Some(near); }\n\
            let far = (-half_b + root) / a;\n\
            if far > t_min && far < t_max { return Some(far); }\n    None\n}\n";
    let renamed = quadratic
        .replace("oc", "w")
        .replace("half_b", "b")
        .replace("discriminant", "d")
        .replace("near", "t0")
        .replace("far", "t1");
    let geometric = "use raylab::{Ray, Sphere};\n\
        fn in_range(t: f32, lo: f32, hi: f32) -> Option<f32> { (t > lo && t < hi).then_some(t) }\n\
        pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {\n\
            let speed = ray.dir.length();\n    let unit = ray.dir / speed;\n\
            let to_center = sphere.center() - ray.origin;\n\
            let along = to_center.dot(unit);\n\
            let gap = sphere.radius().powi(2) - (to_center - along * unit).length_squared();\n\
            if gap < 0.0 { return None; }\n    let half = gap.sqrt();\n\
            in_range((along - half) / speed, t_min, t_max)\n\
                .or_else(|| in_range((along + half) / speed, t_min, t_max))\n}\n";
    for (student, chapter) in [
        ("ann", quadratic.to_string()),
        ("zoe", renamed),
        ("bob", geometric.to_string()),
        ("kim", renamed_key),
    ] {
        let folder = fake_workspace(&class, student, &passing);
        std::fs::create_dir_all(folder.join("src/chapters")).expect("mkdir");
        std::fs::write(folder.join(&sphere_file), chapter).expect("write");
    }
    let mut args = vec!["grade", "--code", "class"];
    args.extend(sandbox_or_skip("code_mode_reports_copied_chapters"));
    let out = raylab(&args, dir.path());
    let md = stdout(&out);
    let similar: Vec<&str> = md
        .lines()
        .filter(|line| line.starts_with("- chapter "))
        .collect();
    assert_eq!(similar.len(), 2, "{md}");
    assert!(
        similar
            .iter()
            .any(|line| line.starts_with("- chapter 2: ann and zoe, ")),
        "{md}"
    );
    assert!(
        similar
            .iter()
            .any(|line| line.starts_with("- chapter 2: kim and raylab's answer key, ")),
        "{md}"
    );
    let html = std::fs::read_to_string(class.join("report.html")).expect("report");
    assert!(html.contains("<h2>Similar code</h2>"), "{html}");
    assert!(
        html.contains("half_b"),
        "the shared passage is shown: {html}"
    );
}

/// `grade --code` compares the code that was built, all of `src/`: a
/// chapter file that the student's binary rewrites while it is checked is
/// compared as it was before the build (and the run does not count), and
/// the answer key moved out of the chapter files (each of them a `pub use`
/// of `src/answers/`) is found in `src/` as a whole.
#[cfg(unix)]
#[test]
fn code_mode_compares_all_of_src_as_it_was_before_the_build() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let module = |chapter: u8| {
        raylab::chapters::chapter(chapter)
            .expect("a chapter")
            .module()
    };
    let sphere_file = format!("src/chapters/{}.rs", module(2));
    let quadratic = "use raylab::{Ray, Sphere};\n\
        pub fn intersect_sphere(sphere: &Sphere, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {\n\
            let oc = ray.origin - sphere.center();\n    let a = ray.dir.dot(ray.dir);\n\
            let half_b = oc.dot(ray.dir);\n\
            let c = oc.dot(oc) - sphere.radius() * sphere.radius();\n\
            let discriminant = half_b * half_b - a * c;\n\
            if discriminant < 0.0 { return None; }\n\
            let root = discriminant.sqrt();\n    let near = (-half_b - root) / a;\n\
            if near > t_min && near < t_max { return Some(near); }\n\
            let far = (-half_b + root) / a;\n\
            if far > t_min && far < t_max { return Some(far); }\n    None\n}\n";
    let innocent = "pub fn intersect_sphere() {}\n";
    let passing = verdict_writer(&[(1, "pass", true, false)], true, "");
    let ann = fake_workspace(&class, "ann", &passing);
    std::fs::create_dir_all(ann.join("src/chapters")).expect("mkdir");
    std::fs::write(ann.join(&sphere_file), quadratic).expect("write");
    // ivy's chapter 2 is ann's, renamed; her binary replaces it with
    // something of her own as soon as it runs.
    let ivy = fake_workspace(
        &class,
        "ivy",
        &format!("fn main() {{\n    let _ = std::fs::write({sphere_file:?}, {innocent:?});\n}}\n"),
    );
    std::fs::create_dir_all(ivy.join("src/chapters")).expect("mkdir");
    std::fs::write(
        ivy.join(&sphere_file),
        quadratic.replace("half_b", "h").replace("near", "t0"),
    )
    .expect("write");
    // kai's chapter files each re-export raylab's answer key, moved to
    // src/answers/.
    let answer_key = raylab::workspace::files("x", Path::new("/raylab"), true).expect("the key");
    let kai = fake_workspace(&class, "kai", &passing);
    std::fs::create_dir_all(kai.join("src/answers")).expect("mkdir");
    std::fs::create_dir_all(kai.join("src/chapters")).expect("mkdir");
    for chapter in [2, 5, 6, 8] {
        let text = answer_key
            .get(&format!("src/chapters/{}.rs", module(chapter)))
            .expect("a chapter of the key");
        std::fs::write(
            kai.join(format!("src/answers/{}.rs", module(chapter))),
            text,
        )
        .expect("write");
        std::fs::write(
            kai.join(format!("src/chapters/{}.rs", module(chapter))),
            format!("pub use crate::answers::{}::*;\n", module(chapter)),
        )
        .expect("write");
    }
    // The rewrite needs a binary that may write its workspace: no sandbox.
    let out = raylab(&["grade", "--code", "class", "--no-sandbox"], dir.path());
    let md = stdout(&out);
    assert!(
        md.lines()
            .any(|line| line.starts_with("- chapter 2: ann and ivy, ")),
        "{md}"
    );
    assert!(
        md.lines()
            .any(|line| line.starts_with("- all of src/: kai and raylab's answer key, ")),
        "{md}"
    );
    let csv = std::fs::read_to_string(class.join("grades.csv")).expect("CSV");
    assert!(
        csv.contains(&format!(
            "{sphere_file} changed while the workspace was built and checked"
        )),
        "{csv}"
    );
}

/// `grade --code` counts only code the compiler read from the workspace's
/// Rust files under `src/`, as the compiler itself lists them: a library
/// that includes a text file (from `src/` or beside it), a workspace with
/// a second program, and a crate built from a folder of the student's are
/// not counted, each named.
#[cfg(unix)]
#[test]
fn code_the_compiler_read_from_other_files_is_not_counted() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let passing = verdict_writer(&[(1, "pass", true, false)], true, "");
    let ivy = fake_workspace(&class, "ivy", &passing);
    std::fs::write(ivy.join("src/notes.txt"), "fn key() {}").expect("write");
    std::fs::write(ivy.join("key.txt"), "fn key() {}").expect("write");
    std::fs::write(
        ivy.join("src/lib.rs"),
        "pub struct Mine;
pub const NOTES: &str = include_str!(\"notes.txt\");
         pub const KEY: &str = include_str!(concat!(\"..\", \"/key.txt\"));
",
    )
    .expect("write");
    let joe = fake_workspace(&class, "joe", &passing);
    std::fs::create_dir_all(joe.join("src/bin")).expect("mkdir");
    std::fs::write(joe.join("src/bin/other.rs"), "fn main() {}\n").expect("write");
    let mut args = vec!["grade", "--code", "class", "--build-profile", "dev"];
    args.extend(sandbox_or_skip(
        "code_the_compiler_read_from_other_files_is_not_counted",
    ));
    let out = raylab(&args, dir.path());
    let csv = std::fs::read_to_string(class.join("grades.csv"))
        .unwrap_or_else(|error| panic!("no CSV ({error}): {}", stderr(&out)));
    // Each row from its student's name to the next student's.
    let row = |student: &str| {
        let start = csv
            .find(&format!("\n{student},"))
            .unwrap_or_else(|| panic!("no row for {student}: {csv}"));
        let rest = &csv[start + 1..];
        let end = rest
            .find("\njoe,")
            .filter(|_| student != "joe")
            .unwrap_or(rest.len());
        rest[..end].to_string()
    };
    let ivy = row("ivy");
    assert!(
        ivy.contains(
            "the compiler read src/notes.txt, which is not one of the workspace's Rust files"
        ),
        "{ivy}"
    );
    assert!(ivy.starts_with("ivy,all,error,"), "{ivy}");
    // The stand-in raylab is a crate from a folder of the student's: the
    // build's own messages name it, whatever the manifest says.
    assert!(
        ivy.contains(
            "the build compiled a crate `raylab new` does not write, from stand-in/Cargo.toml"
        ),
        "{ivy}"
    );
    let joe = row("joe");
    assert!(
        joe.contains("the workspace builds a program of its own, src/bin/other.rs"),
        "{joe}"
    );
    assert!(joe.starts_with("joe,all,error,"), "{joe}");
}

/// The workspaces tests/cli/workspace.rs builds (into this test's target
/// folder, in the dev profile), each given a `target/` of hard links to
/// that folder's `debug/`, so that `grade --code --build-profile dev`
/// finds them built, from their own folder as the grader builds them:
/// the judging is tested without a build per student.
fn built_class() -> &'static Path {
    static CLASS: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    CLASS.get_or_init(|| {
        let ws = crate::workspace::workspaces();
        for student in ["student-answer", "student-todo", "student-cheat"] {
            let target = ws.root.join(student).join("target");
            if target.exists() {
                continue;
            }
            std::fs::create_dir_all(&target).expect("mkdir");
            let linked = std::process::Command::new("cp")
                .arg("-al")
                .arg(ws.target.join("debug"))
                .arg(target.join("debug"))
                .status()
                .expect("cp -al");
            assert!(linked.success(), "cp -al into {}", target.display());
        }
        ws.root.clone()
    })
}

/// `raylab grade --code --student NAME` of the built class (see
/// [`built_class`]) with `extra` arguments: the student's result.
fn grade_built(student: &str, extra: &[&str]) -> (serde_json::Value, String) {
    let class = built_class();
    let results = tempfile::tempdir().expect("temp dir");
    let result = results.path().join("result.json");
    let mut args = vec![
        "grade",
        class.to_str().expect("UTF-8 path"),
        "--code",
        "--build-profile",
        "dev",
        "--student",
        student,
        "--result",
        result.to_str().expect("UTF-8 path"),
        // Their target/ folders are the test's own builds.
        "--trust-targets",
    ];
    args.extend(extra);
    args.extend(sandbox_or_skip("the_grader_judges_real_workspaces_itself"));
    let out = raylab(&args, class);
    let text = std::fs::read_to_string(&result)
        .unwrap_or_else(|error| panic!("no result ({error}): {}", stderr(&out)));
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    (value, format!("{}{}", stdout(&out), stderr(&out)))
}

/// `grade --code` of one built workspace of the test's class as
/// Gradescope's autograder runs it, with `extra` arguments: its exit
/// status, its `results.json`, and what it printed.
fn gradescope_built(student: &str, extra: &[&str]) -> (Option<i32>, serde_json::Value, String) {
    let gradescope = tempfile::tempdir().expect("temp dir");
    let results = gradescope.path().join("results.json");
    let workspace = built_class().join(student);
    let mut args = vec![
        "grade",
        workspace.to_str().expect("UTF-8 path"),
        "--code",
        "--build-profile",
        "dev",
        "--gradescope",
        results.to_str().expect("UTF-8 path"),
        // The test's own build, as in `grade_built`: a fresh build here
        // would compile every dependency again, in the sandbox.
        "--trust-targets",
    ];
    args.extend(extra);
    args.extend(sandbox_or_skip("the_grader_judges_real_workspaces_itself"));
    let out = raylab(&args, built_class());
    let text = std::fs::read_to_string(&results)
        .unwrap_or_else(|error| panic!("no results.json ({error}): {}", stderr(&out)));
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    (
        out.status.code(),
        value,
        format!("{}{}", stdout(&out), stderr(&out)),
    )
}

/// Replies to chapter 5's `phong_terms` checkpoints, each the reference's
/// answer to the first of them, framed as the judge reads them: what a
/// chapter would write to the judge's pipe if it could reach it.
fn forged_phong_replies() -> Vec<u8> {
    use raylab::check::protocol::{Request, write_frame};
    let case = raylab::check::by_chapter::checkpoints(5)
        .into_iter()
        .find(|case| case.function() == "phong_terms")
        .expect("a phong_terms checkpoint");
    let reply = raylab::check::serve::answer::<raylab::Reference>(&Request::Case(case.kind.call()));
    let mut frames = Vec::new();
    for _ in 0..64 {
        write_frame(&mut frames, &reply).expect("a frame");
    }
    frames
}

/// The status of a graded student's code run, and the verdicts' text.
fn code_status(result: &serde_json::Value) -> (String, String) {
    let run = &result["student"]["outcome"]["Code"];
    (
        run["status"].as_str().unwrap_or_default().to_string(),
        run["stdout"].as_str().unwrap_or_default().to_string(),
    )
}

/// `grade --code` of real workspaces: the grader judges, their binaries
/// answer. The answer key passes (and renders a hidden scene as raylab's
/// reference does), the skeleton is not started, chapters that run
/// raylab's own answers fail (its hidden scene too, worded as any failure), a chapter answering from a table
/// prepared in advance passes the lesson's inputs but not `--fresh` ones,
/// and one that has another program print the table gets nothing.
#[cfg(unix)]
#[test]
fn the_grader_judges_real_workspaces_itself() {
    let (answer, text) = grade_built("student-answer", &["--chapter", "3"]);
    let (status, verdicts) = code_status(&answer);
    assert_eq!(status, "Pass", "{verdicts}\n{text}");
    assert!(verdicts.contains("chapter 3: Nearest hit"), "{verdicts}");

    // The same run as Gradescope's autograder runs it: a point per chapter.
    let (code, results, said) = gradescope_built("student-answer", &["--chapter", "3"]);
    assert_eq!(code, Some(0), "{said}");
    assert_eq!(assert_gradescope_results(&results, 3), 3.0, "{results}");

    let (todo, text) = grade_built("student-todo", &["--chapter", "2"]);
    let (status, verdicts) = code_status(&todo);
    assert_eq!(status, "NotStarted", "{verdicts}\n{text}");

    let (cheat, text) = grade_built("student-cheat", &["--chapter", "3"]);
    let (status, verdicts) = code_status(&cheat);
    assert_eq!(status, "Fail", "{verdicts}\n{text}");
    assert!(
        verdicts.contains("runs raylab's own answer instead of yours: Sphere::intersect"),
        "{verdicts}"
    );

    // The table of every call the check makes, in the cheat's own folder,
    // where its binary answers from it.
    let table = built_class().join("student-cheat/answers.table");
    std::fs::write(&table, crate::workspace::harvested_table()).expect("write the table");
    let (plain, _) = grade_built("student-cheat", &["--chapter", "1"]);
    let (fresh, _) = grade_built("student-cheat", &["--chapter", "1", "--fresh", "7"]);
    std::fs::remove_file(&table).expect("remove the table");
    let (status, verdicts) = code_status(&plain);
    assert_eq!(status, "Pass", "{verdicts}");
    let (status, verdicts) = code_status(&fresh);
    assert_eq!(status, "Fail", "{verdicts}");
    assert_eq!(fresh["options"]["fresh"], 7, "{fresh}");
    // The same table printed by a program the chapter starts: the
    // answering process may start none, so it has no table, and fails.
    let cheat = built_class().join("student-cheat");
    std::fs::write(
        cheat.join("answers.printed"),
        crate::workspace::harvested_table(),
    )
    .expect("write the table");
    std::fs::write(cheat.join("answers.program"), "cat answers.printed").expect("write");
    let (spawned, _) = grade_built("student-cheat", &["--chapter", "1"]);
    std::fs::remove_file(cheat.join("answers.printed")).expect("remove the table");
    std::fs::remove_file(cheat.join("answers.program")).expect("remove the program");
    let (status, verdicts) = code_status(&spawned);
    assert_eq!(status, "Fail", "{verdicts}");
    let (honest, _) = grade_built("student-answer", &["--chapter", "1", "--fresh", "7"]);
    assert_eq!(code_status(&honest).0, "Pass", "{}", code_status(&honest).1);

    // A chapter that writes replies of the judge's protocol (right ones,
    // made here by raylab) to every file descriptor it can reach by a
    // path: in the sandbox none is the judge's pipe, and the chapter's own
    // answer is judged.
    if sandbox_or_skip("the_grader_judges_real_workspaces_itself").is_empty() {
        let frames = built_class().join("student-cheat/forged.frames");
        std::fs::write(&frames, forged_phong_replies()).expect("write the frames");
        let (forger, _) = grade_built("student-cheat", &["--chapter", "5"]);
        std::fs::remove_file(&frames).expect("remove the frames");
        let (status, verdicts) = code_status(&forger);
        assert_eq!(status, "Fail", "{verdicts}");
        let five = verdicts
            .split("chapter 5: ")
            .nth(1)
            .unwrap_or_else(|| panic!("no chapter 5: {verdicts}"));
        assert!(five.contains("failed (phong_terms"), "{five}");
        assert!(five.contains("got:      diffuse (9, 9, 9)"), "{five}");
    }

    // A hidden scene: the answer key renders it as raylab's reference
    // does; the cheat's chapter 2 runs raylab's own answer, which no
    // render may use.
    let scene_text = "background = [0.2, 0.3, 0.4]\n[camera]\nposition = [0, 1, -4]\n\
        look_at = [0, 0.5, 0]\n[render]\nwidth = 40\nheight = 30\n[[lights]]\n\
        position = [2, 5, -3]\n[[objects]]\nsphere = { center = [0.3, 0.6, 0], radius = 0.6171 }\n\
        [[objects]]\nplane = { point = [0, 0, 0], normal = [0, 1, 0] }\n";
    let scenes = tempfile::tempdir().expect("temp dir");
    let scene = scenes.path().join("private.toml");
    std::fs::write(&scene, scene_text).expect("write");
    let scene = scene.to_str().expect("UTF-8 path");
    // Under --fresh, seen from a turned camera, which the answer key
    // renders as raylab does.
    let hidden = [
        "--chapter",
        "1",
        "--scene",
        scene,
        "--scene-chapter",
        "6",
        "--fresh",
        "7",
    ];
    let (answer, printed) = grade_built("student-answer", &hidden);
    let scenes = &answer["student"]["outcome"]["Code"]["scenes"];
    assert_eq!(scenes[0]["passed"], true, "{scenes}");
    // Its chapter 2 writes each radius it meets on stderr (chapter 1's
    // check meets none): none of the hidden scene's comes back, in the
    // result or in what grade printed.
    for shown in [answer.to_string(), printed] {
        assert!(!shown.contains("0.6171"), "{shown}");
        // It met that radius and started threads up to the process limit:
        // the limits reported are those reached before the hidden scenes.
        assert!(!shown.contains("process limit"), "{shown}");
    }
    let limits = &answer["student"]["outcome"]["Code"]["limits"];
    assert_eq!(limits, &serde_json::json!([]), "{answer}");
    let (cheat, _) = grade_built("student-cheat", &hidden);
    let scenes = &cheat["student"]["outcome"]["Code"]["scenes"];
    assert_eq!(scenes[0]["passed"], false, "{scenes}");
    // Its chapter 1 passes, its hidden scene fails: the student does not
    // pass (pass 16 of issue 41: the status said pass, and Gradescope's
    // run exited 0 and wrote "pass"), wherever the status is read.
    let (status, verdicts) = code_status(&cheat);
    assert!(
        verdicts.contains("chapter 1: Ray-plane intersection - pass"),
        "{verdicts}"
    );
    assert_eq!(status, "Fail", "{verdicts}");
    let (code, results, said) = gradescope_built("student-cheat", &hidden);
    assert_eq!(code, Some(1), "{said}");
    assert_eq!(results["extra_data"]["status"], "fail", "{results}");
    // Failed, worded as every failure is: how is the student's choice.
    assert!(
        scenes[0]["detail"]
            .as_str()
            .unwrap_or_default()
            .contains("how it failed is not shown"),
        "{scenes}"
    );
}

/// Without bubblewrap, `grade --code` refuses to run student code, says how
/// to install it, and runs it only with an explicit --no-sandbox.
#[cfg(unix)]
#[test]
fn code_mode_without_bubblewrap_refuses_unless_told() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    fake_workspace(
        &class,
        "ada",
        &verdict_writer(&[(1, "pass", true, false)], true, ""),
    );
    // A PATH with everything of this one (cargo, rustc, the linker) but
    // bwrap.
    let tools = dir.path().join("tools");
    std::fs::create_dir(&tools).expect("mkdir");
    let path = std::env::var_os("PATH").unwrap_or_default();
    let cargo_folder = Path::new(env!("CARGO")).parent().map(Path::to_path_buf);
    for folder in std::env::split_paths(&path).chain(cargo_folder) {
        for entry in std::fs::read_dir(&folder).into_iter().flatten().flatten() {
            let link = tools.join(entry.file_name());
            if entry.file_name() != "bwrap" && !link.exists() {
                let _ = std::os::unix::fs::symlink(entry.path(), link);
            }
        }
    }
    let tools = tools.as_path();
    let mut command = common::command(&["grade", "--code", "class"], dir.path());
    command.env("PATH", tools);
    let out = command.output().expect("runs");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("bubblewrap"), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("apt-get install bubblewrap"),
        "{}",
        stderr(&out)
    );
    assert!(stderr(&out).contains("--no-sandbox"), "{}", stderr(&out));
    assert!(!class.join("grades.csv").exists());
    let mut command = common::command(&["grade", "--code", "--no-sandbox", "class"], dir.path());
    command.env("PATH", tools);
    let out = command.output().expect("runs");
    let csv = std::fs::read_to_string(class.join("grades.csv")).unwrap_or_default();
    // It ran (unsandboxed): a stand-in that answers no question, an error.
    assert!(csv.contains("ada,all,error,"), "{}\n{csv}", stderr(&out));
    assert!(
        csv.contains("before it said hello"),
        "{}\n{csv}",
        stderr(&out)
    );
}

/// Pass 11 of issue 41, finding 6: with --force, `grade --code` wrote its
/// report over a student's source, its CSV over the hidden scene and a
/// result file over a workspace's Cargo.toml. Each is an input, refused
/// with or without --force, and left as it was.
#[test]
fn code_mode_outputs_never_replace_a_workspace_or_a_scene() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    let amy = fake_workspace(&class, "amy", "fn main() {}\n");
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, "background = [0, 0, 0]\n").expect("write");
    let source = amy.join("src/main.rs");
    let kept = |path: &Path| std::fs::read(path).expect("read");
    let (source_before, manifest_before, scene_before) =
        (kept(&source), kept(&amy.join("Cargo.toml")), kept(&scene));
    let attempts: [&[&str]; 4] = [
        &[
            "grade",
            "class",
            "--code",
            "--report",
            "class/amy/src/main.rs",
            "--force",
        ],
        &[
            "grade",
            "class",
            "--code",
            "--csv",
            "scene.toml",
            "--scene",
            "scene.toml",
            "--force",
        ],
        &[
            "grade",
            "class",
            "--code",
            "--student",
            "amy",
            "--result",
            "class/amy/Cargo.toml",
            "--force",
        ],
        &[
            "grade",
            "class/amy",
            "--code",
            "--gradescope",
            "class/amy/results.json",
            "--force",
        ],
    ];
    for args in attempts {
        let out = raylab(args, dir.path());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        let said = stderr(&out);
        assert!(
            said.contains("inside the workspace") || said.contains("input"),
            "{args:?}: {said}"
        );
    }
    assert_eq!(kept(&source), source_before);
    assert_eq!(kept(&amy.join("Cargo.toml")), manifest_before);
    assert_eq!(kept(&scene), scene_before);
    assert!(!amy.join("results.json").exists());
}

/// `--against` the folder being graded would compare each hand-in with
/// itself: refused, by its path, and (pass 14 of issue 41) where its
/// reference is a hand-in by another path: a hard link to a student's
/// PNG, as a bind mount of the student's folder would be.
#[test]
fn against_the_graded_folder_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().join("alice");
    std::fs::create_dir(&folder).expect("mkdir");
    save(&folder.join("chapter-1.png"), &render(1, 48, 36, |_| {}));
    let out = raylab(&["grade", "alice", "--against", "alice"], dir.path());
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("compared with itself"),
        "{}",
        stderr(&out)
    );
    assert!(!folder.join("report.html").exists());
    let references = dir.path().join("references");
    std::fs::create_dir(&references).expect("mkdir");
    std::fs::hard_link(
        folder.join("chapter-1.png"),
        references.join("chapter-1.png"),
    )
    .expect("a hard link");
    let class = dir.path().join("class");
    std::fs::create_dir(&class).expect("mkdir");
    std::fs::rename(&folder, class.join("alice")).expect("move");
    // And through a symbolic link (pass 15), which a reference is read
    // through.
    let linked = dir.path().join("linked");
    std::fs::create_dir(&linked).expect("mkdir");
    #[cfg(unix)]
    std::os::unix::fs::symlink(
        class.join("alice/chapter-1.png"),
        linked.join("chapter-1.png"),
    )
    .expect("a link");
    for (graded, references) in [
        ("class", "references"),
        ("class/alice", "references"),
        ("class", "linked"),
        ("class/alice", "linked"),
    ] {
        let out = raylab(&["grade", graded, "--against", references], dir.path());
        assert_eq!(out.status.code(), Some(2), "{graded}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(&format!("{references}/chapter-1.png is a hand-in")),
            "{}",
            stderr(&out)
        );
    }
}

/// Checks `results` against Gradescope's autograder specification: the
/// fields it requires, their types and allowed values, and a total that is
/// the sum of the tests' scores, none above its maximum. Returns the
/// total.
fn assert_gradescope_results(results: &serde_json::Value, tests: usize) -> f64 {
    const VISIBILITIES: [&str; 4] = ["hidden", "after_due_date", "after_published", "visible"];
    let score = results["score"]
        .as_f64()
        .unwrap_or_else(|| panic!("no top-level score: {results}"));
    for field in ["visibility", "stdout_visibility"] {
        let value = results[field].as_str().unwrap_or_default();
        assert!(
            VISIBILITIES.contains(&value),
            "{field} {value:?}: {results}"
        );
    }
    assert!(results["output"].is_string(), "no output: {results}");
    let listed = results["tests"].as_array().expect("a tests array");
    assert_eq!(listed.len(), tests, "{results}");
    let mut sum = 0.0;
    for test in listed {
        let name = test["name"].as_str().expect("each test has a name");
        let test_score = test["score"].as_f64().expect("each test has a score");
        let max = test["max_score"]
            .as_f64()
            .expect("each test has a max_score");
        assert!(
            (0.0..=max).contains(&test_score),
            "{name}: {test_score} of {max}"
        );
        let status = test["status"].as_str().unwrap_or_default();
        let expected = if test_score == max {
            "passed"
        } else {
            "failed"
        };
        assert_eq!(status, expected, "{name}");
        assert!(
            VISIBILITIES.contains(&test["visibility"].as_str().unwrap_or_default()),
            "{name}: {test}"
        );
        assert!(test["output"].is_string(), "{name}: no output");
        sum += test_score;
    }
    assert_eq!(
        score, sum,
        "the score is not the sum of the tests': {results}"
    );
    score
}

/// `grade --code ONE_WORKSPACE --gradescope results.json`: Gradescope's
/// fields, a test per chapter, and the reason a run scored nothing.
#[cfg(unix)]
#[test]
fn one_submission_is_graded_into_gradescopes_results() {
    let dir = tempfile::tempdir().expect("temp dir");
    let submission = fake_workspace(dir.path(), "submission", &verdict_writer(&[], true, ""));
    let mut args = vec![
        "grade",
        "--code",
        "submission",
        "--gradescope",
        "results.json",
    ];
    args.extend(sandbox_or_skip(
        "one_submission_is_graded_into_gradescopes_results",
    ));
    let out = raylab(&args, dir.path());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let text = std::fs::read_to_string(dir.path().join("results.json")).expect("results.json");
    let results: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    assert_eq!(assert_gradescope_results(&results, usize::from(LAST)), 0.0);
    let output = results["output"].as_str().unwrap_or_default();
    assert!(
        output.contains("error: no verdict") || output.contains("error: not counted"),
        "the reason is shown: {output}"
    );
    // Twice: raylab replaces its own results.json.
    assert_eq!(raylab(&args, dir.path()).status.code(), Some(1));
    // A class folder is not one submission.
    let out = raylab(
        &[
            "grade",
            "--code",
            ".",
            "--gradescope",
            "r.json",
            "--no-sandbox",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("not a workspace"), "{}", stderr(&out));
    assert!(submission.join("Cargo.toml").is_file());
}

/// `grade CLASS --gradebook FILE`: the columns Canvas reads a student by,
/// one column per chapter and the total, one row per student.
#[test]
fn a_class_gets_a_gradebook_that_canvas_and_moodle_import() {
    let dir = tempfile::tempdir().expect("temp dir");
    let class = dir.path().join("class");
    for student in ["ann", "bob"] {
        std::fs::create_dir_all(class.join(student)).expect("mkdir");
    }
    for chapter in 1..=2 {
        let image = render(chapter, 160, 120, |_| {});
        save(&class.join(format!("ann/chapter-{chapter}.png")), &image);
    }
    // Chapter 1's image handed in for chapter 2 as well.
    save(
        &class.join("bob/chapter-1.png"),
        &render(1, 160, 120, |_| {}),
    );
    save(
        &class.join("bob/chapter-2.png"),
        &render(1, 160, 120, |_| {}),
    );
    let out = raylab(
        &["grade", "class", "--gradebook", "gradebook.csv"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let csv = std::fs::read_to_string(dir.path().join("gradebook.csv")).expect("gradebook");
    let rows: Vec<Vec<&str>> = csv.lines().map(|line| line.split(',').collect()).collect();
    let columns = 5 + usize::from(LAST) + 1;
    assert_eq!(
        rows[0][..5],
        ["Student", "ID", "SIS User ID", "SIS Login ID", "Section"]
    );
    assert_eq!(rows[0][5], "raylab chapter 1");
    assert_eq!(rows[0][columns - 1], format!("raylab total ({LAST})"));
    assert_eq!(rows.len(), 3, "{csv}");
    let mut expected_ann = vec!["ann", "", "", "ann", "", "1", "1"];
    expected_ann.extend(std::iter::repeat_n("0", usize::from(LAST) - 2));
    expected_ann.push("2");
    assert_eq!(rows[1], expected_ann, "{csv}");
    assert_eq!(rows[2][5..7], ["1", "0"], "{csv}");
    assert_eq!(rows[2][columns - 1], "1", "{csv}");
    for row in &rows {
        assert_eq!(row.len(), columns, "{csv}");
    }
    // One student's folder has no gradebook.
    let out = raylab(
        &["grade", "class/ann", "--gradebook", "one.csv"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

/// A submission's links are never written through, nor followed, by
/// `run_autograder` (which runs before any sandbox, as Gradescope's root):
/// a `main.rs` that links to a file of the grader's leaves that file alone
/// and is replaced by the template's; a `lib.rs` that links to nothing
/// stays a link (the run is then not counted); a `src` that links to a
/// folder of the grader's brings none of its files in.
#[cfg(unix)]
#[test]
fn the_autograder_writes_through_no_link_of_a_submission() {
    use std::os::unix::fs::{PermissionsExt, symlink};
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path().join("autograder");
    let template = root.join("template/submission/src");
    std::fs::create_dir_all(&template).expect("mkdir");
    std::fs::write(template.join("main.rs"), "fn main() {}\n").expect("write");
    std::fs::write(template.join("lib.rs"), "pub struct Mine;\n").expect("write");
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).expect("mkdir");
    let stub = bin.join("raylab");
    std::fs::write(&stub, "#!/bin/sh\nexit 0\n").expect("write");
    std::fs::set_permissions(&stub, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    let grader = dir.path().join("grader");
    std::fs::create_dir(&grader).expect("mkdir");
    let precious = grader.join("precious.txt");
    std::fs::write(&precious, "the grader's own\n").expect("write");
    let script =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/gradescope/run_autograder");
    let run = || {
        let out = std::process::Command::new("bash")
            .arg(&script)
            .env("AUTOGRADER_ROOT", &root)
            .env("HOME", dir.path())
            .env(
                "PATH",
                format!(
                    "{}:{}",
                    bin.display(),
                    std::env::var("PATH").unwrap_or_default()
                ),
            )
            .output()
            .expect("bash runs");
        assert!(out.status.success(), "{}", stderr(&out));
    };
    let submitted = root.join("submission/src");
    std::fs::create_dir_all(&submitted).expect("mkdir");
    symlink(&precious, submitted.join("main.rs")).expect("link");
    run();
    assert_eq!(
        std::fs::read_to_string(&precious).expect("read"),
        "the grader's own\n"
    );
    let graded = root.join("work/submission/src");
    let main_rs = graded.join("main.rs");
    assert!(!main_rs.is_symlink(), "main.rs is the template's file");
    assert_eq!(
        std::fs::read_to_string(&main_rs).expect("read"),
        "fn main() {}\n"
    );
    symlink(grader.join("nothing.rs"), submitted.join("lib.rs")).expect("link");
    run();
    assert!(
        !grader.join("nothing.rs").exists(),
        "written through lib.rs"
    );
    assert!(graded.join("lib.rs").is_symlink(), "lib.rs is left a link");
    std::fs::remove_dir_all(&submitted).expect("rm");
    symlink(&grader, &submitted).expect("link");
    run();
    assert!(
        !graded.join("precious.txt").exists(),
        "a linked src brought the grader's files in"
    );
}

/// Gradescope's `run_autograder` grades each submission under a fresh
/// seed of its own and with the zip's hidden scenes, and passes its
/// settings on: run with a `raylab` that writes down its arguments.
#[cfg(unix)]
#[test]
fn the_autograder_passes_its_settings_on() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path().join("autograder");
    let template = root.join("template/submission/src");
    std::fs::create_dir_all(&template).expect("mkdir");
    for file in ["main.rs", "lib.rs"] {
        std::fs::write(template.join(file), "").expect("write");
    }
    std::fs::create_dir_all(root.join("submission/src")).expect("mkdir");
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).expect("mkdir");
    let said = dir.path().join("arguments");
    let stub = bin.join("raylab");
    std::fs::write(
        &stub,
        format!("#!/bin/sh\nprintf '%s\\n' \"$@\" > '{}'\n", said.display()),
    )
    .expect("write");
    std::fs::set_permissions(&stub, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    let script =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/gradescope/run_autograder");
    let run = |settings: &[(&str, &str)]| -> Vec<String> {
        let mut command = std::process::Command::new("bash");
        command
            .arg(&script)
            .env("AUTOGRADER_ROOT", &root)
            .env("HOME", dir.path())
            .env(
                "PATH",
                format!(
                    "{}:{}",
                    bin.display(),
                    std::env::var("PATH").unwrap_or_default()
                ),
            );
        for (name, value) in settings {
            command.env(name, value);
        }
        let out = command.output().expect("bash runs");
        assert!(out.status.success(), "{}", stderr(&out));
        std::fs::read_to_string(&said)
            .expect("the stub ran")
            .lines()
            .map(str::to_string)
            .collect()
    };
    let after = |args: &[String], flag: &str| -> Option<String> {
        let at = args.iter().position(|arg| arg == flag)?;
        args.get(at + 1).cloned()
    };
    let first = run(&[]);
    let second = run(&[]);
    let seed = after(&first, "--fresh").expect("a fresh seed by default");
    assert!(seed.parse::<u64>().is_ok(), "{seed}");
    assert_ne!(
        Some(seed),
        after(&second, "--fresh"),
        "a new seed each submission"
    );
    assert_eq!(
        after(&first, "--scene"),
        None,
        "no scenes folder, no --scene"
    );
    std::fs::create_dir_all(root.join("source/scenes")).expect("mkdir");
    let args = run(&[
        ("RAYLAB_FRESH", "42"),
        ("RAYLAB_CHAPTER", "5"),
        ("RAYLAB_TIMEOUT", "77"),
        ("RAYLAB_SCENE_CHAPTER", "9"),
    ]);
    assert_eq!(after(&args, "--fresh").as_deref(), Some("42"));
    assert_eq!(after(&args, "--chapter").as_deref(), Some("5"));
    assert_eq!(after(&args, "--timeout").as_deref(), Some("77"));
    assert_eq!(after(&args, "--scene-chapter").as_deref(), Some("9"));
    let scenes = root.join("source/scenes").display().to_string();
    assert_eq!(after(&args, "--scene"), Some(scenes));
    let args = run(&[
        ("RAYLAB_FRESH", "off"),
        ("RAYLAB_SCENES", "/elsewhere/one.toml"),
    ]);
    assert!(!args.iter().any(|arg| arg == "--fresh"), "{args:?}");
    assert_eq!(
        after(&args, "--scene").as_deref(),
        Some("/elsewhere/one.toml")
    );
}
