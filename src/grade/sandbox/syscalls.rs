//! The system calls no process of a run may make, as a seccomp program
//! bubblewrap installs before it starts the run's first program
//! (`--seccomp FD`), for the build and the answers alike. Each fails with
//! `ENOSYS`, as if the kernel had no such call, which is how programs that
//! could use one are written to cope; no compiler, linker or answer needs
//! any of them.
//!
//! The kernel's keyrings (`add_key`, `keyctl`, `request_key`) are kept
//! per user, not per namespace: every run is the same user (`nobody` when
//! the grader is root), so a key one run added was read by the next, the
//! next student's included, and outlived the grading.

/// A file holding the compiled program (`struct sock_filter` after
/// `struct sock_filter`, as bubblewrap reads them), at its start; `None`
/// where raylab has no seccomp compiler for the machine.
pub(super) fn filter_file() -> Result<Option<std::fs::File>, String> {
    #[cfg(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    ))]
    {
        use crate::check::seccomp::{Call, compile};
        use std::io::{Seek, Write};
        let program = compile(
            &[Call::ADD_KEY, Call::KEYCTL, Call::REQUEST_KEY],
            libc::ENOSYS,
        )?;
        let mut bytes = Vec::with_capacity(program.len() * 8);
        for instruction in &program {
            bytes.extend_from_slice(&instruction.code.to_ne_bytes());
            bytes.push(instruction.jt);
            bytes.push(instruction.jf);
            bytes.extend_from_slice(&instruction.k.to_ne_bytes());
        }
        let write = || -> std::io::Result<std::fs::File> {
            let mut file = tempfile::tempfile()?;
            file.write_all(&bytes)?;
            file.rewind()?;
            // A copy numbered 3 or more: the child's standard streams take 0 to 2.
            file.try_clone()
        };
        write().map(Some).map_err(|error| error.to_string())
    }
    #[cfg(not(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    )))]
    Ok(None)
}
