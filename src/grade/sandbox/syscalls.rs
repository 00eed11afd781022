//! The system calls no process of a run may make, as a seccomp program
//! bubblewrap installs before it starts the run's first program
//! (`--seccomp FD`), for the build and the answers alike.
//!
//! The kernel's keyrings (`add_key`, `keyctl`, `request_key`) are kept
//! per user, not per namespace: every run is the same user (`nobody` when
//! the grader is root), so a key one run added was read by the next, the
//! next student's included, and outlived the grading. No compiler, linker
//! or answer needs them; each fails as if the kernel had none (`ENOSYS`),
//! which is how programs that could use one are written to cope.

/// A file holding the compiled program (`struct sock_filter` after
/// `struct sock_filter`, as bubblewrap reads them), at its start; `None`
/// where raylab has no seccomp compiler for the machine.
pub(super) fn filter_file() -> Result<Option<std::fs::File>, String> {
    #[cfg(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    ))]
    {
        use seccompiler::{BpfProgram, SeccompAction, SeccompFilter, TargetArch};
        use std::io::{Seek, Write};
        let arch = if cfg!(target_arch = "x86_64") {
            TargetArch::x86_64
        } else {
            TargetArch::aarch64
        };
        let rules = [libc::SYS_add_key, libc::SYS_keyctl, libc::SYS_request_key]
            .into_iter()
            .map(|call| (call, Vec::new()))
            .collect();
        let filter = SeccompFilter::new(
            rules,
            SeccompAction::Allow,
            SeccompAction::Errno(libc::ENOSYS as u32),
            arch,
        )
        .map_err(|error| error.to_string())?;
        let program: BpfProgram = filter
            .try_into()
            .map_err(|error: seccompiler::BackendError| error.to_string())?;
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
