//! The browser page's entry into the renderer (web/, built to WebAssembly).
//!
//! The page talks to the chapters through one function, [`call`]: a JSON
//! request in, a JSON answer out (and, for a render, the pixels after it).
//! It is plain Rust, so the tests run it natively; [`web_exports!`](crate::web_exports) turns
//! it into the few C functions the page's hand-written loader calls. Every
//! answer is built from the same functions as the command line's:
//! [`crate::render::render_rows`] for pixels, [`crate::ray_tree`] for a
//! pixel's rays, [`Scene::parse`] for the scene's errors. A worker renders
//! the rows it is given, so any split of the image between workers puts the
//! command line's image back together.
//!
//! Requests (`op` names the operation):
//! - `{"op": "chapters"}`: every chapter's number, title, what it adds and
//!   its built-in scene's TOML, the chapter the page opens at, and how the
//!   same chapters run on the command line.
//! - `{"op": "prepare", "job": JOB}`: the job's size, samples and the
//!   effects its stage simulates, or the scene's error with its line and
//!   column.
//! - `{"op": "render", "job": JOB, "rows": [first, end]}`: those rows.
//! - `{"op": "trace", "job": JOB, "pixel": [x, y]}`: the pixel's ray tree,
//!   as `raylab trace --json` prints it.
//!
//! A JOB is `{"chapter": N, "scene": TOML or null (the built-in scene),
//! "width", "height", "samples", "depth", "epsilon", "without"}`, each setting
//! optional and meaning what the same option of `raylab render` means. A job
//! whose rays could go beyond the render's budgets is refused, as `raylab
//! render` refuses it ([`crate::render::RayEstimate`]), and so is one of
//! chapter 14 with more than [`PAGE_LIGHT_PATHS`] light paths.

use crate::course::Chapters;
use crate::scene::{OffsetRule, RenderSettings, Scene};

/// What the page asks.
#[derive(Debug, serde::Deserialize)]
#[serde(tag = "op", rename_all = "lowercase", deny_unknown_fields)]
enum Request {
    Chapters,
    Prepare { job: Job },
    Render { job: Job, rows: [u32; 2] },
    Trace { job: Job, pixel: [u32; 2] },
}

/// A scene at a chapter's stage with the page's settings.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Job {
    chapter: u8,
    scene: Option<String>,
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
    depth: Option<u32>,
    /// A fixed offset along the ray, as `raylab render --epsilon`.
    epsilon: Option<f32>,
    /// Effects to leave out, as `raylab render --without`.
    without: Option<Vec<String>>,
}

/// Why a request has no answer. The page shows the message; a scene's
/// error also gives the line and column it names, to mark in the editor.
#[derive(Debug, thiserror::Error)]
pub enum WebError {
    #[error("the page sent a request raylab does not understand: {0}")]
    Request(String),
    #[error("{0}")]
    Scene(#[from] crate::scene::SceneError),
    #[error("{0}")]
    Render(#[from] crate::render::RenderError),
    #[error("invalid render settings: {0}")]
    Settings(crate::scene::SettingsError),
    #[error(
        "pixel {x},{y} cast {rays} rays, more than the {MAX_SHOWN_RAYS} the page draws: \
         lower the samples or the depth, or run raylab trace"
    )]
    TooManyRays { rays: usize, x: u32, y: u32 },
    #[error(
        "{paths} light paths ({width}x{height} pixels at light_paths = {per_pixel}), more than \
         the {PAGE_LIGHT_PATHS} the page traces: chapter 14's light lands anywhere in the image, \
         so every worker traces all of them for any rows it renders; lower the width or \
         light_paths, or run raylab render"
    )]
    LightPaths {
        paths: u64,
        width: u32,
        height: u32,
        per_pixel: u32,
    },
    #[error("pixel {x},{y} is outside the {width}x{height} image")]
    Pixel {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
}

