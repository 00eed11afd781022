fn main() {
    // Rust programs ignore SIGPIPE, so once a reader such as `head` closes
    // the pipe, the next `println!` panics. Command-line tools are expected
    // to stop quietly instead: restore the default action of the signal.
    #[cfg(unix)]
    // SAFETY: called first thing, before any other thread exists; setting a
    // signal's action to its default installs no handler code.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Ctrl-C or a kill while an output is being written must not leave its
    // temporary file behind (see raylab::cleanup).
    raylab::cleanup::install_signal_handlers();
    std::process::exit(raylab::cli::main());
}
