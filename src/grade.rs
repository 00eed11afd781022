//! Grading a folder of student renders against the reference images
//! (`raylab grade`).
//!
//! Students hand in one PNG per chapter named `chapter-N.png` (N a chapter
//! of the course, lower case, no leading zero), rendered from the chapter's
//! built-in scene with its default settings, at the lesson's size, at
//! the size of an `--against` image, or small (at most [`SMALL_PIXELS`],
//! at least [`MIN_SIDE`] a side): see [`References::graded_size`]. Each
//! is compared (see
//! [`crate::diff`]) with a reference of the same size, never one rendered by
//! code that can be the student's (see [`References`]): an `--against`
//! folder's `chapter-N.png` of that size if one is given, else the reference
//! image shipped inside raylab ([`crate::chapters::ChapterInfo::reference_png`],
//! 160x120), else the built-in scene rendered at the hand-in's size by
//! raylab's reference chapters, once they are shown to reproduce the shipped
//! images bit for bit. Anything else in the folder is listed as ignored
//! (the first 50 by name, then how many more), never fatal.
//!
//! [`class`] grades a folder of students (one subfolder each), and their
//! workspaces' `check` with `--code`.

pub mod canonical;
pub mod class;
pub mod code;
pub mod compiled;
pub mod hidden;
pub mod lms;
pub mod origin;
pub mod references;
pub mod sandbox;
pub mod similarity;
pub mod snapshot;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use base64::Engine as _;

use crate::chapters::{LAST_CHAPTER, REFERENCE_HEIGHT, REFERENCE_WIDTH};
use crate::course::Chapters;
use crate::diff::{Comparison, Criteria, Image, compare, psnr_text};
pub use references::{MODIFIED_CHAPTERS, References, shipped_reference};

/// One chapter compared with its reference.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Graded {
    pub chapter: u8,
    #[serde(with = "raw_path")]
    pub file: PathBuf,
    /// The two images, while they are kept: a class's grading writes a
    /// student's figures into the report as it goes and then drops them
    /// ([`Graded::drop_images`]), so that its memory does not grow with the
    /// class.
    #[serde(skip)]
    pub images: Option<Box<GradedImages>>,
    /// Where the reference came from, for people.
    pub reference_source: String,
    pub comparison: Comparison,
}

/// A hand-in and the reference it was compared with.
#[derive(Debug, Clone)]
pub struct GradedImages {
    pub student: Image,
    pub reference: Image,
}

/// A chapter's file that could not be compared, and why.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Unreadable {
    pub chapter: u8,
    #[serde(with = "raw_path")]
    pub file: PathBuf,
    pub reason: String,
}

/// A folder entry that is not a chapter's PNG, and why.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Ignored {
    pub name: String,
    pub reason: String,
}

/// The most ignored entries of a folder listed one by one: a hand-in of
/// 300,000 empty files made a report of 15 MB naming each.
pub(crate) const MOST_IGNORED_LISTED: usize = 50;

/// A folder's ignored entries as they are found: the first
/// [`MOST_IGNORED_LISTED`] by name, and how many more there were.
#[derive(Default)]
pub(crate) struct IgnoredList {
    kept: std::collections::BTreeMap<String, String>,
    more: usize,
}

impl IgnoredList {
    pub(crate) fn add(&mut self, ignored: Ignored) {
        self.kept.insert(ignored.name, ignored.reason);
        if self.kept.len() > MOST_IGNORED_LISTED {
            self.kept.pop_last();
            self.more += 1;
        }
    }

    /// The entries kept, sorted by name, then one line for the rest, which
    /// are `rest`.
    pub(crate) fn into_list(self, rest: &str) -> Vec<Ignored> {
        let more = self.more;
        let mut list: Vec<Ignored> = self
            .kept
            .into_iter()
            .map(|(name, reason)| Ignored { name, reason })
            .collect();
        if more > 0 {
            list.push(Ignored {
                name: format!("{more} more"),
                reason: format!("{rest} either, not listed one by one"),
            });
        }
        list
    }
}

/// The outcome of grading one folder.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Grade {
    #[serde(with = "raw_path")]
    pub folder: PathBuf,
    pub criteria: Criteria,
    pub graded: Vec<Graded>,
    pub missing: Vec<u8>,
    pub unreadable: Vec<Unreadable>,
    pub ignored: Vec<Ignored>,
}

