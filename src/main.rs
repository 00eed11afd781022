fn main() {
    // `main_with` restores SIGPIPE and installs the clean-up signal
    // handlers first: a student workspace's `main` calls it too.
    std::process::exit(raylab::cli::main());
}
