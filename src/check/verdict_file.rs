//! The verdict file: how a check run in a student's process hands its
//! verdict to the process that reports it.
//!
//! A student's chapters run inside the student's binary, where their code
//! may end the process (`std::process::exit(0)`), print a table that looks
//! like a verdict, or die. So the verdict is never read from that process's
//! exit status or output: the check writes it, record by record, to a file
//! named by the process that started it (the student's own `check`, which
//! runs the chapters in a child, or `raylab grade --code`), and only a file
//! that ends with its closing record counts. A run that ends early leaves
//! the progress records: the chapter and the function that was running.
//!
//! Each line is one JSON record: `progress` before each step of a
//! chapter's check, `verdict` for each chapter, `end` last.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{ChapterVerdict, CheckReport, Overall, Status};

/// The largest verdict file read: a check of every chapter writes a few
/// dozen kilobytes.
pub const MAX_VERDICT_FILE: u64 = 4 << 20;

/// One line of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Record {
    /// A step of chapter `chapter`'s check starts: `function` is the
    /// course function it calls (or "the image", "robustness").
    Progress {
        chapter: u8,
        function: String,
        case: String,
    },
    /// Chapter `chapter`'s own check has ended (its verdict comes with the
    /// others at the end).
    Finished {
        chapter: u8,
    },
    Verdict(SentVerdict),
    End,
}

/// A chapter's verdict as the file carries it: what the report prints and
/// what the grade counts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SentVerdict {
    pub chapter: u8,
    /// The status word of the summary table (`pass`, `FAIL`, ...).
    pub status: String,
    pub passes: bool,
    pub robust: bool,
    pub not_started: bool,
    /// The check itself could not run.
    pub error: bool,
    /// The verdict as the student reads it.
    pub text: String,
    /// Its row of the summary table.
    pub row: String,
}

impl SentVerdict {
    pub fn of(verdict: &ChapterVerdict) -> SentVerdict {
        SentVerdict {
            chapter: verdict.chapter,
            status: verdict.status.word(),
            passes: verdict.passes(),
            robust: verdict.robust(),
            not_started: matches!(verdict.status, Status::NotStarted | Status::Blocked { .. }),
            error: verdict.status == Status::Error || !verdict.errors.is_empty(),
            text: verdict.text(),
            row: CheckReport::summary_row(verdict),
        }
    }
}

/// Why a verdict file could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum VerdictFileError {
    #[error("cannot write the verdict file {}: {error}", path.display())]
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("cannot read the verdict file {}: {error}", path.display())]
    Read {
        path: PathBuf,
        error: crate::input::InputError,
    },
}

/// Appends records to a verdict file.
#[derive(Debug)]
pub struct VerdictWriter {
    path: PathBuf,
    file: std::sync::Mutex<std::fs::File>,
}

impl VerdictWriter {
    /// Creates (or empties) the file at `path`.
    pub fn create(path: &Path) -> Result<VerdictWriter, VerdictFileError> {
        let file = std::fs::File::create(path).map_err(|error| VerdictFileError::Write {
            path: path.to_path_buf(),
            error,
        })?;
        Ok(VerdictWriter {
            path: path.to_path_buf(),
            file: std::sync::Mutex::new(file),
        })
    }

    /// Writes `record` as one line, at once, so that a process that dies
    /// right after leaves it whole.
    pub fn write(&self, record: &Record) -> Result<(), VerdictFileError> {
        let mut line = serde_json::to_string(record).unwrap_or_default();
        line.push('\n');
        let error = |error| VerdictFileError::Write {
            path: self.path.clone(),
            error,
        };
        let mut file = self
            .file
            .lock()
            .map_err(|_| error(std::io::Error::other("a writer panicked")))?;
        file.write_all(line.as_bytes()).map_err(error)
    }
}

/// The file this process's check writes its progress to, once installed.
static PROGRESS: std::sync::OnceLock<VerdictWriter> = std::sync::OnceLock::new();

/// Makes `writer` the file every check of this process reports its steps
/// to; returns it back if one is installed already.
pub fn install(writer: VerdictWriter) -> Result<&'static VerdictWriter, VerdictWriter> {
    PROGRESS.set(writer)?;
    PROGRESS.get().ok_or_else(|| unreachable!())
}

/// Notes that a step of chapter `chapter`'s check starts (nothing without
/// an installed file).
pub(crate) fn step(chapter: u8, function: &str, case: &str) {
    if let Some(writer) = PROGRESS.get() {
        let _ = writer.write(&Record::Progress {
            chapter,
            function: function.to_string(),
            case: case.to_string(),
        });
    }
}

/// Notes that chapter `chapter`'s own check has ended.
pub(crate) fn finished(chapter: u8) {
    if let Some(writer) = PROGRESS.get() {
        let _ = writer.write(&Record::Finished { chapter });
    }
}

/// What a verdict file said.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SentReport {
    pub verdicts: Vec<SentVerdict>,
    /// The last step started by each chapter whose check had not ended,
    /// in chapter order: where a run that did not end was.
    pub running: Vec<(u8, String, String)>,
    /// Whether the closing record came.
    pub complete: bool,
}

