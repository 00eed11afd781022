//! Running the `raylab` binary from the integration tests, as a user would.
//! The `cli` test binary declares it once (`tests/cli/main.rs`) and its
//! modules say `use crate::common;`; not every module uses every helper,
//! hence the `dead_code` allowance.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `raylab args...` in `dir` and waits for it.
pub fn raylab(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run raylab")
}

/// The cargo running these tests, to build a workspace that `grade
/// --code` builds on later: without `CARGO_INCREMENTAL` (scripts/test.sh
/// sets it in CI), which the grader's sandbox clears and which cargo
/// counts in the profile of a path dependency. With it, every graded
/// build of a workspace built here would compile raylab again.
pub fn cargo() -> Command {
    let mut command = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    command.env_remove("CARGO_INCREMENTAL");
    judged_by_this_raylab(&mut command);
    command
}

/// Makes a student workspace's check, started by `command` (its binary's
/// `check`, its `cargo test`), judged by the raylab binary this suite
/// built: a student's build holds none of raylab's answers and hands the
/// judging to raylab's own binary, which it would otherwise build in
/// release.
pub fn judged_by_this_raylab(command: &mut Command) -> &mut Command {
    command.env("RAYLAB_JUDGE", env!("CARGO_BIN_EXE_raylab"))
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Runs `command`, failing the test instead of hanging when raylab blocks
/// (on a FIFO, say): the child is killed after two minutes, far beyond any
/// run here, so this is a guard, not a timing assertion.
pub fn output_or_blocked(mut command: Command) -> Output {
    use std::process::Stdio;
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run raylab");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("raylab blocked: {command:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// The `raylab` command, not yet run.
pub fn command(args: &[&str], dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_raylab"));
    command.args(args).current_dir(dir);
    command
}

/// Runs `raylab args...` with the hang guard of [`output_or_blocked`].
pub fn raylab_unblocked(args: &[&str], dir: &Path) -> Output {
    output_or_blocked(command(args, dir))
}

/// Runs `raylab args...` as on a nearly full disk: no file it writes may
/// grow past `bytes` (RLIMIT_FSIZE; the write fails with EFBIG instead of
/// the process being killed, as SIGXFSZ is ignored).
#[cfg(unix)]
pub fn raylab_with_file_size_limit(args: &[&str], dir: &Path, bytes: u64) -> Output {
    use std::os::unix::process::CommandExt;
    let mut command = command(args, dir);
    // SAFETY: between fork and exec only async-signal-safe calls are made.
    unsafe {
        command.pre_exec(move || {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit {
                rlim_cur: bytes as libc::rlim_t,
                rlim_max: bytes as libc::rlim_t,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    output_or_blocked(command)
}

/// Makes a FIFO (named pipe) at `path`.
#[cfg(unix)]
pub fn make_fifo(path: &Path) {
    use std::os::unix::ffi::OsStrExt;
    let name = std::ffi::CString::new(path.as_os_str().as_bytes()).expect("a path");
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o644) }, 0, "mkfifo");
}

/// The files in `dir` whose names start like raylab's temporary files.
pub fn temporary_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("list")
        .filter_map(|entry| entry.ok())
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with(".raylab-"))
        .collect()
}

/// A PNG file that declares `width` x `height` pixels but holds only its
/// header (a few dozen bytes): what a hostile file would send to make a
/// reader allocate gigabytes.
pub fn png_declaring(width: u32, height: u32) -> Vec<u8> {
    let mut bytes = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let mut header = Vec::new();
    header.extend(width.to_be_bytes());
    header.extend(height.to_be_bytes());
    header.extend([8, 2, 0, 0, 0]); // 8-bit RGB, deflate, no filter, no interlace
    for (kind, data) in [(*b"IHDR", header.as_slice()), (*b"IEND", &[][..])] {
        bytes.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        bytes.extend(&body);
        bytes.extend(crc32(&body).to_be_bytes());
    }
    bytes
}

/// `png` (a whole PNG file) with a chunk of `kind` holding `data` added
/// right after its header chunk.
pub fn with_chunk(png: &[u8], kind: [u8; 4], data: &[u8]) -> Vec<u8> {
    // The signature (8 bytes), then IHDR: length, type, 13 bytes, CRC.
    let after_header = 8 + 4 + 4 + 13 + 4;
    let mut bytes = png[..after_header].to_vec();
    bytes.extend((data.len() as u32).to_be_bytes());
    let mut body = kind.to_vec();
    body.extend(data);
    bytes.extend(&body);
    bytes.extend(crc32(&body).to_be_bytes());
    bytes.extend(&png[after_header..]);
    bytes
}

/// A zlib stream that inflates to `length` zero bytes (`length` one more
/// than a multiple of 258), about 13 bits for each 258 bytes: one block of
/// deflate's fixed Huffman codes, a literal zero and then copies of 258
/// bytes at distance 1 (RFC 1951, 3.2.6).
pub fn zeros_deflated(length: u64) -> Vec<u8> {
    assert_eq!((length - 1) % 258, 0, "{length} is not 1 + 258 k");
    let mut bits = BitWriter::default();
    bits.push(1, 1); // the last block
    bits.push(1, 2); // fixed Huffman codes
    let code = |bits: &mut BitWriter, code: u32, width: u32| {
        // Huffman codes go most significant bit first.
        for bit in (0..width).rev() {
            bits.push((code >> bit) & 1, 1);
        }
    };
    code(&mut bits, 0x30, 8); // literal 0
    for _ in 0..(length - 1) / 258 {
        code(&mut bits, 0xc5, 8); // length 258 (symbol 285)
        code(&mut bits, 0, 5); // distance 1
    }
    code(&mut bits, 0, 7); // end of block (symbol 256)
    let mut stream = vec![0x78, 0x01];
    stream.extend(bits.finish());
    // Adler-32 of zeros: a stays 1, b adds it once a byte.
    let adler = (((length % 65_521) as u32) << 16) | 1;
    stream.extend(adler.to_be_bytes());
    stream
}

/// Bits packed least significant first, as deflate packs them.
#[derive(Default)]
struct BitWriter {
    bytes: Vec<u8>,
    filled: u32,
}

impl BitWriter {
    fn push(&mut self, value: u32, width: u32) {
        for bit in 0..width {
            if self.filled % 8 == 0 {
                self.bytes.push(0);
            }
            if (value >> bit) & 1 == 1 {
                if let Some(last) = self.bytes.last_mut() {
                    *last |= 1 << (self.filled % 8);
                }
            }
            self.filled += 1;
        }
    }

    fn finish(self) -> Vec<u8> {
        self.bytes
    }
}

/// CRC-32 (IEEE), as PNG chunks use.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Runs `command` with its standard output a pipe whose reader has already
/// gone (`command | head -0`): the read end is closed before the child
/// starts, so its first write surely meets a closed pipe.
#[cfg(unix)]
pub fn output_into_closed_pipe(mut command: Command) -> Output {
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut ends = [0; 2];
    // SAFETY: `pipe` fills the two descriptors, which we then own.
    assert_eq!(unsafe { libc::pipe(ends.as_mut_ptr()) }, 0, "pipe");
    let (read_end, write_end) =
        unsafe { (OwnedFd::from_raw_fd(ends[0]), OwnedFd::from_raw_fd(ends[1])) };
    drop(read_end);
    command
        .stdout(std::process::Stdio::from(write_end))
        .output()
        .expect("run the command")
}
