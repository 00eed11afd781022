//! A student's answering process may not start programs.
//!
//! The judge trusts an answer only as the work of the process that gave
//! it: raylab counts, inside that process, every call to its own answers
//! (`crate::answer_key`). A program started from a chapter escapes that
//! count: raylab's own binary asked to `probe` a ray, or the student's own
//! binary asked for a command that runs raylab's exact intersections. So
//! before it reads its first question, `serve` installs a seccomp filter
//! that makes `execve` and `execveat` fail with `EPERM` for every thread
//! of the process and every thread it starts later; a filter cannot be
//! removed once installed. Forking stays allowed: a copy of the process
//! is the same student code, under the same filter.

/// Why starting programs could not be forbidden.
#[derive(Debug, thiserror::Error)]
#[error("cannot forbid this process to start programs: {0}")]
pub struct NoProgramsError(String);

/// Forbids this process, and every thread and process it starts, to run
/// another program. Linux on x86-64 and AArch64 only; elsewhere it does
/// nothing (the sandbox of `grade --code` is Linux's bubblewrap anyway).
pub fn forbid_starting_programs() -> Result<(), NoProgramsError> {
    #[cfg(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    ))]
    {
        use super::seccomp::{Call, compile};
        let program =
            compile(&[Call::EXECVE, Call::EXECVEAT], libc::EPERM).map_err(NoProgramsError)?;
        seccompiler::apply_filter_all_threads(&program)
            .map_err(|error| NoProgramsError(error.to_string()))?;
    }
    Ok(())
}

#[cfg(all(
    test,
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
))]
mod tests {
    /// Set in the child run of [`a_process_that_forbade_programs_cannot_start_one`].
    const CHILD: &str = "RAYLAB_TEST_FORBID_PROGRAMS_CHILD";

    /// The filter applies to the whole process, so the test runs itself
    /// again as a child: there, after the filter, starting `true` (and the
    /// test binary itself, from a thread started later) must fail with
    /// permission denied; a thread started before must not escape it.
    #[test]
    fn a_process_that_forbade_programs_cannot_start_one() {
        if std::env::var_os(CHILD).is_some() {
            let before = std::thread::spawn(|| {
                std::thread::sleep(std::time::Duration::from_millis(200));
                std::process::Command::new("true").status().map(|_| ())
            });
            super::forbid_starting_programs().expect("the filter installs");
            let here = std::process::Command::new("true").status().map(|_| ());
            let itself = std::thread::spawn(|| {
                std::process::Command::new(std::env::current_exe().expect("its path"))
                    .arg("--list")
                    .output()
                    .map(|_| ())
            })
            .join()
            .expect("the thread ends");
            let before = before.join().expect("the thread ends");
            for (what, result) in [("here", here), ("itself", itself), ("before", before)] {
                let denied = result
                    .as_ref()
                    .is_err_and(|error| error.kind() == std::io::ErrorKind::PermissionDenied);
                assert!(denied, "{what}: {result:?}");
            }
            return;
        }
        let child = std::process::Command::new(std::env::current_exe().expect("its path"))
            .args([
                "--exact",
                "check::no_programs::tests::a_process_that_forbade_programs_cannot_start_one",
            ])
            .env(CHILD, "1")
            .output()
            .expect("the test binary runs");
        let text = String::from_utf8_lossy(&child.stdout).into_owned()
            + &String::from_utf8_lossy(&child.stderr);
        assert!(child.status.success(), "{text}");
        assert!(text.contains("1 passed"), "{text}");
        // Outside the filter, starting a program works: the child's
        // failures are the filter's.
        assert!(std::process::Command::new("true").status().is_ok());
    }
}
