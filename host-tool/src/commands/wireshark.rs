//! `protolink wireshark`: prints the Lua dissector that [`crate::wireshark`] generates from
//! the protocol crates' layout tables.

use clap::Args;

use crate::error::Result;
use crate::render::Out;

/// Arguments of `protolink wireshark` (none: the dissector goes to stdout).
#[derive(Debug, Clone, Args)]
pub(crate) struct WiresharkArgs {}

/// Runs `protolink wireshark`: the dissector on stdout.
///
/// # Errors
/// Writing the output, or a layout the generator does not know.
pub(crate) fn run(_args: &WiresharkArgs) -> Result<()> {
    let mut out = Out::new();
    let text = crate::wireshark::lua()?;
    for line in text.lines() {
        out.line(line)?;
    }
    out.flush()
}
