//! The `bridgetwin` binary: parses arguments and dispatches (see `cli`).

fn main() -> std::process::ExitCode {
    bridgetwin::cli::main()
}
