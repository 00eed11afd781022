//! Seccomp programs for this machine, compiled from the system calls they
//! refuse, each call under every number a process can reach it by.
//!
//! On x86-64 a process enters the kernel through three tables: the 64-bit
//! one, i386's (`int 0x80`) and x32's (the 64-bit entry with bit 30 of the
//! number set, on kernels built with it and booted with `syscall.x32=y`).
//! A program that names only the 64-bit numbers lets the same call through
//! x32's. The programs compiled here kill a process that calls through
//! another architecture's table (seccompiler's check of `arch`, which
//! i386's fails), and refuse each call under its x32 number too: most
//! calls have the 64-bit number with the bit set ("common" in the kernel's
//! `arch/x86/entry/syscalls/syscall_64.tbl`), a few have x32 numbers of
//! their own (`execve` is 520 there, `execveat` 545).
#![cfg(all(
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
))]

use seccompiler::{BpfProgram, SeccompAction, SeccompFilter, TargetArch};

/// Bit 30 of a call's number selects x32's table.
#[cfg(target_arch = "x86_64")]
const X32_BIT: i64 = 0x4000_0000;

/// A system call, by its numbers in the tables of this machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Call {
    native: i64,
    x32: Option<i64>,
}

impl Call {
    /// A call whose x32 number is its 64-bit number (on x86-64).
    const fn common(native: i64) -> Call {
        Call {
            native,
            x32: x32_number(native),
        }
    }

    pub(crate) const EXECVE: Call = Call {
        native: libc::SYS_execve,
        x32: x32_number(520),
    };
    pub(crate) const EXECVEAT: Call = Call {
        native: libc::SYS_execveat,
        x32: x32_number(545),
    };
    pub(crate) const ADD_KEY: Call = Call::common(libc::SYS_add_key);
    pub(crate) const KEYCTL: Call = Call::common(libc::SYS_keyctl);
    pub(crate) const REQUEST_KEY: Call = Call::common(libc::SYS_request_key);
    pub(crate) const FALLOCATE: Call = Call::common(libc::SYS_fallocate);
    pub(crate) const IO_URING_SETUP: Call = Call::common(libc::SYS_io_uring_setup);
    pub(crate) const UNSHARE: Call = Call::common(libc::SYS_unshare);
    pub(crate) const CLONE: Call = Call::common(libc::SYS_clone);
    pub(crate) const CLONE3: Call = Call::common(libc::SYS_clone3);

    /// Every number the call is reached by on this machine.
    pub(crate) fn numbers(self) -> impl Iterator<Item = i64> {
        std::iter::once(self.native).chain(self.x32)
    }
}

#[cfg(target_arch = "x86_64")]
const fn x32_number(number: i64) -> Option<i64> {
    Some(X32_BIT | number)
}

#[cfg(not(target_arch = "x86_64"))]
const fn x32_number(_: i64) -> Option<i64> {
    None
}

/// A program that fails each refused call with `errno`, kills a process
/// calling through another architecture's table, and lets every other
/// call through.
pub(crate) fn compile(refused: &[Call], errno: i32) -> Result<BpfProgram, String> {
    compile_flagged(refused, &[], errno)
}