impl SentReport {
    /// Reads the file at `path`; lines that are not records are skipped
    /// (a record is never split: each is written whole).
    pub fn read(path: &Path) -> Result<SentReport, VerdictFileError> {
        let bytes = crate::input::read_bounded(
            path,
            MAX_VERDICT_FILE,
            "verdict file",
            crate::input::Links::Refuse,
        )
        .map_err(|error| VerdictFileError::Read {
            path: path.to_path_buf(),
            error,
        })?;
        let mut report = SentReport::default();
        for line in String::from_utf8_lossy(&bytes).lines() {
            match serde_json::from_str::<Record>(line) {
                Ok(Record::Progress {
                    chapter,
                    function,
                    case,
                }) => {
                    report.running.retain(|(other, ..)| *other != chapter);
                    report.running.push((chapter, function, case));
                }
                Ok(Record::Finished { chapter }) => {
                    report.running.retain(|(other, ..)| *other != chapter);
                }
                Ok(Record::Verdict(verdict)) => report.verdicts.push(verdict),
                Ok(Record::End) => report.complete = true,
                Err(_) => {}
            }
        }
        Ok(report)
    }

    /// Pass, fail or error, as [`CheckReport::overall`] says: a report
    /// without its closing record fails.
    pub fn overall(&self) -> Overall {
        if !self.complete || self.verdicts.is_empty() {
            Overall::Fail
        } else if self.verdicts.iter().any(|v| v.error) {
            Overall::Error
        } else if self.verdicts.iter().all(|v| v.passes) {
            Overall::Pass
        } else {
            Overall::Fail
        }
    }

    /// Every verdict, what ended the run early if it did, then the table.
    /// `ended` says how the process ended ("exited with status 0").
    pub fn text(&self, ended: &str) -> String {
        let mut out = String::new();
        for verdict in &self.verdicts {
            out.push_str(&verdict.text);
            out.push('\n');
        }
        if !self.complete {
            out.push_str(&self.early_end(ended));
            out.push('\n');
        }
        out.push_str(&CheckReport::summary_header());
        for verdict in &self.verdicts {
            out.push_str(&verdict.row);
        }
        if !self.complete {
            out.push_str("(no verdict: the check did not finish)\n");
        }
        out
    }

    /// The steps of the chapters still running, earliest chapter first
    /// (later chapters call its code), in words: "chapter 1's check ran
    /// intersect_plane (plane-ahead), and chapter 3's ...". Empty when none
    /// is.
    pub fn running_text(&self) -> String {
        let mut running = self.running.clone();
        running.sort_by_key(|(chapter, ..)| *chapter);
        running
            .iter()
            .map(|(chapter, function, case)| {
                format!(
                    "chapter {chapter}'s check ran {function} ({})",
                    crate::text::terminal_safe(case)
                )
            })
            .collect::<Vec<_>>()
            .join(", and ")
    }

    fn early_end(&self, ended: &str) -> String {
        let steps = self.running_text();
        let during = if steps.is_empty() {
            String::new()
        } else {
            format!(" while {steps}")
        };
        format!(
            "the check did not finish: the process {ended}{during}, before the verdict.\n  \
             A chapter's function must return its answer: std::process::exit, abort or a \
             stack overflow end the whole check, and the chapters it did not reach fail.\n"
        )
    }
}

/// How a process ended, in words: "exited with status 0", "was killed by
/// signal 11".
pub fn process_end(status: std::process::ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return format!("was killed by signal {signal}");
        }
    }
    match status.code() {
        Some(code) => format!("exited with status {code}"),
        None => "ended".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_closed_file_passes() {
        let dir = std::env::temp_dir().join(format!("raylab-verdict-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("verdict.jsonl");
        let writer = VerdictWriter::create(&path).unwrap();
        let pass = SentVerdict {
            chapter: 1,
            status: "pass".into(),
            passes: true,
            robust: true,
            not_started: false,
            error: false,
            text: "chapter 1: pass\n".into(),
            row: "1 pass\n".into(),
        };
        writer
            .write(&Record::Progress {
                chapter: 1,
                function: "intersect_plane".into(),
                case: "plane-ahead".into(),
            })
            .unwrap();
        writer.write(&Record::Verdict(pass)).unwrap();
        let open = SentReport::read(&path).unwrap();
        assert_eq!(open.overall(), Overall::Fail);
        assert!(
            open.text("exited with status 0")
                .contains("chapter 1's check ran intersect_plane")
        );
        writer.write(&Record::End).unwrap();
        let closed = SentReport::read(&path).unwrap();
        assert_eq!(closed.overall(), Overall::Pass);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Chapters run in parallel: the chapter whose check ended is not
    /// blamed, every chapter still running is, the earliest first.
    #[test]
    fn an_unfinished_run_names_every_chapter_still_running() {
        let dir = std::env::temp_dir().join(format!("raylab-running-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("verdict.jsonl");
        let writer = VerdictWriter::create(&path).unwrap();
        let step = |chapter: u8, function: &str, case: &str| Record::Progress {
            chapter,
            function: function.into(),
            case: case.into(),
        };
        for record in [
            step(1, "intersect_plane", "plane-ahead"),
            step(11, "hit_box", "box-entry"),
            step(4, "in_shadow", "shadow-blocker"),
            Record::Finished { chapter: 11 },
            step(3, "nearest_hit", "nearest-two"),
        ] {
            writer.write(&record).unwrap();
        }
        let text = SentReport::read(&path)
            .unwrap()
            .text("was killed by signal 9");
        assert!(
            text.contains(
                "while chapter 1's check ran intersect_plane (plane-ahead), and chapter 3's \
                 check ran nearest_hit (nearest-two), and chapter 4's check ran in_shadow"
            ),
            "{text}"
        );
        assert!(!text.contains("hit_box"), "{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