/// A path in a grading job's result file as its bytes, so that a student's
/// folder whose name is not UTF-8 survives the JSON (serde's own `PathBuf`
/// refuses it).
pub(crate) mod raw_path {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::path::{Path, PathBuf};

    pub fn serialize<S: Serializer>(path: &Path, serializer: S) -> Result<S::Ok, S::Error> {
        #[cfg(unix)]
        {
            use std::os::unix::ffi::OsStrExt;
            path.as_os_str().as_bytes().serialize(serializer)
        }
        #[cfg(not(unix))]
        {
            path.to_string_lossy().as_bytes().serialize(serializer)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<PathBuf, D::Error> {
        let bytes = Vec::<u8>::deserialize(deserializer)?;
        #[cfg(unix)]
        {
            use std::os::unix::ffi::OsStringExt;
            Ok(PathBuf::from(std::ffi::OsString::from_vec(bytes)))
        }
        #[cfg(not(unix))]
        {
            Ok(PathBuf::from(String::from_utf8_lossy(&bytes).into_owned()))
        }
    }
}

/// Why a folder or a class could not be graded, a hand-in is unreadable
/// (its [`Unreadable::reason`]) or a report not made. Each message is whole,
/// the underlying reason included.
#[derive(Debug, thiserror::Error)]
pub enum GradeError {
    #[error("cannot read the folder {}: {error}", folder.display())]
    Folder {
        folder: PathBuf,
        error: std::io::Error,
    },
    /// A hand-in that is not a regular file, or too large.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// A hand-in or a reference that does not decode, or images that cannot
    /// be compared.
    #[error(transparent)]
    Image(#[from] crate::diff::DiffError),
    #[error(
        "too small to grade: {width}x{height}; hand in at least {MIN_SIDE}x{MIN_SIDE} pixels \
         (the references are {REFERENCE_WIDTH}x{REFERENCE_HEIGHT})"
    )]
    TooSmall { width: u32, height: u32 },
    #[error(
        "too large to grade: {width}x{height} is more than {MAX_HAND_IN_PIXELS} pixels \
         (1920x1080); its reference would be rendered at that size. Hand in the default \
         size of `raylab render --chapter N`"
    )]
    TooLarge { width: u32, height: u32 },
    #[error(
        "not graded at {width}x{height}: references are made at the lesson's size, \
         {}x{} for chapter {chapter} (what `raylab render --chapter {chapter}` writes), at \
         the size of an --against image, or at up to {SMALL_PIXELS} pixels in all \
         ({REFERENCE_WIDTH}x{REFERENCE_HEIGHT}); render the chapter again at one of those",
        lesson.0, lesson.1
    )]
    NotAGradedSize {
        chapter: u8,
        width: u32,
        height: u32,
        lesson: (u32, u32),
    },
    #[error(transparent)]
    Scene(#[from] crate::SceneError),
    #[error(transparent)]
    Render(#[from] crate::RenderError),
    /// `size` is the hand-in's, written `WxH`.
    #[error("cannot render a reference at {size}: {error}")]
    ReferenceSize {
        size: String,
        error: crate::scene::SettingsError,
    },
    /// The chapters do not reproduce the shipped image; `why` says how.
    #[error("not graded: {MODIFIED_CHAPTERS} ({why})")]
    Modified { why: String },
    #[error("there is no chapter {0}")]
    NoSuchChapter(u8),
    #[error("raylab's shipped reference of chapter {chapter}: {error}")]
    Shipped {
        chapter: u8,
        error: crate::diff::DiffError,
    },
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    #[error("there is no student {name} in {}", folder.display())]
    NoSuchStudent { name: String, folder: PathBuf },
    #[error("the result of {name} was graded another way: {why}; merge results of one grading")]
    MergeMismatch { name: String, why: String },
    #[error("two results for {name}")]
    MergeTwice { name: String },
    #[error("hidden scene {}: {why}", file.display())]
    HiddenScene { file: PathBuf, why: String },
    /// The temporary file the class report's sections go to.
    #[error("cannot write the report's temporary file: {0}")]
    Staging(std::io::Error),
    /// A student's run could not be sandboxed (its folder, its copy of the
    /// workspace).
    #[error(transparent)]
    Sandbox(#[from] sandbox::SandboxError),
    /// The command that runs a workspace's check could not start.
    #[error("cannot run {} in {}: {error}", cargo.display(), workspace.display())]
    Run {
        cargo: PathBuf,
        workspace: PathBuf,
        error: std::io::Error,
    },
}

/// The error for reading the folder `folder`, for `map_err`.
fn folder_error(folder: &Path) -> impl FnOnce(std::io::Error) -> GradeError + '_ {
    move |error| GradeError::Folder {
        folder: folder.to_path_buf(),
        error,
    }
}

/// The chapter a file name stands for, or why it stands for none.
pub fn chapter_of(name: &str) -> Result<u8, NameError> {
    let Some(stem) = name.strip_suffix(".png") else {
        return Err(if name.to_ascii_lowercase().ends_with(".png") {
            NameError::ExtensionCase
        } else {
            NameError::NotPng
        });
    };
    let Some(number) = stem.strip_prefix("chapter-") else {
        return Err(NameError::NotChapterName);
    };
    if number.is_empty() || !number.bytes().all(|b| b.is_ascii_digit()) {
        return Err(NameError::NotChapterNumber);
    }
    match number.parse::<u8>() {
        Ok(n) if (1..=LAST_CHAPTER).contains(&n) && !number.starts_with('0') => Ok(n),
        _ => Err(NameError::NoSuchChapter {
            number: number.to_string(),
        }),
    }
}

/// Why a file name stands for no chapter ([`chapter_of`]): the words a
/// grade report gives for an ignored file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NameError {
    #[error("the extension must be .png in lower case")]
    ExtensionCase,
    #[error("not a .png file")]
    NotPng,
    #[error("not named chapter-N.png")]
    NotChapterName,
    #[error("not named chapter-N.png (N must be a chapter number)")]
    NotChapterNumber,
    /// `number` as written: digits, maybe with leading zeros.
    #[error("there is no chapter {number} (chapters are 1 to {LAST_CHAPTER}, no leading zeros)")]
    NoSuchChapter { number: String },
}

