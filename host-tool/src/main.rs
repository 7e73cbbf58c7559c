//! The `protolink` binary: parse the command line, run, and turn any error into one sentence.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;
use protolink::Error;
use protolink::cli::Cli;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.run() {
        Ok(()) => ExitCode::SUCCESS,
        // The reader went away (`protolink decode ... | head`): not an error of ours.
        Err(Error::Output(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "error: {e}");
            ExitCode::FAILURE
        }
    }
}
