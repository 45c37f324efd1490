//! The `shotdamp` command: parses arguments and hands over to [`shotdamp::cli`].

use std::process::ExitCode;

fn main() -> ExitCode {
    shotdamp::cli::main()
}
