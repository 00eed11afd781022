//! The instructor's hidden scenes (`raylab grade --code --scene FILE`):
//! each student's chapters render scenes the student never saw, and each
//! image is compared with raylab's reference chapters on the same scene.
//! A copied reference image proves nothing here: the scene is new, and
//! the image comes from the student's binary, asked by the grader to
//! render it (in the sandbox), whose answer key is sealed. Under `--fresh`
//! each scene's camera is turned as the chapters' images are, so that
//! pixels rendered in advance from a scene learnt in an earlier round do
//! not pass either.
//!
//! What comes back to the student about a hidden scene is one bit: passed
//! or not. The student's process chooses its answer, so anything the
//! outcome carried of it (a panic's text, an exit status, an image's
//! size, where its largest difference lies) is a channel through which
//! code that read the scene could write it into the report the student
//! reads.

use std::path::{Path, PathBuf};

use super::GradeError;
use crate::check::judge::{Asker, Step};
use crate::check::protocol::{Answered, Reply, Request, View};
use crate::diff::{Criteria, Image, Metrics, compare};

/// A hidden scene, loaded and checked, with its reference image.
pub struct HiddenScene {
    /// The file's name, for the report.
    pub name: String,
    pub text: String,
    pub chapter: u8,
    /// The camera turned under `--fresh`, from which `reference` is seen.
    pub view: Option<View>,
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
/// at `chapter`, each from its camera turned by `fresh` where given. A
/// scene that names an OBJ file is refused: the render runs in a sandbox
/// that sees only the scene.
pub fn load(
    paths: &[PathBuf],
    chapter: u8,
    fresh: Option<u64>,
) -> Result<Vec<HiddenScene>, GradeError> {
    let mut scenes = Vec::new();
    for (file, name, text) in texts(paths)? {
        let origin = format!("hidden scene {}", file.display());
        let mut scene = crate::Scene::parse(&text, &origin)?;
        let view = fresh.map(|seed| {
            crate::check::judge::turned_view(&scene.camera, seed, &format!("hidden scene {name}"))
        });
        if let Some(view) = &view {
            scene.camera = view.applied_to(&scene.camera);
        }
        let rendered = crate::render(&scene, chapter, &scene.render, None)?;
        scenes.push(HiddenScene {
            name,
            text,
            chapter,
            view,
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
                        .is_some_and(|extension| extension.eq_ignore_ascii_case("toml"))
                })
                .collect();
            // A folder that gives no scene would grade as if no scene were
            // asked for: every student would pass what was meant to test them.
            if inside.is_empty() {
                return Err(GradeError::HiddenScene {
                    file: path.clone(),
                    why: "the folder holds no .toml file (the scenes of its subfolders are not \
                          read: give each subfolder its own --scene)"
                        .into(),
                });
            }
            inside.sort();
            files.extend(inside);
        } else {
            files.push(path.clone());
        }
    }
    let names = distinct_names(&files)?;
    let mut texts = Vec::new();
    for (file, name) in files.into_iter().zip(names) {
        let text = crate::input::read_scene_text(&file)?;
        if !crate::Scene::obj_files(&text, Path::new("")).is_empty() {
            return Err(GradeError::HiddenScene {
                file,
                why: "it names an OBJ file; a hidden scene must be whole in itself \
                      (`mesh = { generated = N }` is fine)"
                    .into(),
            });
        }
        texts.push((file, name, text));
    }
    Ok(texts)
}

/// What tells a file from every other: its device and inode where there
/// are, else its canonical path.
fn file_identity(path: &Path) -> (u64, u64, PathBuf) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(metadata) = std::fs::metadata(path) {
            return (metadata.dev(), metadata.ino(), PathBuf::new());
        }
    }
    (0, 0, path.to_path_buf())
}