/// [`compile`], also failing each call of `flagged` whose first argument
/// has any bit of its mask set (`clone` asking for a new namespace).
pub(crate) fn compile_flagged(
    refused: &[Call],
    flagged: &[(Call, u64)],
    errno: i32,
) -> Result<BpfProgram, String> {
    use seccompiler::{SeccompCmpArgLen, SeccompCmpOp, SeccompCondition, SeccompRule};
    let arch = if cfg!(target_arch = "x86_64") {
        TargetArch::x86_64
    } else {
        TargetArch::aarch64
    };
    // A call with no rule is refused whatever its arguments.
    let mut rules: std::collections::BTreeMap<i64, Vec<SeccompRule>> = refused
        .iter()
        .flat_map(|call| call.numbers())
        .map(|number| (number, Vec::new()))
        .collect();
    for (call, mask) in flagged {
        for number in call.numbers() {
            // One rule per bit: a rule matches when its argument, masked,
            // equals the value, so "any bit set" is one rule per bit.
            let mut bit_rules = Vec::new();
            for bit in (0..64).map(|bit| 1u64 << bit).filter(|bit| mask & bit != 0) {
                let condition = SeccompCondition::new(
                    0,
                    SeccompCmpArgLen::Qword,
                    SeccompCmpOp::MaskedEq(bit),
                    bit,
                )
                .map_err(|error| error.to_string())?;
                bit_rules.push(SeccompRule::new(vec![condition]).map_err(|e| e.to_string())?);
            }
            rules.insert(number, bit_rules);
        }
    }
    let errno = u32::try_from(errno).map_err(|_| format!("{errno} is not an errno"))?;
    let filter = SeccompFilter::new(
        rules,
        SeccompAction::Allow,
        SeccompAction::Errno(errno),
        arch,
    )
    .map_err(|error| error.to_string())?;
    filter
        .try_into()
        .map_err(|error: seccompiler::BackendError| error.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a program answers for one call, run as the kernel runs it on
    /// `struct seccomp_data` (number, arch, instruction pointer, six
    /// arguments), for the instructions seccompiler emits.
    fn verdict(program: &BpfProgram, arch: u32, number: i64, arguments: [u64; 6]) -> u32 {
        let mut data = Vec::with_capacity(64);
        data.extend_from_slice(&(number as u32).to_ne_bytes());
        data.extend_from_slice(&arch.to_ne_bytes());
        data.extend_from_slice(&0u64.to_ne_bytes());
        for argument in arguments {
            data.extend_from_slice(&argument.to_ne_bytes());
        }
        let (mut accumulator, mut at) = (0u32, 0usize);
        loop {
            let instruction = &program[at];
            let code = u32::from(instruction.code);
            at += 1;
            match (code & 0x07, code) {
                // BPF_LD | BPF_W | BPF_ABS
                (0x00, 0x20) => {
                    let offset = instruction.k as usize;
                    let word: [u8; 4] = data[offset..offset + 4].try_into().expect("4 bytes");
                    accumulator = u32::from_ne_bytes(word);
                }
                // BPF_ALU | BPF_AND | BPF_K
                (0x04, 0x54) => accumulator &= instruction.k,
                (0x05, _) => {
                    let taken = match code & 0xf0 {
                        0x00 => {
                            at += instruction.k as usize;
                            continue;
                        }
                        0x10 => accumulator == instruction.k,
                        0x20 => accumulator > instruction.k,
                        0x30 => accumulator >= instruction.k,
                        0x40 => accumulator & instruction.k != 0,
                        other => panic!("jump {other:#x} not interpreted"),
                    };
                    at += usize::from(if taken {
                        instruction.jt
                    } else {
                        instruction.jf
                    });
                }
                // BPF_RET | BPF_K
                (0x06, 0x06) => return instruction.k,
                _ => panic!("instruction {code:#x} not interpreted"),
            }
        }
    }

    const ALLOW: u32 = libc::SECCOMP_RET_ALLOW;

    fn native_arch() -> u32 {
        if cfg!(target_arch = "x86_64") {
            62 | 0x8000_0000 | 0x4000_0000
        } else {
            183 | 0x8000_0000 | 0x4000_0000
        }
    }

    /// `clone` is refused only with one of the flagged bits in its first
    /// argument: a thread or a process starts, a namespace does not.
    #[test]
    fn a_flagged_call_is_refused_only_with_a_flag_set() {
        let refused = libc::SECCOMP_RET_ERRNO | libc::EPERM as u32;
        let mask = (libc::CLONE_NEWUSER | libc::CLONE_NEWNS) as u64;
        let program = compile_flagged(&[Call::UNSHARE], &[(Call::CLONE, mask)], libc::EPERM)
            .expect("it compiles");
        let arch = native_arch();
        let with_flags = |flags: i32| [flags as u64, 0, 0, 0, 0, 0];
        let thread = libc::CLONE_VM | libc::CLONE_FS | libc::CLONE_FILES | libc::CLONE_THREAD;
        for number in Call::CLONE.numbers() {
            assert_eq!(verdict(&program, arch, number, with_flags(thread)), ALLOW);
            assert_eq!(
                verdict(&program, arch, number, with_flags(libc::SIGCHLD)),
                ALLOW
            );
            for flags in [libc::CLONE_NEWUSER, libc::CLONE_NEWNS | libc::SIGCHLD] {
                assert_eq!(verdict(&program, arch, number, with_flags(flags)), refused);
            }
        }
        for number in Call::UNSHARE.numbers() {
            assert_eq!(verdict(&program, arch, number, with_flags(0)), refused);
        }
        assert_eq!(
            verdict(&program, arch, libc::SYS_getpid, with_flags(0)),
            ALLOW
        );
    }

    #[test]
    fn a_refused_call_is_refused_by_every_number_and_no_other_call_is() {
        let errno = libc::ENOSYS;
        let refused = libc::SECCOMP_RET_ERRNO | errno as u32;
        let program = compile(&[Call::EXECVE, Call::ADD_KEY], errno).expect("it compiles");
        let arch = native_arch();
        let anything = [7; 6];
        for call in [Call::EXECVE, Call::ADD_KEY] {
            for number in call.numbers() {
                assert_eq!(
                    verdict(&program, arch, number, anything),
                    refused,
                    "{number:#x}"
                );
            }
        }
        assert_eq!(verdict(&program, arch, libc::SYS_getpid, anything), ALLOW);
        let expected = if cfg!(target_arch = "x86_64") { 2 } else { 1 };
        assert_eq!(Call::EXECVE.numbers().count(), expected);
        #[cfg(target_arch = "x86_64")]
        {
            // x32's own execve, and another call under x32's number.
            assert_eq!(verdict(&program, arch, X32_BIT | 520, anything), refused);
            assert_eq!(verdict(&program, arch, X32_BIT | 248, anything), refused);
            assert_eq!(
                verdict(&program, arch, X32_BIT | libc::SYS_getpid, anything),
                ALLOW
            );
            // i386's table (AUDIT_ARCH_I386) kills the process.
            let i386 = 3 | 0x4000_0000;
            assert_eq!(
                verdict(&program, i386, 11, anything),
                libc::SECCOMP_RET_KILL_PROCESS
            );
        }
    }
}
