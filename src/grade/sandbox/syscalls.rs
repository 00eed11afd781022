//! The system calls no process of a run may make, as a seccomp program
//! bubblewrap installs before it starts the run's first program
//! (`--add-seccomp-fd FD`), for the build and the answers alike. Each
//! fails as it does where the kernel or the file system lacks it, which is
//! how programs that could use one are written to cope; no compiler,
//! linker or answer needs any of them.
//!
//! - The kernel's keyrings (`add_key`, `keyctl`, `request_key`: `ENOSYS`)
//!   are kept per user, not per namespace: every run is the same user
//!   (`nobody` when the grader is root), so a key one run added was read
//!   by the next, the next student's included, and outlived the grading.
//! - `fallocate` (`EOPNOTSUPP`, which glibc's `posix_fallocate` answers by
//!   writing the blocks) takes disk without writing a page, so without
//!   counting in what the run's processes wrote: a deleted file so
//!   filled, sent over a Unix socket and closed, held 5 GiB the disk
//!   limit could not see (`held::written`).
//! - `io_uring_setup` (`ENOSYS`): a ring's operations (an `fallocate`
//!   among them) pass no seccomp program, and its registered files are
//!   held where `/proc` does not list them.
//! - New namespaces (`unshare`, and `clone` with a `CLONE_NEW*` flag:
//!   `EPERM`, as without the privilege; `clone3`, whose flags sit in
//!   memory no seccomp program reads: `ENOSYS`, which glibc answers by
//!   calling `clone`). In a user namespace of its own, code with no
//!   privilege gets every capability over new mounts, cgroups and
//!   network devices: the mounts and limits of the sandbox held, but
//!   each is a way into the parts of the kernel where privilege bugs are
//!   found, and nothing a build or an answer does needs one.

/// Files holding the compiled programs (`struct sock_filter` after
/// `struct sock_filter`, as bubblewrap reads them), each at its start:
/// one program a failure, since a program fails every call it refuses the
/// same way. None where raylab has no seccomp compiler for the machine.
pub(super) fn filter_files() -> Result<Vec<std::fs::File>, String> {
    #[cfg(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    ))]
    {
        use crate::check::seccomp::{Call, compile, compile_flagged};
        use std::io::{Seek, Write};
        let new_namespace = (libc::CLONE_NEWNS
            | libc::CLONE_NEWCGROUP
            | libc::CLONE_NEWUTS
            | libc::CLONE_NEWIPC
            | libc::CLONE_NEWUSER
            | libc::CLONE_NEWPID
            | libc::CLONE_NEWNET) as u64;
        let programs = [
            compile(
                &[
                    Call::ADD_KEY,
                    Call::KEYCTL,
                    Call::REQUEST_KEY,
                    Call::IO_URING_SETUP,
                    Call::CLONE3,
                ],
                libc::ENOSYS,
            )?,
            compile(&[Call::FALLOCATE], libc::EOPNOTSUPP)?,
            compile_flagged(
                &[Call::UNSHARE],
                &[(Call::CLONE, new_namespace)],
                libc::EPERM,
            )?,
        ];
        programs
            .iter()
            .map(|program| {
                let mut bytes = Vec::with_capacity(program.len() * 8);
                for instruction in program {
                    bytes.extend_from_slice(&instruction.code.to_ne_bytes());
                    bytes.push(instruction.jt);
                    bytes.push(instruction.jf);
                    bytes.extend_from_slice(&instruction.k.to_ne_bytes());
                }
                let mut file = tempfile::tempfile()?;
                file.write_all(&bytes)?;
                file.rewind()?;
                // A copy numbered 3 or more: the child's standard streams
                // take 0 to 2.
                file.try_clone()
            })
            .collect::<std::io::Result<Vec<_>>>()
            .map_err(|error| error.to_string())
    }
    #[cfg(not(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    )))]
    Ok(Vec::new())
}
