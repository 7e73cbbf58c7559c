//! Capture files: pcapng written by `record`, pcapng and classic pcap read by `decode` and
//! `replay`, through the `pcap-file` crate (the file format is never hand-written here).
//!
//! UDP is stored as real Ethernet/IPv4/UDP packets (MAC addresses zero, the real addresses and
//! ports, UDP checksum 0 = "not computed", which IPv4 allows), so Wireshark shows them as they
//! were on the wire. Byte streams (`serial:`, `tcp:`, `file:`, stdin) are stored as timestamped
//! chunks on an interface whose link type names the protocol:
//!
//! | link type | number | carries |
//! | --- | --- | --- |
//! | `USER0` | 147 | AEOLUS byte stream (a UART) |
//! | `USER1` | 148 | AYDP byte stream, the document's profile (`spec`) |
//! | `USER2` | 149 | AYDP byte stream, the released software's profile (`reference`) |
//! | `USER3` | 150 | AOK, PC -> device (commands) |
//! | `USER4` | 151 | AOK, device -> PC (debug values, acks, replies) |
//! | `USER5` | 152 | GDL90 byte stream |
//!
//! Reading, UDP (and TCP) payloads are found on Ethernet, raw IPv4, BSD loopback and Linux
//! cooked links; the protocol comes from the port (5001/5002 AEOLUS, 4000 GDL90, 6321 AYDP) or
//! the link type above.

use std::net::SocketAddrV4;
use std::time::Duration;

use crate::error::Error;
use crate::proto::{ProfileArg, Proto, Side};

mod read;
mod resync;
mod write;

pub use read::{CaptureReader, file_is_capture, is_capture};
pub use write::{CaptureWriter, MAX_UDP_PAYLOAD, ethernet_udp};

/// UDP port of AEOLUS telemetry (box -> app).
pub const PORT_AEOLUS_OUT: u16 = 5001;
/// UDP port of AEOLUS commands (app -> box).
pub(crate) const PORT_AEOLUS_IN: u16 = 5002;
/// UDP port of GDL90 for EFB apps.
pub(crate) const PORT_GDL90: u16 = 4000;
/// TCP port of the AYDP reference software.
pub(crate) const PORT_AYDP: u16 = 6321;

/// The largest payload stored in one record.
pub(crate) const SNAPLEN: u32 = 65_535;

/// What a byte-stream interface carries, named by its link type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct StreamKind {
    /// The protocol.
    pub(crate) proto: Proto,
    /// The AYDP profile (only for AYDP).
    pub(crate) profile: ProfileArg,
    /// Who sent the AOK bytes (only for AOK).
    pub(crate) side: Side,
}

impl StreamKind {
    /// The link type number (USER0 = 147 ...) for this stream.
    pub(crate) fn link_type(&self) -> u32 {
        match (self.proto, self.profile, self.side) {
            (Proto::Aeolus, _, _) => 147,
            (Proto::Aydp, ProfileArg::Spec, _) => 148,
            (Proto::Aydp, ProfileArg::Reference, _) => 149,
            (Proto::Aok, _, Side::Pc) => 150,
            (Proto::Aok, _, Side::Device) => 151,
            (Proto::Gdl90, _, _) => 152,
        }
    }

    /// The stream a link type number names, if it is one of ours. Fields that do not apply
    /// take their defaults (spec profile, device side).
    pub(crate) fn from_link_type(link: u32) -> Option<Self> {
        let (proto, profile, side) = match link {
            147 => (Proto::Aeolus, ProfileArg::Spec, Side::Device),
            148 => (Proto::Aydp, ProfileArg::Spec, Side::Device),
            149 => (Proto::Aydp, ProfileArg::Reference, Side::Device),
            150 => (Proto::Aok, ProfileArg::Spec, Side::Pc),
            151 => (Proto::Aok, ProfileArg::Spec, Side::Device),
            152 => (Proto::Gdl90, ProfileArg::Spec, Side::Device),
            _ => return None,
        };
        Some(StreamKind {
            proto,
            profile,
            side,
        })
    }
}

/// The protocol a UDP or TCP port carries, if it is one of ours.
pub(crate) fn proto_for_port(port: u16) -> Option<Proto> {
    match port {
        PORT_AEOLUS_OUT | PORT_AEOLUS_IN => Some(Proto::Aeolus),
        PORT_GDL90 => Some(Proto::Gdl90),
        PORT_AYDP => Some(Proto::Aydp),
        _ => None,
    }
}

/// The IP transport of a payload found in a capture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Transport {
    /// A UDP datagram.
    Udp,
    /// A TCP segment (no reassembly: payloads in capture order).
    Tcp,
}

/// What one capture record holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Payload {
    /// A UDP datagram or TCP segment's payload, with its addresses.
    Ip {
        /// UDP or TCP.
        transport: Transport,
        /// Sender.
        src: SocketAddrV4,
        /// Receiver.
        dst: SocketAddrV4,
        /// The payload bytes.
        bytes: Vec<u8>,
    },
    /// A chunk of a byte stream on one of our link types.
    Stream {
        /// The interface it was captured on (pcapng), 0 for classic pcap.
        interface: u32,
        /// What the stream carries.
        kind: StreamKind,
        /// The bytes.
        bytes: Vec<u8>,
    },
    /// Anything else (another protocol, a link type we do not read): skipped and counted.
    Other,
}

/// One record of a capture.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    /// 1-based record number, as Wireshark numbers frames.
    pub(crate) frame: u64,
    /// Arrival time since the Unix epoch.
    pub(crate) time: Duration,
    /// What it holds.
    pub(crate) payload: Payload,
}

/// A `pcap-file` error as one of ours, saying what was being done.
pub(crate) fn pcap_err(what: String) -> impl Fn(pcap_file::PcapError) -> Error {
    move |e| match e {
        pcap_file::PcapError::IoError(source) => Error::Io {
            what: what.clone(),
            source,
        },
        other => Error::Io {
            what: what.clone(),
            source: std::io::Error::other(other.to_string()),
        },
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn link_type_example() -> Result<(), Box<dyn std::error::Error>> {
        use crate::proto::{ProfileArg, Proto, Side};
        let k = StreamKind {
            proto: Proto::Aok,
            profile: ProfileArg::Spec,
            side: Side::Device,
        };
        assert_eq!(k.link_type(), 151);
        assert_eq!(StreamKind::from_link_type(151), Some(k));
        Ok(())
    }

    #[test]
    fn proto_for_port_example() -> Result<(), Box<dyn std::error::Error>> {
        use crate::proto::Proto;
        assert_eq!(proto_for_port(5001), Some(Proto::Aeolus));
        assert_eq!(proto_for_port(53), None);
        Ok(())
    }
}
