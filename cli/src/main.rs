//! The `holo` binary: the command line is the `holo_cli` library.

fn main() -> std::process::ExitCode {
    holo_cli::main()
}
