//! A student's binary answering the judge from a process of its own.
//!
//! [`Remote`] starts the binary as `serve` when first asked, says hello
//! (both sides must be built from the same raylab), sends each request on
//! the child's stdin and reads one reply from its stdout, with a time limit
//! and a notice for a step that takes long. A child that ends while
//! answering is one failed case: the next request starts another. What the
//! child writes on stderr is kept (its end) or passed through, never read
//! as anything.

use std::io::Read;
use std::process::Child;
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::asker::{Asker, Ended, Step};
use super::protocol::{Hello, ProtocolError, Reply, Request};

/// How to start a student's binary as `serve`: the command, and whatever
/// must live as long as the process (a sandbox's cgroup).
pub type Spawn = dyn Fn() -> std::io::Result<(std::process::Command, Box<dyn std::any::Any + Send>)>
    + Send
    + Sync;

/// A notice that a step takes long: called once per step, after
/// `Remote::stall_after`.
pub type StallNotice = dyn Fn(&Step, Duration) + Send + Sync;

/// How much of what a student's process writes to its standard error is
/// kept (the end): it may write without end, and none of it is a verdict.
pub const KEPT_STDERR: usize = 64 * 1024;

/// How long a process started as `serve` may take to say hello.
const HELLO_WITHIN: Duration = Duration::from_secs(60);

/// A student's binary, started as `serve` when first asked, and again
/// after it ends.
pub struct Remote {
    spawn: Arc<Spawn>,
    running: Option<Running>,
    /// Set once the binary does not say raylab's hello: nothing more is
    /// asked of it.
    refused: Option<String>,
    deadline: Option<Instant>,
    stall_after: Duration,
    on_stall: Option<Arc<StallNotice>>,
    /// Whether the processes write to this one's stderr (a student's own
    /// check, where their prints help them), or to [`Remote::stderr`].
    inherit_stderr: bool,
    /// The end of what every process of this asker wrote on stderr.
    stderr: Arc<Mutex<Vec<u8>>>,
}

struct Running {
    child: Child,
    /// Requests, to the thread that writes them to the child's stdin.
    requests: mpsc::Sender<Request>,
    replies: mpsc::Receiver<Result<Reply, ProtocolError>>,
    _keep: Box<dyn std::any::Any + Send>,
}

impl Drop for Running {
    fn drop(&mut self) {
        kill_group(&mut self.child);
        let _ = self.child.wait();
    }
}

impl Remote {
    pub fn new(spawn: Arc<Spawn>) -> Remote {
        Remote {
            spawn,
            running: None,
            refused: None,
            deadline: None,
            stall_after: Duration::from_secs(30),
            on_stall: None,
            inherit_stderr: false,
            stderr: Arc::new(Mutex::new(Vec::new())),
        }
    }

    /// The processes write to this process's stderr: what a student's
    /// chapters print while their own check runs is theirs to read.
    pub fn inheriting_stderr(mut self) -> Remote {
        self.inherit_stderr = true;
        self
    }

    /// Past `deadline`, the process is killed and nothing more is asked.
    pub fn with_deadline(mut self, deadline: Option<Instant>) -> Remote {
        self.deadline = deadline;
        self
    }

    /// `notice` once a step has gone `after` without an answer.
    pub fn with_stall_notice(mut self, after: Duration, notice: Arc<StallNotice>) -> Remote {
        self.stall_after = after;
        self.on_stall = Some(notice);
        self
    }

    /// The end of what the processes wrote on stderr (none of it counts).
    pub fn stderr(&self) -> String {
        let kept = self
            .stderr
            .lock()
            .map(|kept| kept.clone())
            .unwrap_or_default();
        String::from_utf8_lossy(&kept).into_owned()
    }

    /// Keeps what the processes write on stderr in `buffer` (its end), so
    /// that several askers of one student's check share one.
    pub fn with_stderr_buffer(mut self, buffer: Arc<Mutex<Vec<u8>>>) -> Remote {
        self.stderr = buffer;
        self
    }

