//! Where the reference a hand-in is compared with comes from, never from
//! code that can be the student's: an `--against` image of the hand-in's
//! size, the image shipped inside raylab, or the built-in scene rendered
//! by raylab's reference chapters once they are shown to reproduce the
//! shipped images bit for bit.

use super::{GradeError, SMALL_PIXELS, declared_size};
use crate::course::Chapters;
use crate::diff::Image;
use std::path::{Path, PathBuf};

/// Why a reference is not rendered when this raylab's chapters do not
/// reproduce the shipped images.
pub const MODIFIED_CHAPTERS: &str = "this raylab's chapters differ from the shipped references; \
     grade at 160x120 or use an unmodified raylab";

/// Where the reference for a hand-in comes from, never from code that can
/// be the student's.
///
/// A student who edits raylab's own chapter files and rebuilds gets a
/// `raylab` whose "reference" chapters are their own code: rendering the
/// reference with it would make any hand-in from that code pass, bit for
/// bit. So the references are, in order:
/// 1. the `against` folder's `chapter-N.png`, when there is one of the
///    hand-in's size (the instructor's own images);
/// 2. at 160x120, the image shipped inside raylab
///    ([`crate::chapters::ChapterInfo::reference_png`], pinned by the snapshot
///    tests);
/// 3. at any other size, the built-in scene rendered by the chapters `R`,
///    but only after `R` has rendered the chapter's scene at 160x120 and
///    matched the shipped image bit for bit; otherwise the hand-in is not
///    graded ([`MODIFIED_CHAPTERS`]).
///
/// The check is done once per chapter and kept, so grading a class renders
/// each chapter's check once.
pub struct References<R: Chapters = crate::Reference> {
    against: Option<PathBuf>,
    /// Per chapter checked so far: `Ok` when `R` reproduces its shipped
    /// image, else why not.
    checked: Vec<(u8, Result<(), String>)>,
    /// The references rendered so far, by chapter and size, most recent
    /// last: a class hands in a few sizes, each rendered once.
    rendered: Vec<RenderedReference>,
    /// Per chapter asked so far, the sizes its hand-ins are graded at.
    sizes: Vec<GradedSizes>,
    chapters: std::marker::PhantomData<R>,
}

/// The sizes above [`SMALL_PIXELS`] a chapter's hand-ins are graded at.
struct GradedSizes {
    chapter: u8,
    /// The built-in scene's.
    lesson: (u32, u32),
    /// The `against` folder's image's, if it has a readable one.
    against: Option<(u32, u32)>,
}

/// A reference rendered at a hand-in's size, kept for the next hand-in of
/// that chapter and size.
struct RenderedReference {
    chapter: u8,
    image: Image,
    source: String,
}

/// How many bytes of rendered references [`References`] keeps: the 11
/// chapters at 640x480 are 10 MB; a class of many sizes drops the oldest.
const RENDERED_REFERENCE_BYTES: usize = 64 << 20;

impl<R: Chapters> References<R> {
    pub fn new(against: Option<&Path>) -> References<R> {
        References {
            against: against.map(Path::to_path_buf),
            checked: Vec::new(),
            rendered: Vec::new(),
            sizes: Vec::new(),
            chapters: std::marker::PhantomData,
        }
    }

    /// Whether a hand-in of chapter `chapter` at `width` x `height` is
    /// graded: at the lesson's size (its built-in scene's), at the size of
    /// the `against` folder's image, or at up to [`SMALL_PIXELS`] pixels.
    /// Any other size would have its reference rendered at a size the
    /// student chose, as large and as many as a class hands in.
    pub fn graded_size(&mut self, chapter: u8, width: u32, height: u32) -> Result<(), GradeError> {
        if u64::from(width) * u64::from(height) <= SMALL_PIXELS {
            return Ok(());
        }
        let (lesson, against) = match self.sizes.iter().find(|sizes| sizes.chapter == chapter) {
            Some(sizes) => (sizes.lesson, sizes.against),
            None => {
                let scene = crate::builtin::scene(chapter)?;
                let lesson = (scene.render.width, scene.render.height);
                let against = self.against.as_ref().and_then(|folder| {
                    let bytes = crate::input::read_bounded(
                        &folder.join(format!("chapter-{chapter}.png")),
                        crate::input::MAX_PNG_FILE_BYTES,
                        "PNG",
                        crate::input::Links::Refuse,
                    )
                    .ok()?;
                    declared_size(&bytes).ok()
                });
                self.sizes.push(GradedSizes {
                    chapter,
                    lesson,
                    against,
                });
                (lesson, against)
            }
        };
        if (width, height) == lesson || Some((width, height)) == against {
            return Ok(());
        }
        Err(GradeError::NotAGradedSize {
            chapter,
            width,
            height,
            lesson,
        })
    }

