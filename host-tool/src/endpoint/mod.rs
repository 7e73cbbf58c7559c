//! Endpoints: one syntax for every subcommand, and the byte streams they open.
//!
//! | text | what it opens |
//! | --- | --- |
//! | `serial:/dev/ttyUSB0@921600` | a serial port, 8N1, at that baud rate (115200 when `@BAUD` is left out) |
//! | `tcp:127.0.0.1:7000` | a TCP connection to that address (the QEMU UART sockets) |
//! | `udp:5001` | a UDP socket bound to `127.0.0.1:5001`; `udp:0.0.0.0:5001` listens on every interface |
//! | `file:capture.bin` | a file, read from start to end (read-only) |
//! | `-` | standard input for reading, standard output for writing |
//! | `capture.bin` | a bare path: a file, as `file:` |
//!
//! A UDP endpoint answers the sender of the last datagram it received.
//!
//! | module | holds |
//! | --- | --- |
//! | [`address`] | the syntax: [`Endpoint`] from and to text, [`parse_local_addr`] |
//! | [`link`] | opening an endpoint as a byte stream: [`Link`], [`Input`] |
//! | [`udp_out`] | sending datagrams to a destination: a socket of its family, and the rule for the run's outcome |

pub(crate) mod address;
pub(crate) mod link;
pub(crate) mod udp_out;

pub use address::{DEFAULT_BAUD, Endpoint, parse_local_addr};
pub use link::{CONNECT_TIMEOUT, Input, Link, STDIN_CHUNKS};
