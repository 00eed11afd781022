//! No panic escapes the command line: a chapter still `todo!()` is
//! reported as "not started", any other panic as a message naming the
//! chapter it came from.
//!
//! A workspace's functions start as `todo!("chapter N: name")` (see
//! [`crate::workspace`]), which panics; so can a student's code, anywhere
//! in the render, on any of rayon's threads. Rayon hands a worker's panic
//! to the thread that started the parallel loop, so one `catch_unwind`
//! around the whole command sees it. The panic hook, which runs where the
//! panic happened, prints nothing (a student should read a verdict, not a
//! backtrace): it only records where the panic came from, to name the
//! chapter. With `RUST_BACKTRACE` set, the default report of the first panic
//! that is not a `todo!()` is printed too.

use std::panic::{self, AssertUnwindSafe, PanicHookInfo};
use std::sync::Mutex;

use crate::chapters::{CHAPTERS, ChapterInfo};

use super::{EXIT_ERROR, EXIT_FAILED_CHECK};

/// What the hook learnt about one panic.
#[derive(Debug, Clone)]
struct Record {
    message: String,
    location: String,
    chapter: Option<u8>,
}

/// The first few panics (rayon's threads may panic together).
static RECORDS: Mutex<Vec<Record>> = Mutex::new(Vec::new());
const MAX_RECORDS: usize = 8;

/// Runs `command` and returns its exit status, or the status of the panic
/// that stopped it, after printing what the panic means.
pub fn run(command: impl FnOnce() -> i32) -> i32 {
    let verbose = std::env::var_os("RUST_BACKTRACE").is_some_and(|value| value != "0");
    let default_hook = panic::take_hook();
    panic::set_hook(Box::new(move |info| {
        // Every pixel may panic the same way: the default report (and its
        // backtrace) once is enough. A `todo!()` is no bug to trace: a
        // function not written yet, which the message below says in full.
        let text = payload_text(info.payload());
        let todo = text.starts_with("not yet implemented");
        if record(info) && verbose && !todo && unwritable_stream(&text).is_none() {
            default_hook(info);
        }
    }));
    match panic::catch_unwind(AssertUnwindSafe(command)) {
        Ok(status) => status,
        Err(payload) => {
            let message = payload_text(payload.as_ref());
            let records = RECORDS.lock().map(|r| r.clone()).unwrap_or_default();
            let record = records
                .iter()
                .find(|record| record.message == message)
                .or(records.first())
                .cloned()
                .unwrap_or(Record {
                    message,
                    location: "an unknown place".to_string(),
                    chapter: None,
                });
            let (status, report) = explain(&record);
            eprintln!("{}", crate::text::terminal_safe(&report));
            status
        }
    }
}