/// A name for each of `files` in the report, the gradebook's columns and
/// the merge, each told apart from the others: the file's name, or as
/// many of its folders before it as it takes (`week1/scene.toml` beside
/// `week2/scene.toml`), because scenes are scored by name and two of one
/// name would count as one. A file given twice is refused.
fn distinct_names(files: &[PathBuf]) -> Result<Vec<String>, GradeError> {
    let mut paths = Vec::new();
    let mut identities = Vec::new();
    for file in files {
        let whole = std::fs::canonicalize(file).unwrap_or_else(|_| file.clone());
        // The file itself, whatever path reaches it: a hard link too.
        let identity = file_identity(&whole);
        let again = identities.iter().position(|seen| *seen == identity);
        identities.push(identity);
        if let Some(index) = again {
            return Err(GradeError::HiddenScene {
                file: file.clone(),
                why: format!(
                    "it is the scene {} again (the same file)",
                    files[index].display()
                ),
            });
        }
        // Its components from the file's name back to the root.
        let components: Vec<String> = whole
            .components()
            .rev()
            .filter_map(|component| match component {
                std::path::Component::Normal(part) => Some(crate::text::visible_name(part)),
                _ => None,
            })
            .collect();
        paths.push((whole, components));
    }
    let name = |components: &[String], kept: usize| {
        let mut parts: Vec<&str> = components.iter().take(kept).map(String::as_str).collect();
        parts.reverse();
        parts.join("/")
    };
    let mut kept = vec![1; paths.len()];
    loop {
        let names: Vec<String> = (paths.iter().zip(&kept))
            .map(|((_, components), &kept)| name(components, kept))
            .collect();
        let mut grew = false;
        for (index, own) in names.iter().enumerate() {
            let shared = names.iter().filter(|other| *other == own).count() > 1;
            if shared && kept[index] < paths[index].1.len() {
                kept[index] += 1;
                grew = true;
            }
        }
        if !grew {
            return Ok(names);
        }
    }
}

/// What a student reads of a hidden scene that failed, however it failed:
/// which way it failed (a wrong image, none, a crash, raylab's own
/// answers, the time it took) is the student's code's choice, and would
/// tell of the scene more than the one bit pass or fail.
fn failed_detail(chapter: u8) -> String {
    format!(
        "not rendered as raylab's reference chapters render the scene at chapter {chapter} \
         (how it failed is not shown: the scene is hidden)"
    )
}

/// Renders each of `scenes` with the student's chapters, asked through
/// `asker` (the workspace's binary answering as `serve`), and compares the
/// image with the scene's reference. Before `deadline`, each scene has its
/// share of the time left: one that never ends fails alone.
pub fn grade_scenes(
    scenes: &[HiddenScene],
    asker: &mut dyn Asker,
    deadline: Option<std::time::Instant>,
) -> Vec<SceneOutcome> {
    let count = scenes.len();
    scenes
        .iter()
        .enumerate()
        .map(|(index, scene)| {
            if let Some(deadline) = deadline {
                let now = std::time::Instant::now();
                let left = deadline.saturating_duration_since(now);
                let scenes_left = u32::try_from(count - index).unwrap_or(u32::MAX);
                asker.set_deadline(Some(now + left / scenes_left));
            }
            let passed = renders_as_reference(scene, asker);
            SceneOutcome {
                name: scene.name.clone(),
                passed,
                metrics: None,
                detail: if passed {
                    format!(
                        "rendered as raylab's reference chapters render the scene at chapter {} \
                         (by how much is not shown: the scene is hidden)",
                        scene.chapter
                    )
                } else {
                    failed_detail(scene.chapter)
                },
            }
        })
        .collect()
}

