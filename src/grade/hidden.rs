//! The instructor's hidden scenes (`raylab grade --code --scene FILE`):
//! each student's chapters render scenes the student never saw, and each
//! image is compared with raylab's reference chapters on the same scene.
//! A copied reference image proves nothing here: the scene is new, and
//! the image comes from the student's binary, asked by the grader to
//! render it (in the sandbox), whose answer key is sealed.

use std::path::{Path, PathBuf};

use super::GradeError;
use crate::check::judge::{Asker, Ended, Step};
use crate::check::protocol::{Answered, Reply, Request};
use crate::diff::{Criteria, Image, Metrics, compare};

/// A hidden scene, loaded and checked, with its reference image.
pub struct HiddenScene {
    /// The file's name, for the report.
    pub name: String,
    pub text: String,
    pub chapter: u8,
    pub reference: Image,
}

/// How one student's render of a hidden scene compared.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SceneOutcome {
    pub name: String,
    pub passed: bool,
    pub metrics: Option<Metrics>,
    /// Why there is no image, or the reference it was compared with.
    pub detail: String,
}

/// The scenes of `paths` (files, or folders whose `*.toml` files are taken
/// in the order of their names), rendered by raylab's reference chapters
/// at `chapter`. A scene that names an OBJ file is refused: the render
/// runs in a sandbox that sees only the scene.
pub fn load(paths: &[PathBuf], chapter: u8) -> Result<Vec<HiddenScene>, GradeError> {
    let mut scenes = Vec::new();
    for (file, name, text) in texts(paths)? {
        let origin = format!("hidden scene {}", file.display());
        let scene = crate::Scene::parse(&text, &origin)?;
        let rendered = crate::render(&scene, chapter, &scene.render, None)?;
        scenes.push(HiddenScene {
            name,
            text,
            chapter,
            reference: rendered.into(),
        });
    }
    Ok(scenes)
}

/// The files of `paths` as [`load`] takes them, each with its name for the
/// report and its text, read and refused as there, but not rendered.
pub fn texts(paths: &[PathBuf]) -> Result<Vec<(PathBuf, String, String)>, GradeError> {
    let mut files = Vec::new();
    for path in paths {
        if path.is_dir() {
            let mut inside: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(super::folder_error(path))?
                .flatten()
                .map(|entry| entry.path())
                .filter(|file| {
                    file.extension()
                        .is_some_and(|extension| extension == "toml")
                })
                .collect();
            inside.sort();
            files.extend(inside);
        } else {
            files.push(path.clone());
        }
    }
    let mut texts = Vec::new();
    for file in files {
        let text = crate::input::read_scene_text(&file)?;
        if !crate::Scene::obj_files(&text, Path::new("")).is_empty() {
            return Err(GradeError::HiddenScene {
                file,
                why: "it names an OBJ file; a hidden scene must be whole in itself \
                      (`mesh = { generated = N }` is fine)"
                    .into(),
            });
        }
        let name = file
            .file_name()
            .map(crate::text::visible_name)
            .unwrap_or_else(|| file.display().to_string());
        texts.push((file, name, text));
    }
    Ok(texts)
}

/// Why a hidden scene's failure says no more.
const WITHHELD: &str = "its text is not shown: the scene is hidden";

