//! The `protolink` binary: parse the command line, run, and turn any error into one sentence
//! ([`protolink::cli::main_with`] does all three).
//!
//! Exit status: 0 done (confirmed, or unconfirmed where the protocol gives no answer), 1 a
//! failure or a refusal by the box, 2 a command-line mistake.

use std::process::ExitCode;

fn main() -> ExitCode {
    ExitCode::from(protolink::cli::main_with(std::env::args_os()))
}
