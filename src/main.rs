//! The `rocking` command: parse the arguments, run, map errors to an exit code.

fn main() -> std::process::ExitCode {
    rocking::cli::main()
}