/// Grades the PNGs in `folder` against raylab's references ([`References`]
/// with raylab's own chapters; `against` is an optional folder of
/// `chapter-N.png` used where its size is the hand-in's). `skip` names a
/// file not to list at all (the report itself, when it is written into the
/// folder).
pub fn grade(
    folder: &Path,
    against: Option<&Path>,
    criteria: Criteria,
    skip: Option<&Path>,
) -> Result<Grade, GradeError> {
    grade_with(
        folder,
        &mut References::<crate::Reference>::new(against),
        criteria,
        skip,
    )
}

/// [`grade`] with the references of `references`, whose chapters `R`
/// render a reference at a size raylab ships none for. Only tests use
/// chapters other than raylab's own: to plant a modified "reference" and
/// show that it cannot pass a hand-in made by the same code.
pub fn grade_with<R: Chapters>(
    folder: &Path,
    references: &mut References<R>,
    criteria: Criteria,
    skip: Option<&Path>,
) -> Result<Grade, GradeError> {
    let entries = std::fs::read_dir(folder).map_err(folder_error(folder))?;
    let skip = skip.and_then(|path| path.canonicalize().ok());
    // A chapter's file, and why it is refused unread, if it is.
    let mut found: Vec<(u8, PathBuf, Option<String>)> = Vec::new();
    let mut ignored = IgnoredList::default();
    let chapter_looks: Vec<String> = (1..=LAST_CHAPTER)
        .map(|chapter| crate::text::look(&format!("chapter-{chapter}.png")))
        .collect();
    for entry in entries {
        let entry = entry.map_err(folder_error(folder))?;
        let path = entry.path();
        let name = crate::text::visible_name(&entry.file_name());
        if skip.is_some() && path.canonicalize().ok() == skip {
            continue;
        }
        // The entry itself, not what a link points to.
        let kind = entry.file_type().map_err(folder_error(folder))?;
        if kind.is_symlink() {
            // A link could lead out of the folder (to another student's
            // image, to /etc/passwd): it is never followed.
            let reason = SYMBOLIC_LINK_REFUSED.to_string();
            match chapter_of(&name) {
                Ok(chapter) => found.push((chapter, path, Some(reason))),
                Err(_) => ignored.add(Ignored { name, reason }),
            }
            continue;
        }
        if kind.is_dir() {
            ignored.add(Ignored {
                name,
                reason: "a folder".into(),
            });
            continue;
        }
        let raw = entry.file_name();
        let raw = raw.to_string_lossy();
        let look = crate::text::look(&raw);
        let looks_like = (1..=LAST_CHAPTER)
            .zip(&chapter_looks)
            .find(|(_, chapter_look)| **chapter_look == look)
            .map(|(chapter, _)| chapter)
            .ok_or(());
        match (chapter_of(&raw), looks_like) {
            (Ok(chapter), _) => found.push((chapter, path, None)),
            // `chapter\u{2010}3.png` (a Unicode hyphen) shows as the name
            // it is not: spelled out, and said so.
            (Err(_), Ok(chapter)) => ignored.add(Ignored {
                name: crate::text::spelled_out(&entry.file_name()),
                reason: format!(
                    "looks like chapter-{chapter}.png, but is spelled with other characters"
                ),
            }),
            (Err(reason), Err(_)) => ignored.add(Ignored {
                name,
                reason: reason.to_string(),
            }),
        }
    }
    found.sort();
    let ignored = ignored.into_list("entries that are not a chapter's image");
    let mut grade = Grade {
        folder: folder.to_path_buf(),
        criteria,
        graded: Vec::new(),
        missing: Vec::new(),
        unreadable: Vec::new(),
        ignored,
    };
    for chapter in 1..=LAST_CHAPTER {
        let Some((_, file, refused)) = found.iter().find(|(c, _, _)| *c == chapter) else {
            grade.missing.push(chapter);
            continue;
        };
        if let Some(reason) = refused {
            grade.unreadable.push(Unreadable {
                chapter,
                file: file.clone(),
                reason: reason.clone(),
            });
            continue;
        }
        match grade_chapter(chapter, file, references, criteria) {
            Ok(graded) => grade.graded.push(graded),
            Err(error) => grade.unreadable.push(Unreadable {
                chapter,
                file: file.clone(),
                reason: format!("{error:#}"),
            }),
        }
    }
    Ok(grade)
}