/// Whether the student's render of `scene`, asked through `asker`, is the
/// reference's by [`Criteria::default`]. Whatever else the student's
/// process sends or does (a panic, an error, another answer, an exit of
/// its choosing, a reply the judge refuses, no reply in time, an answer of
/// raylab's) is a failure, told apart by nothing.
fn renders_as_reference(scene: &HiddenScene, asker: &mut dyn Asker) -> bool {
    let step = Step {
        chapter: scene.chapter,
        function: "render".into(),
        case: format!("the hidden scene {}", scene.name),
    };
    let request = Request::Render {
        scene: scene.text.clone(),
        chapter: scene.chapter,
        view: scene.view,
    };
    let image = match asker.ask(&request, &step) {
        // In a student's build an answer of raylab's reports, then panics.
        Ok(Reply::Answer { used, escaped, .. }) if !used.is_empty() || !escaped.is_empty() => {
            return false;
        }
        Ok(Reply::Answer {
            answer: Answered::Rgb { width, height, rgb },
            ..
        }) => Image { width, height, rgb },
        Ok(_) | Err(_) => return false,
    };
    compare(
        &image,
        &scene.reference,
        Criteria::default(),
        ("student", "reference"),
    )
    .is_ok_and(|comparison| comparison.passes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::Panic;
    use crate::check::judge::Ended;

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
            view: None,
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
            let outcomes = grade_scenes(std::slice::from_ref(&scene), &mut Leaking(leak), None);
            let shown = format!("{outcomes:?}");
            assert!(!shown.contains("secret_position"), "{shown}");
            assert!(outcomes.iter().all(|outcome| !outcome.passed), "{shown}");
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
            None,
        );
        let shown = format!("{ran:?}");
        assert!(!shown.contains("secret_position"), "{shown}");
        // The right image, but made with raylab's answers: a failure.
        assert!(!ran[0].passed, "{shown}");
    }

    /// Answers every render with a fixed outcome, whatever the scene.
    struct Fixed(fn() -> Result<Reply, Ended>);
    impl Asker for Fixed {
        fn ask(&mut self, _: &Request, _: &Step) -> Result<Reply, Ended> {
            (self.0)()
        }
    }

    fn answered(answer: Answered) -> Result<Reply, Ended> {
        Ok(Reply::Answer {
            answer,
            used: Vec::new(),
            escaped: Vec::new(),
        })
    }

    /// What the student's process chooses (its exit status, its image's
    /// size, where its image differs, a crash, raylab's own answers, the
    /// time it takes) comes back as nothing but a failure, each worded as
    /// the others: each was a way to write a hidden scene's numbers into
    /// the report, or to tell it a bit more than pass or fail.
    #[test]
    fn nothing_the_process_chooses_comes_back_but_pass_or_fail() {
        let scene = HiddenScene {
            name: "hidden.toml".into(),
            text: String::new(),
            chapter: 4,
            view: None,
            reference: Image {
                width: 2,
                height: 1,
                rgb: vec![10; 6],
            },
        };
        let choices: [fn() -> Result<Reply, Ended>; 8] = [
            || Err(Ended::Died("exited with status 49".into())),
            || Err(Ended::TimedOut),
            || {
                Ok(Reply::Answer {
                    answer: Answered::Rgb {
                        width: 2,
                        height: 1,
                        rgb: vec![10; 6],
                    },
                    used: vec!["nearest_hit".into()],
                    escaped: Vec::new(),
                })
            },
            || {
                answered(Answered::Panicked(Panic {
                    message: "stack overflow".into(),
                    location: None,
                    file: None,
                }))
            },
            || Err(Ended::Refused("a reply of 4949 bytes".into())),
            || answered(Answered::Error("49".into())),
            || {
                answered(Answered::Rgb {
                    width: 49,
                    height: 1,
                    rgb: vec![0; 49 * 3],
                })
            },
            // The second pixel 49 levels off: its place and size chosen.
            || {
                answered(Answered::Rgb {
                    width: 2,
                    height: 1,
                    rgb: vec![10, 10, 10, 59, 59, 59],
                })
            },
        ];
        let mut details = Vec::new();
        for choice in choices {
            let outcomes = grade_scenes(std::slice::from_ref(&scene), &mut Fixed(choice), None);
            let shown = format!("{outcomes:?}");
            assert!(!shown.contains("49"), "{shown}");
            assert!(
                outcomes.iter().all(|o| !o.passed && o.metrics.is_none()),
                "{shown}"
            );
            details.push(outcomes[0].detail.clone());
        }
        details.dedup();
        assert_eq!(details.len(), 1, "{details:#?}");
        let same = grade_scenes(
            std::slice::from_ref(&scene),
            &mut Fixed(|| {
                answered(Answered::Rgb {
                    width: 2,
                    height: 1,
                    rgb: vec![10; 6],
                })
            }),
            None,
        );
        assert!(same[0].passed && same[0].metrics.is_none(), "{same:?}");
    }

    /// Answers a scene whose text is `loop` only once its deadline has
    /// passed (as a process that never ends, killed at its deadline), and
    /// every other with the scene's reference.
    struct LoopsOnOne {
        reference: Image,
        deadline: Option<std::time::Instant>,
    }
    impl Asker for LoopsOnOne {
        fn ask(&mut self, request: &Request, _: &Step) -> Result<Reply, Ended> {
            let Request::Render { scene, .. } = request else {
                return Err(Ended::Refused("not a render".into()));
            };
            let Some(deadline) = self.deadline else {
                return Err(Ended::Refused("no deadline".into()));
            };
            if scene == "loop" || std::time::Instant::now() >= deadline {
                std::thread::sleep(deadline.saturating_duration_since(std::time::Instant::now()));
                return Err(Ended::TimedOut);
            }
            answered(Answered::Rgb {
                width: self.reference.width,
                height: self.reference.height,
                rgb: self.reference.rgb.clone(),
            })
        }

        fn set_deadline(&mut self, deadline: Option<std::time::Instant>) {
            self.deadline = deadline;
        }
    }

    /// A scene that never ends fails alone: each scene has its share of the
    /// time left, and the scenes after it still pass.
    /// Pass 16 of issue 41: two hidden scenes of one file name were one
    /// column of the gradebook, worth the point if either passed.
    #[test]
    fn scenes_of_one_file_name_are_told_apart_and_a_scene_given_twice_is_refused() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let scene = crate::builtin::scene_text(1).expect("chapter 1's scene");
        for week in ["week1", "week2", "other/week1"] {
            std::fs::create_dir_all(dir.path().join(week)).expect("a folder");
            std::fs::write(dir.path().join(week).join("scene.toml"), scene).expect("written");
        }
        std::fs::write(dir.path().join("alone.toml"), scene).expect("written");
        let files = ["week1", "week2", "other/week1", "."].map(|folder| {
            dir.path().join(folder).join(if folder == "." {
                "alone.toml"
            } else {
                "scene.toml"
            })
        });
        let names: Vec<String> = texts(&files)
            .expect("read")
            .into_iter()
            .map(|(_, name, _)| name)
            .collect();
        assert_eq!(
            names,
            [
                format!(
                    "{}/week1/scene.toml",
                    dir.path()
                        .file_name()
                        .and_then(|name| name.to_str())
                        .unwrap_or_default()
                ),
                "week2/scene.toml".to_string(),
                "other/week1/scene.toml".to_string(),
                "alone.toml".to_string(),
            ]
        );
        let twice = [
            files[1].clone(),
            dir.path().join("week2/../week2/scene.toml"),
        ];
        let error = texts(&twice).unwrap_err().to_string();
        assert!(error.contains("again"), "{error}");
    }

    /// Pass 17 of issue 41: a `--scene` folder whose scenes were in
    /// subfolders (or named `.TOML`, or none) gave no scene, and every
    /// student passed; a hard link to a scene counted it twice.
    #[test]
    fn a_scene_folder_that_gives_no_scene_and_a_hard_link_are_refused() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let scene = crate::builtin::scene_text(1).expect("chapter 1's scene");
        let hidden = dir.path().join("hidden");
        std::fs::create_dir_all(hidden.join("week1")).expect("a folder");
        std::fs::write(hidden.join("week1/scene.toml"), scene).expect("written");
        let error = texts(std::slice::from_ref(&hidden))
            .unwrap_err()
            .to_string();
        assert!(error.contains("holds no .toml file"), "{error}");
        std::fs::write(hidden.join("Week2.TOML"), scene).expect("written");
        let read = texts(std::slice::from_ref(&hidden)).expect("read");
        assert_eq!(read.len(), 1);
        assert_eq!(read[0].1, "Week2.TOML");
        std::fs::hard_link(
            hidden.join("week1/scene.toml"),
            dir.path().join("linked.toml"),
        )
        .expect("a hard link");
        let twice = [
            hidden.join("week1/scene.toml"),
            dir.path().join("linked.toml"),
        ];
        let error = texts(&twice).unwrap_err().to_string();
        assert!(error.contains("again"), "{error}");
    }

    #[test]
    fn a_scene_that_never_ends_fails_alone() {
        let reference = Image {
            width: 1,
            height: 1,
            rgb: vec![7; 3],
        };
        let scene = |name: &str, text: &str| HiddenScene {
            name: name.into(),
            text: text.into(),
            chapter: 4,
            view: None,
            reference: reference.clone(),
        };
        let scenes = [
            scene("a.toml", "loop"),
            scene("b.toml", ""),
            scene("c.toml", ""),
        ];
        let mut asker = LoopsOnOne {
            reference: reference.clone(),
            deadline: None,
        };
        let deadline = std::time::Instant::now() + std::time::Duration::from_millis(600);
        let outcomes = grade_scenes(&scenes, &mut asker, Some(deadline));
        let passed: Vec<bool> = outcomes.iter().map(|outcome| outcome.passed).collect();
        assert_eq!(passed, [false, true, true], "{outcomes:?}");
    }

    /// Under `--fresh` a hidden scene is seen from a turned camera: its
    /// pixels rendered in advance from the scene as written fail.
    #[test]
    fn under_fresh_a_hidden_scene_rendered_in_advance_fails() {
        let folder = tempfile::tempdir().expect("a folder");
        let file = folder.path().join("hidden.toml");
        let text = crate::builtin::scene_text(3).expect("chapter 3's scene");
        let small = text
            .replace("width = 640", "width = 48")
            .replace("height = 480", "height = 36");
        assert_ne!(small, text, "chapter 3's scene sets its size");
        std::fs::write(&file, small).expect("write");
        let plain = load(std::slice::from_ref(&file), 3, None).expect("loads");
        let turned = load(std::slice::from_ref(&file), 3, Some(5)).expect("loads");
        assert!(plain[0].view.is_none());
        let view = turned[0].view.expect("a turned view");
        let again = load(std::slice::from_ref(&file), 3, Some(5)).expect("loads");
        assert_eq!(again[0].view.map(|v| v.position), Some(view.position));
        struct Replay(Image);
        impl Asker for Replay {
            fn ask(&mut self, _: &Request, _: &Step) -> Result<Reply, Ended> {
                answered(Answered::Rgb {
                    width: self.0.width,
                    height: self.0.height,
                    rgb: self.0.rgb.clone(),
                })
            }
        }
        let rendered_in_advance = plain[0].reference.clone();
        let without = grade_scenes(&plain, &mut Replay(rendered_in_advance.clone()), None);
        assert!(without[0].passed, "{without:?}");
        let with = grade_scenes(&turned, &mut Replay(rendered_in_advance), None);
        assert!(!with[0].passed, "{with:?}");
        // The turned view's own render passes.
        let honest = grade_scenes(&turned, &mut Replay(turned[0].reference.clone()), None);
        assert!(honest[0].passed, "{honest:?}");
    }
}