    fn start(&mut self) -> Result<(), Ended> {
        let (mut command, keep) = (self.spawn)().map_err(|error| {
            Ended::Refused(format!(
                "the student's binary could not be started: {error}"
            ))
        })?;
        command
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(if self.inherit_stderr {
                std::process::Stdio::inherit()
            } else {
                std::process::Stdio::piped()
            });
        #[cfg(unix)]
        {
            use std::os::unix::process::CommandExt;
            // Its own process group, so that the whole of it goes when it
            // is killed; and it dies with the judge.
            command.process_group(0);
            // SAFETY: prctl is async-signal-safe and is all that runs
            // between fork and exec.
            #[cfg(target_os = "linux")]
            unsafe {
                command.pre_exec(|| {
                    libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                    Ok(())
                });
            }
        }
        let mut child = command.spawn().map_err(|error| {
            Ended::Refused(format!(
                "the student's binary could not be started: {error}"
            ))
        })?;
        let (Some(mut input), Some(mut output)) = (child.stdin.take(), child.stdout.take()) else {
            kill_group(&mut child);
            return Err(Ended::Refused("the student's binary has no pipes".into()));
        };
        // Written by a thread of its own that ignores SIGPIPE: raylab dies
        // of it on a closed stdout (as a command line tool should), and a
        // child that ended before reading its request must not take the
        // judge with it. The reply thread sees the end of the child.
        let (requests, to_write) = mpsc::channel::<Request>();
        std::thread::spawn(move || {
            block_sigpipe_on_this_thread();
            for request in to_write {
                if super::protocol::write_frame(&mut input, &request).is_err() {
                    return;
                }
            }
        });
        let (sender, replies) = mpsc::channel();
        std::thread::spawn(move || {
            loop {
                // Cut to a bound here, before anything of the judge's
                // keeps it.
                let reply = super::protocol::read_frame::<Reply>(&mut output).map(Reply::bounded);
                let stop = reply.is_err();
                if sender.send(reply).is_err() || stop {
                    return;
                }
            }
        });
        if let Some(errors) = child.stderr.take() {
            let kept = Arc::clone(&self.stderr);
            std::thread::spawn(move || keep_tail(errors, &kept));
        }
        self.running = Some(Running {
            child,
            requests,
            replies,
            _keep: keep,
        });
        let hello = Step {
            chapter: 0,
            function: "hello".into(),
            case: "the student's binary starting".into(),
        };
        match self.exchange(&Request::Hello(Hello::ours()), &hello, Some(HELLO_WITHIN)) {
            Ok(Reply::Hello {
                hello: theirs,
                comparison: _,
            }) if theirs == Hello::ours() => Ok(()),
            Ok(Reply::Hello { hello: theirs, .. }) => Err(Ended::Refused(mismatch(&theirs))),
            Ok(_) => Err(Ended::Refused(
                "the student's binary answered raylab's hello with something else".into(),
            )),
            Err(Ended::Died(how)) => Err(Ended::Refused(format!(
                "the student's binary {how} before it said hello: it does not answer raylab's \
                 questions (is it built against another raylab, or its main.rs not the one \
                 `raylab new` writes?)"
            ))),
            Err(other) => Err(other),
        }
    }

    /// Sends `request` and waits for its reply.
    fn exchange(
        &mut self,
        request: &Request,
        step: &Step,
        within: Option<Duration>,
    ) -> Result<Reply, Ended> {
        let Some(running) = self.running.as_mut() else {
            return Err(Ended::Died("was not running".into()));
        };
        if running.requests.send(request.clone()).is_err() {
            return Err(self.died());
        }
        let asked = Instant::now();
        let mut told = false;
        loop {
            let mut wait = Duration::from_millis(200);
            if let Some(deadline) = self.deadline {
                let left = deadline.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    self.running = None;
                    return Err(Ended::TimedOut);
                }
                wait = wait.min(left);
            }
            if within.is_some_and(|within| asked.elapsed() >= within) {
                self.running = None;
                return Err(Ended::Died(format!(
                    "did not answer within {} s",
                    within.map_or(0, |within| within.as_secs())
                )));
            }
            let Some(running) = self.running.as_mut() else {
                return Err(Ended::Died("was not running".into()));
            };
            match running.replies.recv_timeout(wait) {
                Ok(Ok(reply)) => return Ok(reply),
                Ok(Err(_)) | Err(mpsc::RecvTimeoutError::Disconnected) => return Err(self.died()),
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if !told && asked.elapsed() >= self.stall_after {
                        told = true;
                        if let Some(notice) = &self.on_stall {
                            notice(step, asked.elapsed());
                        }
                    }
                }
            }
        }
    }

    /// The process ended (or talks nonsense): how, once it is gone.
    fn died(&mut self) -> Ended {
        let Some(mut running) = self.running.take() else {
            return Ended::Died("was not running".into());
        };
        // Its pipe closed: it has ended, or is about to.
        let ended = Instant::now();
        let status = loop {
            match running.child.try_wait() {
                Ok(Some(status)) => break Some(status),
                Ok(None) if ended.elapsed() < Duration::from_secs(2) => {
                    std::thread::sleep(Duration::from_millis(10));
                }
                _ => break None,
            }
        };
        Ended::Died(
            status.map_or_else(|| "closed its pipe and was killed".to_string(), process_end),
        )
    }
}

