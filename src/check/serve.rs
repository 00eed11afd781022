//! The student's side of the judge: answering questions, nothing more.
//!
//! A student's binary started as `serve` (see [`crate::check::judge`])
//! reads [`Request`]s and answers each with a [`Reply`]: the raw answer
//! its chapters give, worked out by raylab's own code around them (the
//! loop over pixels, the rays of a case), with the panic it raised if it
//! raised one and the answers of raylab's that ran meanwhile. It never
//! sees an expected value and decides nothing: whatever it prints, writes
//! or exits with, the judge reads only these replies.

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3;

use super::panics::guarded;
use super::protocol::{
    Answered, Hello, ProtocolError, Reply, Request, View, read_frame, write_frame,
};
use crate::Chapters;
use crate::chapters::{REFERENCE_HEIGHT, REFERENCE_WIDTH};

/// Set once this process answers questions: the judge's own entry points
/// refuse to run inside it, so that a chapter cannot run the checks (and
/// read their expected values) from within.
static SERVING: AtomicBool = AtomicBool::new(false);

/// Whether this process is a student's, answering the judge.
pub fn serving() -> bool {
    SERVING.load(Ordering::SeqCst)
}

/// Answers requests read from `input` on `output` until the judge closes
/// `input`, with the chapters `C`.
pub fn serve<C: Chapters>(
    mut input: impl Read,
    mut output: impl Write,
) -> Result<(), ProtocolError> {
    SERVING.store(true, Ordering::SeqCst);
    loop {
        let request: Request = match read_frame(&mut input) {
            Ok(request) => request,
            Err(ProtocolError::Closed) => return Ok(()),
            Err(error) => return Err(error),
        };
        write_frame(&mut output, &answer::<C>(&request))?;
    }
}

/// The reply of the chapters `C` to `request`: what `serve` sends, and
/// what the judge computes itself when it asks raylab's own chapters.
pub fn answer<C: Chapters>(request: &Request) -> Reply {
    if let Request::Hello(_) = request {
        return Reply::Hello {
            hello: Hello::ours(),
            comparison: C::COMPARISON,
        };
    }
    // Reports from threads of the chapters' own, before this request, are
    // not this request's.
    crate::answer_key::take_reported();
    let (answer, used) =
        crate::answer_key::recording(|| match guarded(|| work_out::<C>(request)) {
            Ok(Ok(answer)) => answer,
            Ok(Err(error)) => Answered::Error(error),
            Err(panic) => Answered::Panicked(panic),
        });
    Reply::Answer {
        answer,
        used: used.into_iter().map(str::to_string).collect(),
        escaped: crate::answer_key::take_reported()
            .into_iter()
            .map(str::to_string)
            .collect(),
    }
}

fn work_out<C: Chapters>(request: &Request) -> Result<Answered, String> {
    match request {
        Request::Hello(_) => Err("a second hello".into()),
        Request::Case(call) => call.ask::<C>().map(Answered::Case),
        Request::Image { chapter, view } => {
            image::<C>(*chapter, view.as_ref()).map(Answered::Pixels)
        }
        Request::Render {
            scene,
            chapter,
            view,
        } => {
            let mut scene =
                crate::Scene::parse(scene, "the judge's scene").map_err(|e| e.to_string())?;
            if let Some(view) = view {
                scene.camera = view.applied_to(&scene.camera);
            }
            let rendered = crate::render_with::<C>(&scene, *chapter, &scene.render, None)
                .map_err(|error| error.to_string())?;
            Ok(Answered::Rgb {
                width: rendered.width,
                height: rendered.height,
                rgb: rendered.rgb,
            })
        }
    }
}

/// Chapter `chapter`'s built-in scene at the reference size, in linear
/// light, as [`crate::check`] judges it: the same loop as `raylab render`,
/// on this thread, each pixel the camera's estimate plus what chapter 14's
/// light paths brought to it. Seen from `view` where given.
pub fn image<C: Chapters>(chapter: u8, view: Option<&View>) -> Result<Vec<Vec3>, String> {
    let scene = viewed_scene(chapter, view)?;
    let settings = image_settings(&scene);
    let stage = crate::Stage::<C>::with_chapters(&scene, chapter, settings)
        .map_err(|error| error.to_string())?;
    let light = stage.light_image();
    let mut tracer = super::sampled::judging_tracer(&stage);
    let mut linear = Vec::with_capacity((REFERENCE_WIDTH * REFERENCE_HEIGHT) as usize);
    for y in 0..REFERENCE_HEIGHT {
        for x in 0..REFERENCE_WIDTH {
            let index = linear.len();
            let camera = tracer.pixel(x, y);
            linear.push(camera + light.map_or(Vec3::ZERO, |light| light.pixels[index]));
        }
    }
    Ok(linear)
}

/// Chapter `chapter`'s built-in scene, its camera moved to `view` where
/// given.
pub fn viewed_scene(chapter: u8, view: Option<&View>) -> Result<crate::Scene, String> {
    let mut scene = crate::builtin::scene(chapter).map_err(|error| error.to_string())?;
    if let Some(view) = view {
        scene.camera = view.applied_to(&scene.camera);
    }
    Ok(scene)
}

/// The settings of the chapter image: the scene's, at the reference size.
pub fn image_settings(scene: &crate::Scene) -> crate::RenderSettings {
    crate::RenderSettings {
        width: REFERENCE_WIDTH,
        height: REFERENCE_HEIGHT,
        ..scene.render
    }
}