/// Why a symbolic link among the hand-ins is not graded.
const SYMBOLIC_LINK_REFUSED: &str = "refused: a symbolic link; a hand-in must be a regular \
     file inside the folder (links are never followed)";

/// The smallest hand-in graded, per side. A reference can be rendered at
/// the student's size, so without a floor a 1x1 image (one pixel centre,
/// easy to match) would pass any chapter.
pub const MIN_SIDE: u32 = 16;

/// The largest hand-in graded, in pixels (1920x1080). Its reference is
/// rendered at its size, in time and memory that grow with it: a small PNG
/// can declare 16384x2441 pixels, 40 million, and cost minutes for one file.
pub const MAX_HAND_IN_PIXELS: u64 = 1920 * 1080;

/// The most pixels of a hand-in whose reference is rendered at any size:
/// the shipped reference's. Beside it only the lesson's size (one render
/// per chapter for a whole class) and an `--against` image's are graded,
/// so a class that hands in a different size each costs at most one small
/// render per hand-in, never one at a size a student chose.
pub const SMALL_PIXELS: u64 = REFERENCE_WIDTH as u64 * REFERENCE_HEIGHT as u64;

/// The width and height a PNG declares, read from its header alone.
fn declared_size(bytes: &[u8]) -> Result<(u32, u32), GradeError> {
    let mut header = png::Decoder::new(std::io::Cursor::new(bytes));
    let info = header
        .read_header_info()
        .map_err(|error| GradeError::Image(crate::diff::DiffError::CorruptedHeader(error)))?;
    Ok((info.width, info.height))
}

fn grade_chapter<R: Chapters>(
    chapter: u8,
    file: &Path,
    references: &mut References<R>,
    criteria: Criteria,
) -> Result<Graded, GradeError> {
    // Only a regular file, not a link (even one created after the folder
    // was listed), within the size limits of crate::input.
    let bytes = crate::input::read_bounded(
        file,
        crate::input::MAX_PNG_FILE_BYTES,
        "PNG",
        crate::input::Links::Refuse,
    )?;
    if !bytes.starts_with(&crate::diff::PNG_SIGNATURE) {
        return Err(crate::diff::DiffError::NotPng.into());
    }
    // The size before the pixels: a hand-in too large is refused undecoded.
    let (width, height) = declared_size(&bytes)?;
    if u64::from(width) * u64::from(height) > MAX_HAND_IN_PIXELS {
        return Err(GradeError::TooLarge { width, height });
    }
    if width < MIN_SIDE || height < MIN_SIDE {
        return Err(GradeError::TooSmall { width, height });
    }
    references.graded_size(chapter, width, height)?;
    let student = Image::decode_png(&bytes)?;
    let (reference, reference_source) =
        references.reference(chapter, student.width, student.height)?;
    let comparison = compare(&student, &reference, criteria, ("student", "reference"))?;
    Ok(Graded {
        chapter,
        file: file.to_path_buf(),
        images: Some(Box::new(GradedImages { student, reference })),
        reference_source,
        comparison,
    })
}