impl Asker for Remote {
    fn ask(&mut self, request: &Request, step: &Step) -> Result<Reply, Ended> {
        if let Some(why) = &self.refused {
            return Err(Ended::Refused(why.clone()));
        }
        if self.running.is_none()
            && let Err(error) = self.start()
        {
            self.running = None;
            if let Ended::Refused(why) = &error {
                self.refused = Some(why.clone());
            }
            return Err(error);
        }
        self.exchange(request, step, None)
    }

    fn set_deadline(&mut self, deadline: Option<Instant>) {
        self.deadline = deadline;
    }
}

/// The message for a binary built from another raylab.
fn mismatch(theirs: &Hello) -> String {
    let ours = Hello::ours();
    format!(
        "the student's binary was built against another raylab (protocol {}, raylab {}, source \
         {}) than this one (protocol {}, raylab {}, source {}): build the workspace again \
         against this raylab (its Cargo.toml names raylab's folder), then check again",
        theirs.protocol,
        crate::text::terminal_safe(&theirs.version),
        crate::text::terminal_safe(&theirs.source),
        ours.protocol,
        ours.version,
        ours.source
    )
}

/// Blocks SIGPIPE on the calling thread: a write to a closed pipe then
/// fails with EPIPE instead of ending the process.
fn block_sigpipe_on_this_thread() {
    #[cfg(unix)]
    // SAFETY: plain calls on a signal set on the stack, for this thread.
    unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, libc::SIGPIPE);
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
    }
}

/// Keeps the last [`KEPT_STDERR`] bytes `reader` gives in `kept`.
fn keep_tail(mut reader: impl Read, kept: &Mutex<Vec<u8>>) {
    let mut buffer = [0u8; 8192];
    loop {
        match reader.read(&mut buffer) {
            Ok(0) => return,
            Ok(n) => {
                if let Ok(mut kept) = kept.lock() {
                    kept.extend_from_slice(&buffer[..n]);
                    if kept.len() > 2 * KEPT_STDERR {
                        let excess = kept.len() - KEPT_STDERR;
                        kept.drain(..excess);
                    }
                }
            }
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => {}
            Err(_) => return,
        }
    }
}

/// Kills the child's whole process group (the child is its leader).
pub(crate) fn kill_group(child: &mut Child) {
    #[cfg(unix)]
    {
        if let Ok(group) = libc::pid_t::try_from(child.id()) {
            // SAFETY: killpg with a group this process created; an already
            // empty group only makes it return ESRCH.
            unsafe {
                libc::killpg(group, libc::SIGKILL);
            }
        }
    }
    #[cfg(not(unix))]
    {
        let _ = child.kill();
    }
}

/// How a process ended, in words: "exited with status 0", "was killed by
/// signal 11", with the limit of a process that ended it where a signal
/// says so (the sandbox's limits of CPU time and file size end a process
/// by SIGXCPU and SIGXFSZ; bubblewrap exits with 128 and the signal).
pub fn process_end(status: std::process::ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return format!("was killed by signal {signal}{}", limit_of(signal));
        }
    }
    match status.code() {
        Some(code) => {
            // A status is the program's to choose: 152 may be bubblewrap
            // telling of SIGXCPU, or an exit(152) that would pass for it.
            let limit = code.checked_sub(128).map(limit_of).unwrap_or_default();
            if limit.is_empty() {
                format!("exited with status {code}")
            } else {
                format!(
                    "exited with status {code}: 128 + {}, as bubblewrap tells of a process \
                     ended by that signal{limit}, or a program's own exit with that status",
                    code - 128
                )
            }
        }
        None => "ended".to_string(),
    }
}