impl WebError {
    /// The line and column (from 1) a scene's syntax error names.
    pub fn location(&self) -> Option<(usize, usize)> {
        let WebError::Scene(error) = self else {
            return None;
        };
        let message = error.to_string();
        let at = message.find("line ")?;
        let mut numbers = message[at + "line ".len()..]
            .splitn(2, ", column ")
            .map(|part| part.split(|c: char| !c.is_ascii_digit()).next());
        let line = numbers.next()??.parse().ok()?;
        let column = numbers.next()??.parse().ok()?;
        Some((line, column))
    }
}

/// An answer: JSON for the page, then the bytes of a render's rows.
#[derive(Debug, Default)]
pub struct Answer {
    pub json: serde_json::Value,
    pub pixels: Vec<u8>,
}

impl Answer {
    /// The answer as the page reads it: the JSON's length (4 bytes, little
    /// endian), the JSON, then the pixels.
    pub fn into_bytes(self) -> Vec<u8> {
        let json = self.json.to_string().into_bytes();
        let length = u32::try_from(json.len()).unwrap_or(u32::MAX);
        let mut bytes = Vec::with_capacity(4 + json.len() + self.pixels.len());
        bytes.extend_from_slice(&length.to_le_bytes());
        bytes.extend_from_slice(&json);
        bytes.extend_from_slice(&self.pixels);
        bytes
    }
}

/// Answers one request from the page with the chapters `C`; an error is an
/// answer too: `{"error": message, "line", "column"}`.
pub fn call<C: Chapters>(request: &[u8]) -> Answer {
    answer::<C>(request).unwrap_or_else(|error| Answer {
        json: serde_json::json!({
            "error": error.to_string(),
            "line": error.location().map(|(line, _)| line),
            "column": error.location().map(|(_, column)| column),
        }),
        pixels: Vec::new(),
    })
}

fn answer<C: Chapters>(request: &[u8]) -> Result<Answer, WebError> {
    let request: Request =
        serde_json::from_slice(request).map_err(|error| WebError::Request(error.to_string()))?;
    match request {
        Request::Chapters => Ok(Answer {
            // raylab's own chapters open at chapter 8 (glass, a reflection
            // and a refraction to click on); a student's at chapter 1.
            json: {
                let own = std::any::TypeId::of::<C>() == std::any::TypeId::of::<crate::Reference>();
                serde_json::json!({
                    "chapters": chapters(),
                    "start": if own { 8 } else { 1 },
                    // How the same chapters run on the command line: a
                    // workspace's are its own binary, and an installed
                    // `raylab` refuses to run inside a workspace.
                    "command": if own { "raylab" } else { "cargo run --release --" },
                })
            },
            pixels: Vec::new(),
        }),
        Request::Prepare { job } => {
            let (scene, settings) = job.resolve()?;
            let stage = crate::Stage::<C>::with_chapters(&scene, job.chapter, settings)?;
            let stage_effects = crate::effects::Effects::for_chapter(job.chapter);
            Ok(Answer {
                json: serde_json::json!({
                    "width": settings.width,
                    "height": settings.height,
                    "samples": stage.samples(),
                    "settings": {
                        "samples": settings.samples,
                        "depth": settings.max_depth,
                        "epsilon": (settings.ray_offset == OffsetRule::Fixed).then_some(settings.fixed_epsilon),
                    },
                    "effects": stage.effects.names(),
                    // What the page offers to switch off: the chapter's
                    // stage, before the job's own `without`.
                    "switchable": crate::effects::Effects::for_chapter(job.chapter).switchable(),
                    "without": settings.without.names(),
                    // Of those, the ones the stage keeps (leaving one out
                    // leaves out what is built on it).
                    "on": crate::effects::Effects::for_chapter(job.chapter)
                        .without(settings.without)
                        .switchable(),
                    // Which sliders change the image at this stage, so
                    // the page shows only those: as `raylab render` warns
                    // of an option its chapter does not use.
                    "uses": {
                        "samples": stage_effects.antialiasing || stage_effects.path_tracing,
                        "depth": stage_effects.reflection
                            || stage_effects.refraction
                            || stage_effects.path_tracing,
                        "epsilon": stage_effects.shadows,
                    },
                    "objects": scene.len(),
                    "lights": scene.lights.len(),
                }),
                pixels: Vec::new(),
            })
        }
        Request::Render {
            job,
            rows: [first, end],
        } => {
            let (rgb, counts) = render_cached::<C>(&job, first..end)?;
            let pixels = rgb
                .chunks_exact(3)
                .flat_map(|pixel| [pixel[0], pixel[1], pixel[2], 255])
                .collect();
            Ok(Answer {
                json: serde_json::json!({
                    "rows": [first, end],
                    "rays": rays_json(&counts),
                }),
                pixels,
            })
        }
        Request::Trace { job, pixel: [x, y] } => {
            let (scene, settings) = job.resolve()?;
            let stage = crate::Stage::<C>::with_chapters(&scene, job.chapter, settings)?;
            let traced = crate::ray_tree::trace_pixel(&stage, (x, y)).ok_or(WebError::Pixel {
                x,
                y,
                width: settings.width,
                height: settings.height,
            })?;
            let rays: usize = traced.samples.iter().map(count_rays).sum();
            if rays > MAX_SHOWN_RAYS || traced.truncated {
                return Err(WebError::TooManyRays { rays, x, y });
            }
            let mut json = traced.to_json(job.chapter, None);
            if let Some(samples) = json["samples"].as_array_mut() {
                for (sample, root) in samples.iter_mut().zip(&traced.samples) {
                    add_screen(stage.camera(), root, &mut sample["ray"]);
                }
            }
            Ok(Answer {
                json,
                pixels: Vec::new(),
            })
        }
    }
}

