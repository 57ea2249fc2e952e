//! The `lplace` command line. Everything lives in `lplace::cli`; this file only maps the outcome
//! to the process exit code.

fn main() -> std::process::ExitCode {
    lplace::cli::main()
}