/// The limit a process ended by `signal` reached, in words, if the signal
/// is one a limit sends.
fn limit_of(signal: i32) -> &'static str {
    #[cfg(unix)]
    {
        if signal == libc::SIGXCPU {
            return " (SIGXCPU: it reached the CPU time limit of a process)";
        }
        if signal == libc::SIGXFSZ {
            return " (SIGXFSZ: it reached the file size limit)";
        }
    }
    let _ = signal;
    ""
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// An exit status is the program's to choose: 152 is named as what
    /// SIGXCPU gives inside the sandbox, and as what a program may exit
    /// with, not as a limit reached for certain.
    #[test]
    fn a_status_that_looks_like_a_limit_is_not_taken_for_one() {
        use std::os::unix::process::ExitStatusExt;
        let said = process_end(std::process::ExitStatus::from_raw(152 << 8));
        assert!(
            said.starts_with("exited with status 152: 128 + 24"),
            "{said}"
        );
        assert!(said.contains("or a program's own exit"), "{said}");
        let killed = process_end(std::process::ExitStatus::from_raw(libc::SIGXCPU));
        assert!(killed.contains("it reached the CPU time limit"), "{killed}");
        assert!(!killed.contains("own exit"), "{killed}");
        assert_eq!(
            process_end(std::process::ExitStatus::from_raw(3 << 8)),
            "exited with status 3"
        );
    }
    use crate::check::panics::Panic;
    use crate::check::protocol::{Answered, write_frame};

    /// Finding 4 of issue 41: what a student's process writes is copied
    /// into the report and the CSV, so anything it read could leave that
    /// way whole. The text of its replies (a panic's message and place,
    /// the names of answers it says it ran, an error, its hello) reaches
    /// the judge cut to a bound, however long it was sent.
    #[test]
    fn the_text_a_students_process_sends_is_cut_to_a_bound() {
        let long = "secret ".repeat(150_000);
        let mut frames = Vec::new();
        let hello = Reply::Hello {
            hello: Hello::ours(),
            comparison: false,
        };
        write_frame(&mut frames, &hello).expect("a frame");
        let panic = Reply::Answer {
            answer: Answered::Panicked(Panic {
                message: long.clone(),
                location: Some(long.clone()),
                file: Some(long.clone()),
            }),
            used: vec![long.clone(); 3],
            escaped: vec![long.clone()],
        };
        write_frame(&mut frames, &panic).expect("a frame");
        write_frame(
            &mut frames,
            &Reply::Answer {
                answer: Answered::Error(long.clone()),
                used: Vec::new(),
                escaped: Vec::new(),
            },
        )
        .expect("a frame");
        let folder = tempfile::tempdir().expect("a folder");
        let replies = folder.path().join("replies");
        std::fs::write(&replies, frames).expect("write");
        let spawn: Arc<Spawn> = Arc::new(move || {
            let mut command = std::process::Command::new("sh");
            // Replies whatever is asked, then waits to be killed.
            command.arg("-c").arg("cat \"$0\"; sleep 30").arg(&replies);
            Ok((command, Box::new(()) as Box<dyn std::any::Any + Send>))
        });
        let mut remote = Remote::new(spawn);
        let step = Step {
            chapter: 1,
            function: "f".into(),
            case: "c".into(),
        };
        let ask = Request::Image {
            chapter: 1,
            view: None,
        };
        let Ok(Reply::Answer {
            answer: Answered::Panicked(panic),
            used,
            escaped,
        }) = remote.ask(&ask, &step)
        else {
            panic!("not the panic sent");
        };
        let texts = [
            Some(panic.message),
            panic.location,
            panic.file,
            escaped.first().cloned(),
        ];
        for text in texts.iter().flatten().chain(&used) {
            assert!(text.len() < 4096, "{} bytes came through", text.len());
        }
        let Ok(Reply::Answer {
            answer: Answered::Error(error),
            ..
        }) = remote.ask(&ask, &step)
        else {
            panic!("not the error sent");
        };
        assert!(error.len() < 4096, "{} bytes came through", error.len());
    }
}