impl Graded {
    pub fn passes(&self) -> bool {
        self.comparison.passes()
    }

    /// Keeps the metrics and drops the pixels: both images and the
    /// per-pixel differences (a 640x480 chapter's are 2 MB).
    pub fn drop_images(&mut self) {
        self.images = None;
        self.comparison.pixel_differences = Vec::new();
    }
}

impl Grade {
    /// Every chapter handed in, readable, and within the criteria.
    pub fn all_pass(&self) -> bool {
        self.missing.is_empty()
            && self.unreadable.is_empty()
            && self.graded.iter().all(Graded::passes)
    }

    pub fn passed(&self) -> usize {
        self.graded.iter().filter(|g| g.passes()).count()
    }

    /// Why chapter `chapter` counts as missing: no `chapter-N.png`, and the
    /// file that was probably meant for it, if one is ignored
    /// (`Chapter-3.PNG`, `chapter-03.png`), with the reason.
    pub fn missing_detail(&self, chapter: u8) -> String {
        let wanted = format!("chapter-{chapter}.png");
        let meant = self.ignored.iter().find(|ignored| {
            let name = ignored.name.to_ascii_lowercase();
            name == wanted || name == format!("chapter-0{chapter}.png")
        });
        match meant {
            Some(ignored) => format!("no {wanted} ({}: {})", ignored.name, ignored.reason),
            None => format!("no {wanted}"),
        }
    }

    /// The Markdown summary printed by `raylab grade`.
    pub fn markdown(&self, report: &Path) -> String {
        let mut md = String::new();
        let c = &self.criteria;
        let _ = writeln!(
            md,
            "# raylab grade: {}\n",
            markdown_escape(&self.folder.display().to_string())
        );
        let _ = writeln!(
            md,
            "A pixel is over when a channel differs by more than {} levels; a chapter passes when {}.\n",
            c.threshold,
            allowance_text(c)
        );
        self.markdown_table(&mut md);
        self.markdown_problems(&mut md);
        let _ = writeln!(
            md,
            "**{} of {} chapters pass** ({} compared, {} missing, {} unreadable). Report: {}",
            self.passed(),
            LAST_CHAPTER,
            self.graded.len(),
            self.missing.len(),
            self.unreadable.len(),
            markdown_escape(&report.display().to_string())
        );
        md
    }

    /// The Markdown table of the chapters compared, if any.
    fn markdown_table(&self, md: &mut String) {
        if !self.graded.is_empty() {
            md.push_str("| chapter | file | size | max | mean | RMSE | PSNR (dB) | over threshold | result | reference |\n");
            md.push_str("|---:|---|---|---:|---:|---:|---:|---:|---|---|\n");
            for g in &self.graded {
                let m = &g.comparison.metrics;
                let _ = writeln!(
                    md,
                    "| {} | {} | {}x{} | {} | {:.4} | {:.4} | {} | {} ({:.3}%) | {} | {} |",
                    g.chapter,
                    markdown_escape(&file_name(&g.file)),
                    m.width,
                    m.height,
                    m.max,
                    m.mean,
                    m.rmse,
                    psnr_text(m.psnr_db),
                    m.pixels_over,
                    m.percent_over(),
                    if g.passes() { "PASS" } else { "**FAIL**" },
                    markdown_escape(&g.reference_source),
                );
            }
            md.push('\n');
        }
    }

    /// The Markdown lists of the missing, unreadable and ignored files.
    fn markdown_problems(&self, md: &mut String) {
        if !self.missing.is_empty() {
            let list: Vec<String> = self
                .missing
                .iter()
                .map(|&c| {
                    let detail = self.missing_detail(c);
                    detail.strip_prefix("no ").unwrap_or(&detail).to_string()
                })
                .collect();
            let _ = writeln!(md, "Missing: {}\n", markdown_escape(&list.join(", ")));
        }
        if !self.unreadable.is_empty() {
            md.push_str("Unreadable:\n");
            for u in &self.unreadable {
                let _ = writeln!(
                    md,
                    "- {}: {}",
                    markdown_escape(&file_name(&u.file)),
                    markdown_escape(&u.reason)
                );
            }
            md.push('\n');
        }
        if !self.ignored.is_empty() {
            md.push_str("Ignored:\n");
            for i in &self.ignored {
                let _ = writeln!(
                    md,
                    "- {}: {}",
                    markdown_escape(&i.name),
                    markdown_escape(&i.reason)
                );
            }
            md.push('\n');
        }
    }