fn payload_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(text) = payload.downcast_ref::<&str>() {
        text.to_string()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Records a panic; true for the first one.
fn record(info: &PanicHookInfo) -> bool {
    let Ok(mut records) = RECORDS.lock() else {
        return false;
    };
    if records.len() >= MAX_RECORDS {
        return false;
    }
    let message = payload_text(info.payload());
    let (location, chapter) = match info.location() {
        Some(location) => (
            format!(
                "{}:{}:{}",
                location.file(),
                location.line(),
                location.column()
            ),
            chapter_of_file(location.file()),
        ),
        None => ("an unknown place".to_string(), None),
    };
    // A panic inside raylab (an index out of range, say) may still come from
    // a chapter's call: the innermost chapter function on the stack names it.
    let chapter = chapter
        .or_else(|| chapter_in_backtrace(&std::backtrace::Backtrace::force_capture().to_string()));
    records.push(Record {
        message,
        location,
        chapter,
    });
    records.len() == 1
}

/// The chapter whose file `file` is: a workspace's `src/chapters/chNN_name.rs`
/// or a file of raylab's `chapters/NN_name/`.
fn chapter_of_file(file: &str) -> Option<u8> {
    let path = std::path::Path::new(file);
    let stem = path.file_stem()?.to_str()?;
    let parent = path.parent()?;
    let folder = parent.file_name()?.to_str()?;
    let grandparent = parent.parent().and_then(|p| p.file_name());
    CHAPTERS
        .iter()
        .find(|info| {
            (folder == "chapters" && stem == info.module())
                || (folder == info.folder && grandparent.is_some_and(|name| name == "chapters"))
        })
        .map(|info| info.number)
}

/// The chapter of the innermost frame of `backtrace` (as printed, innermost
/// first) in a chapter module, by symbol or by file.
fn chapter_in_backtrace(backtrace: &str) -> Option<u8> {
    CHAPTERS
        .iter()
        .filter_map(|info| {
            let symbol = format!("chapters::{}::", info.module());
            let file = format!("{}.rs:", info.module());
            [symbol.as_str(), file.as_str()]
                .iter()
                .filter_map(|needle| backtrace.find(needle))
                .min()
                .map(|at| (at, info.number))
        })
        .min()
        .map(|(_, number)| number)
}

/// The exit status and the message for a panic.
fn explain(record: &Record) -> (i32, String) {
    if let Some((stream, why)) = unwritable_stream(&record.message) {
        // A full disk or a closed pipe behind `> out.txt`: the user's
        // setting, not a bug. What was written to files stays.
        return (
            EXIT_ERROR,
            format!("error: cannot write to {stream}: {why} (files written before are kept)"),
        );
    }
    let info = record.chapter.and_then(crate::chapters::chapter);
    let not_started = record
        .message
        .strip_prefix("not yet implemented")
        .or_else(|| record.message.strip_prefix("not implemented"));
    if let Some(rest) = not_started {
        if let Some((info, function)) = crate::workspace::todo_names(rest) {
            return (
                EXIT_FAILED_CHECK,
                not_started_message(info, Some(&function)),
            );
        }
        if let Some(info) = info {
            return (
                EXIT_FAILED_CHECK,
                not_started_message(info, None).replace(
                    "write the function",
                    &format!("finish the todo!() at {}", record.location),
                ),
            );
        }
    }
    let report = match info {
        Some(info) => format!(
            "error: your chapter {} code panicked at {}: {}\n\
             (a panic stops the whole command; chapter {}'s file is src/chapters/{}.rs)",
            info.number,
            record.location,
            record.message,
            info.number,
            info.module()
        ),
        None => format!(
            "error: raylab panicked at {}: {}\n\
             This is a bug in raylab, not in your chapters; RUST_BACKTRACE=1 shows where.",
            record.location, record.message
        ),
    };
    (EXIT_ERROR, report)
}

/// The stream and the reason of the standard library's panic when
/// `print!` cannot write (`raylab render > /dev/full`), if `message` is one.
fn unwritable_stream(message: &str) -> Option<(&'static str, &str)> {
    [
        ("failed printing to stdout: ", "the standard output"),
        ("failed printing to stderr: ", "the standard error"),
    ]
    .into_iter()
    .find_map(|(prefix, stream)| message.strip_prefix(prefix).map(|why| (stream, why)))
}

fn not_started_message(info: &ChapterInfo, function: Option<&str>) -> String {
    crate::workspace::not_started_message(info, function)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chapter `number`'s file in a workspace, from the registry.
    fn workspace_file(number: u8) -> String {
        let info = crate::chapters::chapter(number).expect("a chapter");
        format!("src/chapters/{}.rs", info.module())
    }

    fn record(message: &str, chapter: Option<u8>) -> Record {
        Record {
            message: message.to_string(),
            location: format!("{}:10:5", workspace_file(2)),
            chapter,
        }
    }

    #[test]
    fn a_skeleton_todo_is_not_started() {
        let (status, text) = explain(&record(
            "not yet implemented: chapter 1: intersect_plane",
            None,
        ));
        assert_eq!(status, EXIT_FAILED_CHECK);
        let expected = format!(
            "chapter 1 not started: write intersect_plane in {}",
            workspace_file(1)
        );
        assert!(text.starts_with(&expected), "{text}");
        let (status, text) = explain(&record("not yet implemented", Some(2)));
        assert_eq!(status, EXIT_FAILED_CHECK);
        let expected = format!(
            "chapter 2 not started: finish the todo!() at {}:10:5",
            workspace_file(2)
        );
        assert!(text.contains(&expected), "{text}");
    }

    #[test]
    fn other_panics_name_the_chapter_or_raylab() {
        let (status, text) = explain(&record("attempt to divide by zero", Some(2)));
        assert_eq!(status, EXIT_ERROR);
        assert!(text.contains("your chapter 2 code panicked"), "{text}");
        assert!(text.contains("attempt to divide by zero"), "{text}");
        let (status, text) = explain(&record("index out of bounds", None));
        assert_eq!(status, EXIT_ERROR);
        assert!(text.contains("raylab panicked"), "{text}");
    }

    #[test]
    fn chapters_from_files_and_backtraces() {
        assert_eq!(chapter_of_file(&workspace_file(4)), Some(4));
        let eight = crate::chapters::chapter(8).expect("chapter 8");
        assert_eq!(
            chapter_of_file(&format!("/x/raylab/{}", eight.code_path())),
            Some(8)
        );
        assert_eq!(chapter_of_file("src/render.rs"), None);
        assert_eq!(
            chapter_of_file(&workspace_file(4).replace("chapters/", "")),
            None
        );
        let module = |number| {
            crate::chapters::chapter(number)
                .expect("a chapter")
                .module()
        };
        let backtrace = format!(
            "  10: raylab::render::Tracer<C>::trace\n  \
             11: me::chapters::{}::shade_phong\n  \
             12: me::chapters::{}::shade_mirror\n",
            module(5),
            module(6)
        );
        assert_eq!(chapter_in_backtrace(&backtrace), Some(5));
        assert_eq!(chapter_in_backtrace("  1: std::panicking\n"), None);
    }
}
