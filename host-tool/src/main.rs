//! The `protolink` binary: parse the command line, run, and turn any error into one sentence.
//!
//! Exit status: 0 done (confirmed, or unconfirmed where the protocol gives no answer), 1 a
//! failure or a refusal by the box, 2 a command-line mistake.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;
use protolink::Error;
use protolink::cli::Cli;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            let _ = writeln!(
                std::io::stderr(),
                "{}",
                one_sentence(&e.render().to_string())
            );
            return ExitCode::from(2);
        }
    };
    match cli.run() {
        Ok(()) => ExitCode::SUCCESS,
        // The reader went away (`protolink decode ... | head`): not an error of ours.
        Err(Error::Output(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            let _ = writeln!(std::io::stderr(), "error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// Clap's message up to its usage block, on one line: `error: invalid value 'inf' for ...`.
fn one_sentence(rendered: &str) -> String {
    let head = rendered
        .split("\n\nUsage:")
        .next()
        .unwrap_or(rendered)
        .split("\n\nFor more information")
        .next()
        .unwrap_or(rendered);
    let mut line = head.split_whitespace().collect::<Vec<_>>().join(" ");
    if !line.starts_with("error:") {
        line.insert_str(0, "error: ");
    }
    line
}