/// The most light paths (chapter 14) a page's job may trace: each of the
/// page's workers traces all of them, whatever rows it renders (where a
/// path's light lands is known only once it is traced), so a job of 4096x4096
/// pixels would trace a billion of them for two rows. 2^26 (67 million)
/// allows chapter 14's scene at the page's widest (800 pixels, at 64 paths a
/// pixel, 41 million).
pub const PAGE_LIGHT_PATHS: u64 = 1 << 26;

/// The most rays of one pixel the page is sent: a table of 20,000 rows is
/// already more than anyone reads, and each ray is about half a kilobyte
/// of JSON (a glass pixel at depth 16 and 64 samples could cast millions).
pub const MAX_SHOWN_RAYS: usize = 20_000;

/// The `"rays"` of a render answer: the count of each kind by its name, as
/// `raylab render --json` has them too, and the page's two other counters.
pub(crate) fn rays_json(counts: &crate::RayCounts) -> serde_json::Value {
    let mut json = counts.by_kind_json();
    json.insert(
        "implicit_evaluations".into(),
        counts.implicit_evaluations.into(),
    );
    json.insert(
        "non_finite_samples".into(),
        counts.non_finite_samples.into(),
    );
    json.into()
}

fn count_rays(ray: &crate::ray_tree::TracedRay) -> usize {
    1 + ray.children.iter().map(count_rays).sum::<usize>()
}

/// Adds to each ray of the trace's JSON where it runs in the image:
/// `"screen": [[x, y], [x, y]]` from its origin to what it met (a miss runs
/// toward its vanishing point), cut where it passes behind the camera, or
/// `null` where nothing of it is in front.
fn add_screen(
    camera: &crate::camera::Camera,
    ray: &crate::ray_tree::TracedRay,
    json: &mut serde_json::Value,
) {
    let start = ray.ray.origin;
    let end = match (&ray.hit, ray.t_max.is_finite()) {
        (Some(hit), _) => ray.ray.at(hit.t),
        (None, true) => ray.ray.at(ray.t_max),
        // Far enough that the line ends within a pixel of where the
        // direction vanishes, for any scene of sensible size.
        (None, false) => start + ray.ray.dir.normalize_or_zero() * 1e4 * (1.0 + start.length()),
    };
    json["screen"] = screen_segment(camera, start, end)
        .map_or(serde_json::Value::Null, |[a, b]| serde_json::json!([a, b]));
    if let Some(children) = json["children"].as_array_mut() {
        for (child_json, child) in children.iter_mut().zip(&ray.children) {
            add_screen(camera, child, child_json);
        }
    }
}

