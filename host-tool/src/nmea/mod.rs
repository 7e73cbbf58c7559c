//! NMEA 0183 output, shared by `protolink nmea`: the sentences ([`sentence`]) and the bounded
//! fan-out of lines to TCP clients or UDP datagrams ([`fanout`]).
//!
//! | module | holds |
//! | --- | --- |
//! | [`sentence`] | the checksum, the frame, and `$GPRMC`, `$GPGGA`, `$PGRMZ`, `$POV`, `$LXWP0` from plain values |
//! | [`fanout`] | a TCP server that serves every client through a bounded queue, or a UDP sender |
//! | [`window`] | what a TCP client holds unread, from the window it advertises |

pub(crate) mod fanout;
pub mod sentence;
pub(crate) mod window;
