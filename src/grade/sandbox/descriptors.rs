//! The files bubblewrap starts with: its options, read from a file of
//! their own, and nothing the grader holds.

use std::ffi::OsString;

/// Marks every descriptor from 3 on to close at exec: run between fork
/// and exec, so only async-signal-safe calls.
#[cfg(unix)]
pub(super) fn close_on_exec_from_3() -> std::io::Result<()> {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: close_range only changes the flags of this process's
        // descriptors.
        let marked = unsafe {
            libc::syscall(
                libc::SYS_close_range,
                3u32,
                u32::MAX,
                libc::CLOSE_RANGE_CLOEXEC,
            )
        };
        if marked == 0 {
            return Ok(());
        }
    }
    // Kernels before 5.11, and other systems: one descriptor at a time,
    // up to the process's limit.
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes only `limit`.
    if unsafe { libc::getrlimit(libc::RLIMIT_NOFILE, &mut limit) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    let most = i32::try_from(limit.rlim_cur.min(1 << 20)).unwrap_or(1 << 20);
    for fd in 3..most {
        // SAFETY: on a descriptor that is not open, fcntl fails, harmless.
        unsafe { libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC) };
    }
    Ok(())
}

/// A temporary file holding `options` separated by NUL bytes, read from
/// its start, for bubblewrap's `--args`.
pub(super) fn options_file(options: &[OsString]) -> std::io::Result<std::fs::File> {
    use std::io::{Seek, Write};
    let mut bytes = Vec::new();
    for option in options {
        bytes.extend_from_slice(option.as_encoded_bytes());
        bytes.push(0);
    }
    let mut file = tempfile::tempfile()?;
    file.write_all(&bytes)?;
    file.rewind()?;
    // A copy numbered 3 or more: the child's standard streams take 0 to 2.
    file.try_clone()
}