/// The segment from `start` to `end` in the image, in pixels, its part
/// behind the camera cut off.
fn screen_segment(
    camera: &crate::camera::Camera,
    start: crate::Vec3,
    end: crate::Vec3,
) -> Option<[[f32; 2]; 2]> {
    // A plane just in front of the camera: a camera ray starts on it.
    const NEAR: f32 = 1e-3;
    let (depth_start, depth_end) = (camera.depth(start), camera.depth(end));
    if !(depth_start >= NEAR || depth_end >= NEAR) {
        return None;
    }
    let cut = |behind: crate::Vec3, depth_behind: f32, front: crate::Vec3, depth_front: f32| {
        behind + (front - behind) * ((NEAR - depth_behind) / (depth_front - depth_behind))
    };
    let (start, end) = match (depth_start >= NEAR, depth_end >= NEAR) {
        (true, true) => (start, end),
        (false, _) => (cut(start, depth_start, end, depth_end), end),
        (_, false) => (start, cut(end, depth_end, start, depth_start)),
    };
    let (a, b) = (camera.project(start)?, camera.project(end)?);
    Some([[a.0, a.1], [b.0, b.1]])
}

/// A job prepared once: a worker renders many slices of one image, and a
/// stage costs a scene parse and, at chapter 11, a tree; built again for
/// each slice of 4 rows, chapter 11's mesh makes the page 30 times slower
/// than the command line.
struct Prepared {
    key: String,
    /// Borrows `*scene`: dropped first.
    renderer: std::mem::ManuallyDrop<Box<dyn crate::render::RowRenderer>>,
    scene: *mut Scene,
}

impl Drop for Prepared {
    fn drop(&mut self) {
        // SAFETY: the renderer, which borrows the scene, is dropped first
        // and never used again; the scene came from `Box::into_raw` and
        // nothing else holds it.
        unsafe {
            std::mem::ManuallyDrop::drop(&mut self.renderer);
            drop(Box::from_raw(self.scene));
        }
    }
}

thread_local! {
    static PREPARED: std::cell::RefCell<Option<Prepared>> = const { std::cell::RefCell::new(None) };
}

/// [`crate::render::render_rows`] for `job`, with the stage of the last job
/// kept while the jobs are the same.
fn render_cached<C: Chapters>(
    job: &Job,
    rows: std::ops::Range<u32>,
) -> Result<(Vec<u8>, crate::RayCounts), WebError> {
    let key = format!("{}{job:?}", std::any::type_name::<C>());
    PREPARED.with(|cell| {
        let mut slot = cell.borrow_mut();
        if slot.as_ref().is_some_and(|prepared| prepared.key != key) {
            // The old stage goes before the new scene is parsed: one scene
            // in memory at a time.
            *slot = None;
        }
        let prepared = match &mut *slot {
            Some(prepared) => prepared,
            empty => empty.insert(prepare::<C>(job, key)?),
        };
        Ok(prepared.renderer.render_rows(rows)?)
    })
}

fn prepare<C: Chapters>(job: &Job, key: String) -> Result<Prepared, WebError> {
    let (scene, settings) = job.resolve()?;
    let scene = Box::into_raw(Box::new(scene));
    // SAFETY: the scene lives until `Prepared` is dropped, which drops the
    // renderer first; it is never moved or changed.
    match crate::render::row_renderer::<C>(unsafe { &*scene }, job.chapter, &settings) {
        Ok(renderer) => Ok(Prepared {
            key,
            renderer: std::mem::ManuallyDrop::new(renderer),
            scene,
        }),
        Err(error) => {
            // SAFETY: from `Box::into_raw` above, borrowed by nothing now.
            drop(unsafe { Box::from_raw(scene) });
            Err(error.into())
        }
    }
}

