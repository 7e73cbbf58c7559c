//! The crate's single error type. Every variant prints as one clear sentence.

use std::io;

/// Everything that can stop a `protolink` command.
///
/// `main` prints it as `error: <sentence>` and exits with status 1.
///
/// ```
/// let e = protolink::Error::Timeout { what: "the reply to request data 0x0008".into(), ms: 500 };
/// assert_eq!(e.to_string(), "no answer to the reply to request data 0x0008 within 500 ms");
/// ```
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An endpoint string that does not follow the syntax.
    #[error("invalid endpoint '{text}': {reason}")]
    Endpoint {
        /// The text as given.
        text: String,
        /// What is wrong with it.
        reason: String,
    },
    /// An endpoint could not be opened.
    #[error("cannot open {endpoint}: {source}")]
    Open {
        /// The endpoint, as written on the command line.
        endpoint: String,
        /// The operating system's reason.
        source: io::Error,
    },
    /// Reading from or writing to an open endpoint failed.
    #[error("{what} failed: {source}")]
    Io {
        /// What was being done, e.g. "writing to tcp:127.0.0.1:7001".
        what: String,
        /// The operating system's reason.
        source: io::Error,
    },
    /// The endpoint cannot carry bytes in this direction (e.g. writing to `file:`).
    #[error("{0}")]
    Unsupported(String),
    /// A command-line value that clap could not check by itself.
    #[error("{0}")]
    Usage(String),
    /// The device did not answer in time.
    #[error("no answer to {what} within {ms} ms")]
    Timeout {
        /// What was being waited for.
        what: String,
        /// The timeout.
        ms: u64,
    },
    /// The device answered, but not as expected.
    #[error("{0}")]
    Device(String),
    /// The box refused a change: it answered no (`E`, `I`, a TOAST, a counter) or read back
    /// something else. The sentence names the reason.
    #[error("{0}")]
    Refused(String),
    /// An AYDP message that could not be encoded, with what was being done.
    #[error("{what}: {source}")]
    Aydp {
        /// What was being done.
        what: String,
        /// Why encoding failed.
        source: aydp_proto::EncodeError,
    },
    /// An AOK client operation that failed, with what was being done.
    #[error("{what}: {source}")]
    Aok {
        /// What was being done.
        what: String,
        /// How the client's operation failed.
        source: aok_proto::ClientError,
    },
    /// A capture file ends inside a block (pcapng) or record (pcap): what `record` leaves
    /// when it is killed mid-write. The records before it were read whole.
    #[error(
        "reading the capture {path} failed at byte {offset}, after frame {frames}: the file ends inside the block that starts there"
    )]
    CaptureCut {
        /// The file, as given.
        path: String,
        /// Where the cut block starts: the length of the whole blocks before it.
        offset: u64,
        /// The records read before it.
        frames: u64,
    },
    /// A capture holds a block (pcapng) or record (pcap) that cannot be read: bytes
    /// overwritten, a length that points nowhere. The reader skipped it and reads on from the
    /// next whole one, or ends when none is left.
    #[error(
        "reading the capture {path} failed at byte {offset}, after frame {frames}: {}",
        damage(*.skipped, *.resumed)
    )]
    CaptureDamaged {
        /// The file, as given.
        path: String,
        /// Where the damaged block or record starts.
        offset: u64,
        /// The bytes skipped from there: to the next whole block or record, or to the end.
        skipped: u64,
        /// The records read before it.
        frames: u64,
        /// A whole block or record follows, and the reading goes on there.
        resumed: bool,
    },
    /// An export read some of its sources only in part, or not at all; the other sources were
    /// exported, and the summary says what each lost.
    #[error("{0}")]
    Incomplete(String),
    /// Writing the output (stdout) failed.
    #[error("writing the output failed: {0}")]
    Output(#[source] io::Error),
}

impl Error {
    /// The process exit status for this error: 2 for a command-line mistake, 1 otherwise.
    ///
    /// ```
    /// assert_eq!(protolink::Error::Usage("x".into()).exit_code(), 2);
    /// assert_eq!(protolink::Error::Refused("x".into()).exit_code(), 1);
    /// ```
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Usage(_) | Error::Endpoint { .. } => 2,
            _ => 1,
        }
    }
}

/// What [`Error::CaptureDamaged`] says of the bytes skipped.
fn damage(skipped: u64, resumed: bool) -> String {
    if resumed {
        format!(
            "the damaged {skipped} bytes from there were skipped, and the reading goes on after them"
        )
    } else {
        format!("the {skipped} bytes from there to the end hold no whole block or record")
    }
}

/// The crate's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