    /// The self-contained HTML report: every image inlined as a base64 PNG.
    pub fn html(&self) -> Result<String, GradeError> {
        let mut h = String::new();
        let c = &self.criteria;
        let title = format!("raylab grade: {}", self.folder.display());
        let _ = write!(
            h,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
            html_escape(&title),
            html_escape(&title)
        );
        let _ = writeln!(
            h,
            "<p class=\"verdict {}\"><strong>{} of {} chapters pass</strong>: {} compared, {} missing, {} unreadable.</p>",
            if self.all_pass() { "pass" } else { "fail" },
            self.passed(),
            LAST_CHAPTER,
            self.graded.len(),
            self.missing.len(),
            self.unreadable.len()
        );
        let _ = writeln!(
            h,
            "<p>A pixel is <em>over</em> when one of its R, G, B values differs from the reference by more than {} levels (of 255); a chapter passes when {}. Heatmap: dim grey where identical, dark blue (1 level) to red (the largest difference) where not; the bar below it is the scale, the white tick the threshold.</p>",
            c.threshold,
            allowance_text(c)
        );
        self.html_summary_table(&mut h);
        self.html_problems(&mut h);
        for g in &self.graded {
            chapter_html(&mut h, g)?;
        }
        h.push_str("</body>\n</html>\n");
        Ok(h)
    }

    /// The table of the chapters compared, each linked to its section.
    fn html_summary_table(&self, h: &mut String) {
        if !self.graded.is_empty() {
            h.push_str("<table class=\"summary\">\n<tr><th>chapter</th><th>result</th><th>max</th><th>PSNR (dB)</th><th>pixels over</th></tr>\n");
            for g in &self.graded {
                let m = &g.comparison.metrics;
                let _ = writeln!(
                    h,
                    "<tr><td><a href=\"#chapter-{0}\">{0}</a></td><td class=\"{1}\">{2}</td><td>{3}</td><td>{4}</td><td>{5} ({6:.3}%)</td></tr>",
                    g.chapter,
                    if g.passes() { "pass" } else { "fail" },
                    if g.passes() { "PASS" } else { "FAIL" },
                    m.max,
                    psnr_text(m.psnr_db),
                    m.pixels_over,
                    m.percent_over()
                );
            }
            h.push_str("</table>\n");
        }
    }

    /// The missing, unreadable and ignored files, if any.
    fn html_problems(&self, h: &mut String) {
        if !self.missing.is_empty() || !self.unreadable.is_empty() || !self.ignored.is_empty() {
            h.push_str("<section class=\"problems\">\n");
            if !self.missing.is_empty() {
                let list: Vec<String> = self
                    .missing
                    .iter()
                    .map(|c| format!("chapter-{c}.png"))
                    .collect();
                let _ = writeln!(
                    h,
                    "<p><strong>Missing:</strong> {}</p>",
                    html_escape(&list.join(", "))
                );
            }
            for (heading, rows) in [
                (
                    "Unreadable",
                    self.unreadable
                        .iter()
                        .map(|u| (file_name(&u.file), u.reason.clone()))
                        .collect::<Vec<_>>(),
                ),
                (
                    "Ignored",
                    self.ignored
                        .iter()
                        .map(|i| (i.name.clone(), i.reason.clone()))
                        .collect(),
                ),
            ] {
                if rows.is_empty() {
                    continue;
                }
                let _ = writeln!(h, "<p><strong>{heading}:</strong></p>\n<ul>");
                for (name, reason) in rows {
                    let _ = writeln!(
                        h,
                        "<li><code>{}</code>: {}</li>",
                        html_escape(&name),
                        html_escape(&reason)
                    );
                }
                h.push_str("</ul>\n");
            }
            h.push_str("</section>\n");
        }
    }
}