fn chapters() -> serde_json::Value {
    let chapters: Vec<_> = crate::chapters::CHAPTERS
        .iter()
        .map(|info| {
            serde_json::json!({
                "number": info.number,
                "title": info.title,
                "adds": info.adds,
                "module": info.module(),
                "scene": info.scene,
            })
        })
        .collect();
    serde_json::Value::Array(chapters)
}

impl Job {
    /// The scene and the settings the job names, checked.
    fn resolve(&self) -> Result<(Scene, RenderSettings), WebError> {
        let scene = match &self.scene {
            Some(text) => Scene::parse(text, "the scene")?,
            None => crate::builtin::scene(self.chapter)?,
        };
        let base = scene.render;
        let settings = RenderSettings {
            width: self.width.unwrap_or(base.width),
            height: self.height.unwrap_or(base.height),
            samples: self.samples.unwrap_or(base.samples),
            max_depth: self.depth.unwrap_or(base.max_depth),
            ray_offset: if self.epsilon.is_some() {
                OffsetRule::Fixed
            } else {
                base.ray_offset
            },
            fixed_epsilon: self.epsilon.unwrap_or(base.fixed_epsilon),
            without: match &self.without {
                Some(names) => crate::scene::SwitchedOff::parse(names.iter().map(String::as_str))
                    .map_err(WebError::Request)?,
                None => base.without,
            },
            ..base
        };
        settings.validate().map_err(WebError::Settings)?;
        let samples = settings.samples;
        let traces_light_paths = crate::effects::Effects::for_chapter(self.chapter)
            .without(settings.without)
            .needed_by(&scene, samples)
            .light_tracing;
        let paths = u64::from(settings.width)
            * u64::from(settings.height)
            * u64::from(settings.light_paths);
        if traces_light_paths && paths > PAGE_LIGHT_PATHS {
            return Err(WebError::LightPaths {
                paths,
                width: settings.width,
                height: settings.height,
                per_pixel: settings.light_paths,
            });
        }
        Ok((scene, settings))
    }
}

/// The C functions the page's loader (web/raylab.js) calls, for the
/// chapters `$chapters`: `raylab_alloc` and `raylab_free` for the request's
/// bytes, `raylab_call` to answer it, `raylab_answer_ptr` and
/// `raylab_answer_len` to read the answer. A panic (a chapter's `todo!()`)
/// aborts the module; its message is left as the answer first, so the
/// page can show it.
#[macro_export]
macro_rules! web_exports {
    ($chapters:ty) => {
        thread_local! {
            static ANSWER: ::std::cell::RefCell<Vec<u8>> = const { ::std::cell::RefCell::new(Vec::new()) };
        }

        fn raylab_set_answer(bytes: Vec<u8>) {
            ANSWER.with(|answer| *answer.borrow_mut() = bytes);
        }

        /// Room for a request of `len` bytes.
        #[unsafe(no_mangle)]
        pub extern "C" fn raylab_alloc(len: usize) -> *mut u8 {
            let mut buffer = ::std::mem::ManuallyDrop::new(vec![0u8; len]);
            buffer.as_mut_ptr()
        }

        /// Frees what `raylab_alloc` gave.
        ///
        /// # Safety
        /// `pointer` and `len` are exactly what one `raylab_alloc` returned
        /// and was asked.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn raylab_free(pointer: *mut u8, len: usize) {
            // SAFETY: as the caller promises, a vector of `len` bytes.
            drop(unsafe { Vec::from_raw_parts(pointer, len, len) });
        }

        /// Answers the request in the `len` bytes at `pointer`.
        ///
        /// # Safety
        /// `pointer` holds `len` initialised bytes (from `raylab_alloc`).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn raylab_call(pointer: *const u8, len: usize) {
            static HOOK: ::std::sync::Once = ::std::sync::Once::new();
            HOOK.call_once(|| {
                ::std::panic::set_hook(Box::new(|info| {
                    let payload = info.payload();
                    let message = payload
                        .downcast_ref::<&str>()
                        .map(|text| text.to_string())
                        .or_else(|| payload.downcast_ref::<String>().cloned())
                        .unwrap_or_default();
                    let location = info
                        .location()
                        .map(|at| format!("{}:{}:{}", at.file(), at.line(), at.column()))
                        .unwrap_or_default();
                    let answer = $crate::web::Answer {
                        json: $crate::web::panic_json(&message, &location),
                        pixels: Vec::new(),
                    };
                    raylab_set_answer(answer.into_bytes());
                }));
            });
            // SAFETY: as the caller promises.
            let request = unsafe { ::std::slice::from_raw_parts(pointer, len) };
            raylab_set_answer($crate::web::call::<$chapters>(request).into_bytes());
        }

        /// Where the last answer is.
        #[unsafe(no_mangle)]
        pub extern "C" fn raylab_answer_ptr() -> *const u8 {
            ANSWER.with(|answer| answer.borrow().as_ptr())
        }

        /// How long the last answer is.
        #[unsafe(no_mangle)]
        pub extern "C" fn raylab_answer_len() -> usize {
            ANSWER.with(|answer| answer.borrow().len())
        }
    };
}

