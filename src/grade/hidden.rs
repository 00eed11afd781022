//! The instructor's hidden scenes (`raylab grade --code --scene FILE`):
//! each student's chapters render scenes the student never saw, and each
//! image is compared with raylab's reference chapters on the same scene.
//! A copied reference image proves nothing here: the scene is new, and
//! the image comes from a render the grader runs (in the sandbox) with the
//! student's binary, whose answer key is sealed (a chapter that calls
//! raylab's own code writes no image).

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::GradeError;
use super::code::{Ran, run_binary};
use super::sandbox::Sandbox;
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
    let mut scenes = Vec::new();
    for file in files {
        let text = crate::input::read_scene_text(&file)?;
        let origin = format!("hidden scene {}", file.display());
        if !crate::Scene::obj_files(&text, Path::new("")).is_empty() {
            return Err(GradeError::HiddenScene {
                file,
                why: "it names an OBJ file; a hidden scene must be whole in itself \
                      (`mesh = { generated = N }` is fine)"
                    .into(),
            });
        }
        let scene = crate::Scene::parse(&text, &origin)?;
        let rendered = crate::render(&scene, chapter, &scene.render, None)?;
        let name = file
            .file_name()
            .map(crate::text::visible_name)
            .unwrap_or_else(|| file.display().to_string());
        scenes.push(HiddenScene {
            name,
            text,
            chapter,
            reference: rendered.into(),
        });
    }
    Ok(scenes)
}

/// Renders each of `scenes` with the workspace's binary (`render --scene
/// S --chapter N -o OUT`, inside `sandbox`, each within `timeout`) and
/// compares the image with the scene's reference.
pub fn grade_scenes(
    workspace: &Path,
    scenes: &[HiddenScene],
    timeout: Duration,
    sandbox: Option<&Sandbox>,
    criteria: Criteria,
) -> Result<Vec<SceneOutcome>, GradeError> {
    let mut outcomes = Vec::new();
    for scene in scenes {
        let folder = tempfile::Builder::new()
            .prefix("raylab-hidden-")
            .tempdir()
            .map_err(|error| GradeError::Run {
                cargo: "a temporary folder".into(),
                workspace: workspace.to_path_buf(),
                error,
            })?;
        let scene_path = folder.path().join("scene.toml");
        let image_path = folder.path().join("render.png");
        std::fs::write(&scene_path, &scene.text).map_err(GradeError::Staging)?;
        let args = [
            "render".into(),
            "--scene".into(),
            scene_path.clone().into_os_string(),
            "--chapter".into(),
            scene.chapter.to_string().into(),
            "-o".into(),
            image_path.clone().into_os_string(),
        ];
        let Ran {
            exit,
            timed_out,
            stderr,
            ..
        } = run_binary(workspace, &args, Some(folder.path()), timeout, sandbox)?;
        let failed = |detail: String| SceneOutcome {
            name: scene.name.clone(),
            passed: false,
            metrics: None,
            detail,
        };
        if timed_out {
            outcomes.push(failed(format!("timed out after {} s", timeout.as_secs())));
            continue;
        }
        if !exit.is_some_and(|status| status.success()) {
            outcomes.push(failed(format!(
                "the render failed: {}",
                super::code::last_lines(&stderr, 5)
            )));
            continue;
        }
        let image = crate::input::read_bounded(
            &image_path,
            crate::input::MAX_PNG_FILE_BYTES,
            "PNG",
            crate::input::Links::Refuse,
        )
        .map_err(GradeError::from)
        .and_then(|bytes| Image::decode_png(&bytes).map_err(GradeError::from));
        let outcome = match image {
            Ok(image) => {
                match compare(&image, &scene.reference, criteria, ("student", "reference")) {
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
            }
            Err(error) => failed(format!("no image: {error:#}")),
        };
        outcomes.push(outcome);
    }
    Ok(outcomes)
}