/// One chapter's section of the report: the student's image, the reference
/// and the heatmap, inlined, above the metrics.
fn chapter_html(h: &mut String, g: &Graded) -> Result<(), GradeError> {
    let m = &g.comparison.metrics;
    let pass = g.passes();
    let _ = writeln!(
        h,
        "<section class=\"chapter {}\" id=\"chapter-{}\">\n<h2>Chapter {} <span class=\"badge\">{}</span></h2>",
        if pass { "pass" } else { "fail" },
        g.chapter,
        g.chapter,
        if pass { "PASS" } else { "FAIL" }
    );
    figures_html(h, g, &format!("student: {}", file_name(&g.file)))?;
    h.push_str("<table>\n");
    let at = m
        .max_at
        .map(|(x, y)| format!(" at x={x}, y={y}"))
        .unwrap_or_default();
    for (name, value) in [
        ("size", format!("{}x{}", m.width, m.height)),
        ("max abs difference", format!("{}{at}", m.max)),
        ("mean abs difference", format!("{:.6}", m.mean)),
        ("RMSE", format!("{:.6}", m.rmse)),
        ("PSNR", format!("{} dB", psnr_text(m.psnr_db))),
        (
            "pixels over threshold",
            format!(
                "{} of {} ({:.3}%)",
                m.pixels_over,
                m.pixels,
                m.percent_over()
            ),
        ),
    ] {
        let _ = writeln!(
            h,
            "<tr><th>{name}</th><td>{}</td></tr>",
            html_escape(&value)
        );
    }
    h.push_str("</table>\n</section>\n");
    Ok(())
}

/// The student's image, the reference and the heatmap of `g`, inlined as
/// base64 PNGs (nothing once its images are dropped); `student` captions
/// the first.
fn figures_html(h: &mut String, g: &Graded, student: &str) -> Result<(), GradeError> {
    let Some(images) = &g.images else {
        return Ok(());
    };
    let heatmap = g.comparison.heatmap(&images.student)?;
    h.push_str("<div class=\"images\">\n");
    for (caption, image) in [
        (student.to_string(), &images.student),
        (
            format!("reference: {}", g.reference_source),
            &images.reference,
        ),
        ("heatmap".to_string(), &heatmap),
    ] {
        let _ = writeln!(
            h,
            "<figure><img alt=\"{}\" src=\"data:image/png;base64,{}\"><figcaption>{}</figcaption></figure>",
            html_escape(&caption),
            base64::engine::general_purpose::STANDARD.encode(image.encode_png()?),
            html_escape(&caption)
        );
    }
    h.push_str("</div>\n");
    Ok(())
}

/// The pass rule's allowance in words.
fn allowance_text(criteria: &Criteria) -> String {
    if criteria.allowed_percent == 0.0 {
        "no pixel is over".into()
    } else {
        format!(
            "at most {}% of its pixels are over",
            criteria.allowed_percent
        )
    }
}