/// Renders each of `scenes` with the student's chapters, asked through
/// `asker` (the workspace's binary answering as `serve`), and compares the
/// image with the scene's reference.
pub fn grade_scenes(scenes: &[HiddenScene], asker: &mut dyn Asker) -> Vec<SceneOutcome> {
    scenes
        .iter()
        .map(|scene| {
            let failed = |detail: String| SceneOutcome {
                name: scene.name.clone(),
                passed: false,
                metrics: None,
                detail,
            };
            let step = Step {
                chapter: scene.chapter,
                function: "render".into(),
                case: format!("the hidden scene {}", scene.name),
            };
            let request = Request::Render {
                scene: scene.text.clone(),
                chapter: scene.chapter,
            };
            let image = match asker.ask(&request, &step) {
                // Reported whatever came of them: in a student's build an
                // answer of raylab's reports, then panics.
                Ok(Reply::Answer { used, escaped, .. })
                    if !used.is_empty() || !escaped.is_empty() =>
                {
                    return failed(
                        "the render ran raylab's own answers instead of the student's".into(),
                    );
                }
                Ok(Reply::Answer {
                    answer: Answered::Rgb { width, height, rgb },
                    ..
                }) => Image { width, height, rgb },
                // What the student's process says (a panic's message, an
                // error's text, the names of the answers it ran) is never
                // shown: code that read the hidden scene could write it
                // there, and the report is the student's to read.
                Ok(Reply::Answer {
                    answer: Answered::Panicked(_),
                    ..
                }) => return failed(format!("the render failed: a panic ({WITHHELD})")),
                Ok(Reply::Answer {
                    answer: Answered::Error(_),
                    ..
                }) => return failed(format!("the render failed: an error ({WITHHELD})")),
                Ok(_) => return failed("the render failed: no image came back".into()),
                Err(Ended::TimedOut) => return failed("timed out".into()),
                Err(Ended::Died(how)) => {
                    return failed(format!("the render failed: the process {how}"));
                }
                Err(Ended::Refused(why)) => return failed(format!("the render failed: {why}")),
            };
            match compare(
                &image,
                &scene.reference,
                Criteria::default(),
                ("student", "reference"),
            ) {
                Ok(comparison) => SceneOutcome {
                    name: scene.name.clone(),
                    passed: comparison.passes(),
                    metrics: Some(comparison.metrics),
                    detail: format!(
                        "compared with raylab's reference chapters on the scene at chapter {}",
                        scene.chapter
                    ),
                },
                Err(error) => failed(format!("{error:#}")),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::Panic;

    /// Answers every render with what `reply` makes of the scene's text.
    struct Leaking(fn(&str) -> Answered);
    impl Asker for Leaking {
        fn ask(&mut self, request: &Request, _: &Step) -> Result<Reply, Ended> {
            let Request::Render { scene, .. } = request else {
                return Err(Ended::Refused("not a render".into()));
            };
            Ok(Reply::Answer {
                answer: (self.0)(scene),
                used: vec![scene.clone()],
                escaped: Vec::new(),
            })
        }
    }

    /// Whatever the student's process sends back about a hidden scene, the
    /// outcome, which the student reads, does not carry the scene's text.
    #[test]
    fn a_hidden_scene_never_comes_back_in_what_the_student_reads() {
        let scene = HiddenScene {
            name: "hidden.toml".into(),
            text: "[camera]\nsecret_position = [1.5, 2.5, 3.5]\n".into(),
            chapter: 4,
            reference: Image {
                width: 1,
                height: 1,
                rgb: vec![0; 3],
            },
        };
        let leaks: [fn(&str) -> Answered; 2] = [
            |scene| {
                Answered::Panicked(Panic {
                    message: scene.to_string(),
                    location: Some(scene.to_string()),
                    file: None,
                })
            },
            |scene| Answered::Error(scene.to_string()),
        ];
        for leak in leaks {
            let outcomes = grade_scenes(std::slice::from_ref(&scene), &mut Leaking(leak));
            let shown = format!("{outcomes:?}");
            assert!(!shown.contains("secret_position"), "{shown}");
            assert!(outcomes.iter().all(|outcome| !outcome.passed), "{shown}");
            // Answers reported, then a panic (a student's build has no
            // answer of raylab's to run): named as answers, not as a panic.
            assert!(shown.contains("raylab's own answers"), "{shown}");
        }
        // An image, but with raylab's answers reported: their names are the
        // student's text too.
        let ran = grade_scenes(
            std::slice::from_ref(&scene),
            &mut Leaking(|_| Answered::Rgb {
                width: 1,
                height: 1,
                rgb: vec![0; 3],
            }),
        );
        let shown = format!("{ran:?}");
        assert!(!shown.contains("secret_position"), "{shown}");
        assert!(shown.contains("raylab's own answers"), "{shown}");
    }
}