    /// The reference for chapter `chapter` at `width` x `height`, and where
    /// it came from, for people.
    pub fn reference(
        &mut self,
        chapter: u8,
        width: u32,
        height: u32,
    ) -> Result<(Image, String), GradeError> {
        let size = format!("{width}x{height}");
        let mut why_not_against = None;
        if let Some(folder) = &self.against {
            let path = folder.join(format!("chapter-{chapter}.png"));
            why_not_against = Some(if !path.exists() {
                format!("no {}", path.display())
            } else {
                match Image::load_png(&path) {
                    Ok(image) if (image.width, image.height) == (width, height) => {
                        return Ok((image, path.display().to_string()));
                    }
                    Ok(image) => format!("{} is {}x{}", path.display(), image.width, image.height),
                    Err(error) => format!("{error:#}"),
                }
            });
        }
        let shipped = shipped_reference(chapter)?;
        if (width, height) == (shipped.width, shipped.height) {
            return Ok((
                shipped,
                format!("raylab's shipped reference snapshots/chapter-{chapter}.png"),
            ));
        }
        self.check_chapters(chapter, &shipped)?;
        let why = match why_not_against {
            Some(why) => format!("; {why}"),
            None => String::new(),
        };
        if let Some(kept) = self.rendered.iter().find(|kept| {
            kept.chapter == chapter && (kept.image.width, kept.image.height) == (width, height)
        }) {
            return Ok((kept.image.clone(), format!("{}{why}", kept.source)));
        }
        let scene = crate::builtin::scene(chapter)?;
        let settings = crate::RenderSettings {
            width,
            height,
            ..scene.render
        };
        settings
            .validate()
            .map_err(|error| GradeError::ReferenceSize {
                size: size.clone(),
                error,
            })?;
        let image: Image = crate::render_with::<R>(&scene, chapter, &settings, None)?.into();
        let source = format!(
            "built-in scene rendered at {size} by raylab's reference chapters, checked to \
             reproduce the shipped {}x{} image",
            shipped.width, shipped.height
        );
        let mut kept_bytes: usize = self.rendered.iter().map(|kept| kept.image.rgb.len()).sum();
        while kept_bytes + image.rgb.len() > RENDERED_REFERENCE_BYTES && !self.rendered.is_empty() {
            kept_bytes -= self.rendered.remove(0).image.rgb.len();
        }
        if image.rgb.len() <= RENDERED_REFERENCE_BYTES {
            self.rendered.push(RenderedReference {
                chapter,
                image: image.clone(),
                source: source.clone(),
            });
        }
        Ok((image, format!("{source}{why}")))
    }

    /// Fails with [`MODIFIED_CHAPTERS`] unless the chapters `R` render
    /// chapter `chapter`'s built-in scene at the shipped image's size
    /// exactly as `shipped`. The render of a chapter runs the functions of
    /// every chapter up to it, so this covers all the code that renders the
    /// reference.
    fn check_chapters(&mut self, chapter: u8, shipped: &Image) -> Result<(), GradeError> {
        let verdict = match self.checked.iter().find(|(c, _)| *c == chapter) {
            Some((_, verdict)) => verdict.clone(),
            None => {
                let verdict = reproduces::<R>(chapter, shipped)?;
                self.checked.push((chapter, verdict.clone()));
                verdict
            }
        };
        verdict.map_err(|why| GradeError::Modified { why })
    }
}

/// `Ok(Ok(()))` when the chapters `R` draw chapter `chapter`'s built-in
/// scene at the size of `shipped` exactly as `shipped`, `Ok(Err(why))` when
/// not.
fn reproduces<R: Chapters>(chapter: u8, shipped: &Image) -> Result<Result<(), String>, GradeError> {
    let scene = crate::builtin::scene(chapter)?;
    let settings = crate::RenderSettings {
        width: shipped.width,
        height: shipped.height,
        ..scene.render
    };
    let rendered = crate::render_with::<R>(&scene, chapter, &settings, None)?;
    if rendered.rgb == shipped.rgb {
        return Ok(Ok(()));
    }
    let differing = rendered
        .rgb
        .chunks(3)
        .zip(shipped.rgb.chunks(3))
        .filter(|(a, b)| a != b)
        .count();
    Ok(Err(format!(
        "their chapter {chapter} render at {}x{} differs from the shipped image in {differing} \
         pixels",
        shipped.width, shipped.height
    )))
}

/// Chapter `chapter`'s reference image as shipped inside raylab.
pub fn shipped_reference(chapter: u8) -> Result<Image, GradeError> {
    let info = crate::chapters::chapter(chapter).ok_or(GradeError::NoSuchChapter(chapter))?;
    Image::decode_png(info.reference_png).map_err(|error| GradeError::Shipped { chapter, error })
}