const STYLE: &str = "
body { font-family: sans-serif; margin: 2em; color: #222; background: #fafafa; }
h1 { font-size: 1.5em; word-break: break-all; }
.verdict { font-size: 1.2em; padding: 0.5em 1em; border-radius: 4px; }
.verdict.pass { background: #d8f5d8; } .verdict.fail { background: #fbdcdc; }
.problems { background: #fff6d6; padding: 0.5em 1em; border-radius: 4px; }
.chapter { background: #fff; border: 1px solid #ddd; border-left: 8px solid #999; margin: 1.5em 0; padding: 0.5em 1em; }
.chapter.pass { border-left-color: #2a2; } .chapter.fail { border-left-color: #c22; }
.badge { font-size: 0.8em; color: #fff; padding: 0.1em 0.5em; border-radius: 4px; }
.pass .badge { background: #2a2; } .fail .badge { background: #c22; }
.images { display: flex; flex-wrap: wrap; gap: 1em; }
figure { margin: 0; flex: 1 1 0; min-width: 200px; max-width: 480px; }
figure img { width: 100%; image-rendering: pixelated; border: 1px solid #ccc; }
figcaption { font-size: 0.85em; color: #555; word-break: break-all; }
table { border-collapse: collapse; margin-top: 0.5em; }
th, td { text-align: left; padding: 0.15em 1em 0.15em 0; font-weight: normal; }
th { color: #555; } td { font-family: monospace; }
.summary { margin-bottom: 1em; } .summary th { font-weight: bold; } .summary td.pass { color: #2a2; } .summary td.fail { color: #c22; font-weight: bold; }
a { color: inherit; }
pre { white-space: pre-wrap; overflow-wrap: anywhere; max-width: 100%; }
.similar table { table-layout: fixed; width: 100%; }
.similar td { width: 50%; vertical-align: top; padding-right: 1em; }
.similar pre { margin: 0.2em 0; }
";

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(crate::text::visible_name)
        .unwrap_or_else(|| crate::text::terminal_safe(&path.display().to_string()))
}

/// `text` as HTML text, with control characters and bidirectional
/// overrides escaped as by [`crate::text::terminal_safe`]: a right-to-left
/// override in a name would show `gnp.exe` as `exe.png`.
fn html_escape(text: &str) -> String {
    let text = crate::text::terminal_safe(text);
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// Keeps a name from breaking the Markdown table or list, or from becoming
/// markup: a hand-in named `<img src=x onerror=alert(2)>` must show as
/// text wherever the summary is pasted. Backslash escapes of ASCII
/// punctuation are plain CommonMark; only the characters that can start
/// markup (HTML, emphasis, code, links, GitHub's strikethrough and maths)
/// are escaped, so that `chapter-1.png` stays readable.
fn markdown_escape(text: &str) -> String {
    let text = crate::text::terminal_safe(text);
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\n' | '\r' => out.push(' '),
            '\\' | '|' | '<' | '>' | '&' | '*' | '_' | '`' | '[' | ']' | '~' | '$' => {
                out.push('\\');
                out.push(c);
            }
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chapter_names() {
        assert_eq!(chapter_of("chapter-3.png"), Ok(3));
        assert_eq!(chapter_of("chapter-8.png"), Ok(8));
        for bad in [
            "chapter-99.png",
            "chapter-0.png",
            "chapter-03.png",
            "chapter-x.png",
            "chapter-.png",
            "chapter-3.PNG",
            "Chapter-3.png",
            "notes.txt",
            "chapter-300.png",
        ] {
            assert!(chapter_of(bad).is_err(), "{bad}");
        }
        assert!(
            chapter_of("chapter-99.png")
                .unwrap_err()
                .to_string()
                .contains("no chapter 99")
        );
    }

    /// Pass 13 of issue 41, finding 8: every ignored entry was listed.
    /// The first 50 by name are, then a count of the rest.
    #[test]
    fn a_folder_of_many_other_files_lists_the_first_and_counts_the_rest() {
        let mut list = IgnoredList::default();
        for index in (0..300).rev() {
            list.add(Ignored {
                name: format!("junk-{index:03}"),
                reason: "not a chapter".into(),
            });
        }
        let listed = list.into_list("entries that are not a chapter's image");
        assert_eq!(listed.len(), MOST_IGNORED_LISTED + 1);
        assert_eq!(listed[0].name, "junk-000");
        assert_eq!(listed[MOST_IGNORED_LISTED - 1].name, "junk-049");
        assert_eq!(listed[MOST_IGNORED_LISTED].name, "250 more");
        let few = IgnoredList::default();
        assert!(few.into_list("").is_empty());
    }

    /// A file named with a look-alike of the hyphen or of a letter shows
    /// as the chapter's name it is not: it is spelled out in the list of
    /// ignored files, and said to look like that chapter's.
    #[test]
    fn a_name_that_looks_like_a_chapters_is_spelled_out() {
        let folder = tempfile::tempdir().expect("a folder");
        for name in ["chapter\u{2010}3.png", "ch\u{430}pter-12.png", "notes.txt"] {
            std::fs::write(folder.path().join(name), b"x").expect("write");
        }
        let grade = grade(folder.path(), None, Criteria::default(), None).expect("graded");
        let listed: Vec<(&str, &str)> = grade
            .ignored
            .iter()
            .map(|ignored| (ignored.name.as_str(), ignored.reason.as_str()))
            .collect();
        let looks = |chapter: u8| {
            format!("looks like chapter-{chapter}.png, but is spelled with other characters")
        };
        assert!(
            listed.contains(&("chapter\\u{2010}3.png", looks(3).as_str())),
            "{listed:?}"
        );
        assert!(
            listed.contains(&("ch\\u{430}pter-12.png", looks(12).as_str())),
            "{listed:?}"
        );
        assert!(
            listed
                .iter()
                .any(|(name, reason)| *name == "notes.txt" && !reason.starts_with("looks")),
            "{listed:?}"
        );
        assert_eq!(grade.missing.len(), usize::from(LAST_CHAPTER));
    }

    #[test]
    fn escaping() {
        assert_eq!(
            html_escape("<a href=\"x\">&'"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
        assert_eq!(markdown_escape("a|b\nc"), "a\\|b c");
        assert_eq!(
            markdown_escape("<img src=x onerror=alert(2)>"),
            "\\<img src=x onerror=alert(2)\\>"
        );
        assert_eq!(markdown_escape("chapter-1.png"), "chapter-1.png");
    }
}