/// The answer a panic with `message` at `location` leaves, as an error the
/// page shows: a chapter still `todo!()` is "not started", as on the
/// command line.
pub fn panic_json(message: &str, location: &str) -> serde_json::Value {
    let not_started = message
        .strip_prefix("not yet implemented")
        .or_else(|| message.strip_prefix("not implemented"))
        .and_then(crate::workspace::todo_names);
    let error = match not_started {
        Some((info, function)) => crate::workspace::not_started_message(info, Some(&function)),
        None => format!("the chapters panicked at {location}: {message}"),
    };
    serde_json::json!({ "error": error, "panicked": true })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Reference;

    fn json(answer: Answer) -> serde_json::Value {
        answer.json
    }

    /// The page names the command that traces the same pixel: raylab's
    /// own chapters are `raylab`'s, a workspace's its own binary's (an
    /// installed `raylab` refuses to run inside a workspace).
    #[test]
    fn the_command_line_named_is_the_chapters_own() {
        let chapters = br#"{"op": "chapters"}"#;
        let own = json(call::<Reference>(chapters));
        assert_eq!(own["command"], "raylab");
        assert_eq!(own["start"], 8);
        let student = json(call::<crate::check::planted::Planted>(chapters));
        assert_eq!(student["command"], "cargo run --release --");
        assert_eq!(student["start"], 1);
    }

    #[test]
    fn rows_are_the_render_s_rows() {
        let scene = crate::builtin::scene(6).expect("built-in scene");
        let settings = RenderSettings {
            width: 40,
            height: 30,
            ..scene.render
        };
        let whole = crate::render(&scene, 6, &settings, None).expect("renders");
        let answer = call::<Reference>(
            br#"{"op": "render", "job": {"chapter": 6, "width": 40, "height": 30}, "rows": [10, 17]}"#,
        );
        assert_eq!(answer.pixels.len(), 40 * 7 * 4);
        let rgb: Vec<u8> = answer
            .pixels
            .chunks_exact(4)
            .flat_map(|pixel| pixel[..3].to_vec())
            .collect();
        assert_eq!(rgb, whole.rgb[10 * 40 * 3..17 * 40 * 3]);
        assert!(answer.json["rays"]["primary"].as_u64() == Some(40 * 7));
    }

    #[test]
    fn a_kept_stage_renders_its_own_job_only() {
        // Chapter 11's mesh, then chapter 6, then chapter 11 again: each
        // slice is its own job's, the stage kept or not.
        let whole = |chapter: u8| {
            let scene = crate::builtin::scene(chapter).expect("built-in scene");
            let settings = RenderSettings {
                width: 32,
                height: 24,
                ..scene.render
            };
            crate::render(&scene, chapter, &settings, None)
                .expect("renders")
                .rgb
        };
        for (chapter, rows) in [(11, [0, 5]), (11, [5, 24]), (6, [3, 9]), (11, [2, 4])] {
            let request = serde_json::json!({
                "op": "render",
                "job": {"chapter": chapter, "width": 32, "height": 24},
                "rows": rows,
            });
            let answer = call::<Reference>(request.to_string().as_bytes());
            let rgb: Vec<u8> = answer
                .pixels
                .chunks_exact(4)
                .flat_map(|pixel| pixel[..3].to_vec())
                .collect();
            let [first, end] = rows.map(|row| row as usize * 32 * 3);
            assert_eq!(
                rgb,
                whole(chapter)[first..end],
                "chapter {chapter}, rows {rows:?}"
            );
        }
    }

    #[test]
    fn a_scene_error_names_its_line_and_column() {
        let request = serde_json::json!({
            "op": "prepare",
            "job": {"chapter": 2, "scene": "[camera]\nposition = [0, 1]\n"},
        });
        let answer = json(call::<Reference>(request.to_string().as_bytes()));
        assert_eq!(answer["line"], 2, "{answer}");
        assert_eq!(answer["column"], 12, "{answer}");
        assert!(
            answer["error"]
                .as_str()
                .is_some_and(|e| e.contains("line 2"))
        );
    }

    #[test]
    fn bad_requests_are_answered_with_an_error() {
        for request in [
            &b"not json"[..],
            br#"{"op": "explode"}"#,
            br#"{"op": "render", "job": {"chapter": 99}, "rows": [0, 1]}"#,
            br#"{"op": "render", "job": {"chapter": 3}, "rows": [0, 100000]}"#,
            br#"{"op": "render", "job": {"chapter": 3, "width": 0}, "rows": [0, 1]}"#,
            br#"{"op": "trace", "job": {"chapter": 3}, "pixel": [100000, 0]}"#,
        ] {
            let answer = call::<Reference>(request);
            assert!(answer.json["error"].is_string(), "{}", answer.json);
            assert!(answer.pixels.is_empty());
        }
    }

    #[test]
    fn a_trace_ends_in_the_rendered_pixel() {
        let answer = json(call::<Reference>(
            br#"{"op": "trace", "job": {"chapter": 8, "width": 64, "height": 48}, "pixel": [32, 20]}"#,
        ));
        let scene = crate::builtin::scene(8).expect("built-in scene");
        let settings = RenderSettings {
            width: 64,
            height: 48,
            ..scene.render
        };
        let rendered = crate::render(&scene, 8, &settings, None).expect("renders");
        let at = 3 * (20 * 64 + 32);
        assert_eq!(answer["srgb"], serde_json::json!(rendered.rgb[at..at + 3]));
    }

    #[test]
    fn a_camera_ray_is_drawn_through_its_pixel() {
        let answer = json(call::<Reference>(
            br#"{"op": "trace", "job": {"chapter": 6, "width": 64, "height": 48}, "pixel": [32, 24]}"#,
        ));
        let ray = &answer["samples"][0]["ray"];
        let screen = ray["screen"].as_array().expect("a camera ray is in front");
        for end in screen {
            let (x, y) = (
                end[0].as_f64().unwrap_or(-1.0),
                end[1].as_f64().unwrap_or(-1.0),
            );
            assert!((x - 32.5).abs() < 0.01 && (y - 24.5).abs() < 0.01, "{end}");
        }
        let bounce = &ray["children"]
            .as_array()
            .expect("children")
            .iter()
            .find(|child| child["kind"] == "reflection")
            .expect("the mirror ball reflects");
        assert!(bounce["screen"].is_array());
    }

    #[test]
    fn a_pixel_with_too_many_rays_to_draw_is_refused_with_its_count() {
        let answer = json(call::<Reference>(
            br#"{"op": "trace", "job": {"chapter": 9, "width": 64, "height": 48, "samples": 4096}, "pixel": [32, 20]}"#,
        ));
        let error = answer["error"].as_str().unwrap_or_default();
        assert!(
            error.contains("rays, more than the 20000 the page draws"),
            "{error}"
        );
    }

    /// `call` on another thread: its answer, or `None` if it has none
    /// within `seconds` (the thread is then left to finish on its own).
    fn call_within(request: serde_json::Value, seconds: u64) -> Option<serde_json::Value> {
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let answer = call::<Reference>(request.to_string().as_bytes());
            let _ = sender.send(answer.json);
        });
        receiver
            .recv_timeout(std::time::Duration::from_secs(seconds))
            .ok()
    }

    /// A glass box around a diamond ball, nothing cut by contribution: the
    /// ray tree of one pixel grows by about 1.3 a bounce, and at the page's
    /// `"depth": 64` it would not end for many minutes. Refused at once.
    #[test]
    fn a_job_whose_ray_tree_explodes_is_refused_up_front() {
        let scene = "[camera]\nposition = [0.3, 1.4, -5]\nlook_at = [0, 1, 0]\n\
            [render]\nmin_contribution = 0\n[[lights]]\nposition = [0, 5, -3]\n\
            [[objects]]\n\
            cuboid = { min = [-1, 0, -1], max = [1, 2, 1], rotate_y_degrees = 30 }\n\
            material = { transparency = 1.0, ior = 1.5, fresnel = \"exact\" }\n\
            [[objects]]\nsphere = { center = [0.2, 1.1, 0.1], radius = 0.6 }\n\
            material = { transparency = 1.0, ior = 2.4, fresnel = \"exact\" }\n";
        let job = serde_json::json!({
            "chapter": 10, "scene": scene, "width": 1, "height": 1, "depth": 64,
        });
        for request in [
            serde_json::json!({"op": "render", "job": job, "rows": [0, 1]}),
            serde_json::json!({"op": "trace", "job": job, "pixel": [0, 0]}),
            serde_json::json!({"op": "prepare", "job": job}),
        ] {
            let answer = call_within(request.clone(), 30)
                .unwrap_or_else(|| panic!("no answer within 30 s to {request}"));
            let error = answer["error"].as_str().unwrap_or_default();
            assert!(error.contains("rays for one pixel"), "{request}: {answer}");
        }
    }

    /// Chapter 14's light paths land anywhere in the image, so the page
    /// traces all of them for any rows it is asked: a job with more than
    /// the page's share of them is refused, not traced for minutes.
    #[test]
    fn a_page_job_with_too_many_light_paths_is_refused() {
        let request = serde_json::json!({
            "op": "render",
            "job": {"chapter": 14, "width": 4096, "height": 4096, "samples": 1},
            "rows": [0, 2],
        });
        let answer =
            call_within(request, 30).expect("an answer within 30 s, not the whole image's paths");
        let error = answer["error"].as_str().unwrap_or_default();
        assert!(error.contains("light paths"), "{answer}");
    }

    #[test]
    fn a_todo_panic_says_which_chapter_is_not_started() {
        let answer = panic_json(
            "not yet implemented: chapter 7: pixel_color",
            "src/x.rs:1:1",
        );
        let error = answer["error"].as_str().unwrap_or_default();
        let module = crate::chapters::chapter(7).map(|info| info.module());
        assert!(
            error.starts_with(&format!(
                "chapter 7 not started: write pixel_color in src/chapters/{}.rs",
                module.unwrap_or_default()
            )),
            "{error}"
        );
        let answer = panic_json("index out of bounds", "src/helpers.rs:40:9");
        assert_eq!(
            answer["error"],
            "the chapters panicked at src/helpers.rs:40:9: index out of bounds"
        );
    }

    #[test]
    fn the_answer_starts_with_its_json_length() {
        let bytes = Answer {
            json: serde_json::json!({"a": 1}),
            pixels: vec![7, 8],
        }
        .into_bytes();
        assert_eq!(&bytes[..4], &7u32.to_le_bytes());
        assert_eq!(&bytes[4..11], br#"{"a":1}"#);
        assert_eq!(&bytes[11..], &[7, 8]);
    }
}
