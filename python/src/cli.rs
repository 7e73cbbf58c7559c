//! `python -m protolink decode ...`: the host tool's own command line, so that the output is
//! byte for byte what `protolink decode` prints.

use pyo3::prelude::*;

/// Runs `protolink ARGS...` (`args` without the program name) as the binary does, with the GIL
/// released, and returns its exit status (0 done, 1 a failure, 2 a command-line mistake).
#[pyfunction]
pub(crate) fn run_cli(py: Python<'_>, args: Vec<String>) -> u8 {
    let argv: Vec<String> = std::iter::once("protolink".to_owned())
        .chain(args)
        .collect();
    py.detach(|| protolink::cli::main_with(argv))
}
