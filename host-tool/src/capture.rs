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

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::net::{Ipv4Addr, SocketAddrV4};
use std::path::Path;
use std::time::Duration;

use pcap_file::DataLink;
use pcap_file::pcap::PcapReader;
use pcap_file::pcapng::blocks::Block;
use pcap_file::pcapng::blocks::enhanced_packet::EnhancedPacketBlock;
use pcap_file::pcapng::blocks::interface_description::{
    InterfaceDescriptionBlock, InterfaceDescriptionOption,
};
use pcap_file::pcapng::{PcapNgReader, PcapNgWriter};

use crate::decode::{ProfileArg, Proto, Side};
use crate::error::{Error, Result};

/// UDP port of AEOLUS telemetry (box -> app).
pub const PORT_AEOLUS_OUT: u16 = 5001;
/// UDP port of AEOLUS commands (app -> box).
pub const PORT_AEOLUS_IN: u16 = 5002;
/// UDP port of GDL90 for EFB apps.
pub const PORT_GDL90: u16 = 4000;
/// TCP port of the AYDP reference software.
pub const PORT_AYDP: u16 = 6321;

/// The largest payload stored in one record.
pub const SNAPLEN: u32 = 65_535;

/// What a byte-stream interface carries, named by its link type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StreamKind {
    /// The protocol.
    pub proto: Proto,
    /// The AYDP profile (only for AYDP).
    pub profile: ProfileArg,
    /// Who sent the AOK bytes (only for AOK).
    pub side: Side,
}

/// The link-type mapping, `(USER n, link type number, what it carries)`, for docs and the
/// dissector.
pub const LINK_TYPES: [(u32, &str); 6] = [
    (147, "AEOLUS byte stream"),
    (148, "AYDP byte stream, spec profile"),
    (149, "AYDP byte stream, reference profile"),
    (150, "AOK, PC -> device"),
    (151, "AOK, device -> PC"),
    (152, "GDL90 byte stream"),
];

impl StreamKind {
    /// The link type number (USER0 = 147 ...) for this stream.
    ///
    /// ```
    /// use protolink::capture::StreamKind;
    /// use protolink::decode::{Proto, ProfileArg, Side};
    /// let k = StreamKind { proto: Proto::Aok, profile: ProfileArg::Spec, side: Side::Device };
    /// assert_eq!(k.link_type(), 151);
    /// assert_eq!(StreamKind::from_link_type(151), Some(k));
    /// ```
    pub fn link_type(&self) -> u32 {
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
    pub fn from_link_type(link: u32) -> Option<Self> {
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

    /// The same stream with the fields that do not apply set to their defaults.
    pub fn normalized(self) -> Self {
        Self::from_link_type(self.link_type()).unwrap_or(self)
    }
}

/// The protocol a UDP or TCP port carries, if it is one of ours.
///
/// ```
/// use protolink::capture::proto_for_port;
/// use protolink::decode::Proto;
/// assert_eq!(proto_for_port(5001), Some(Proto::Aeolus));
/// assert_eq!(proto_for_port(53), None);
/// ```
pub fn proto_for_port(port: u16) -> Option<Proto> {
    match port {
        PORT_AEOLUS_OUT | PORT_AEOLUS_IN => Some(Proto::Aeolus),
        PORT_GDL90 => Some(Proto::Gdl90),
        PORT_AYDP => Some(Proto::Aydp),
        _ => None,
    }
}

/// The IP transport of a payload found in a capture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Transport {
    /// A UDP datagram.
    Udp,
    /// A TCP segment (no reassembly: payloads in capture order).
    Tcp,
}

/// What one capture record holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Payload {
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
    pub frame: u64,
    /// Arrival time since the Unix epoch.
    pub time: Duration,
    /// What it holds.
    pub payload: Payload,
}

// ---------------------------------------------------------------------------------------------
// Writing

/// A pcapng file being written, record by record (nothing is held in memory beyond a buffer).
pub struct CaptureWriter {
    writer: PcapNgWriter<BufWriter<File>>,
    path: String,
}

impl std::fmt::Debug for CaptureWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CaptureWriter")
            .field("path", &self.path)
            .finish()
    }
}

fn pcap_err(what: String) -> impl Fn(pcap_file::PcapError) -> Error {
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

impl CaptureWriter {
    /// Creates `path` with one interface of link type `link` (Ethernet for UDP, or a
    /// [`StreamKind::link_type`]), named `name`.
    ///
    /// # Errors
    /// Creating or writing the file.
    pub fn create(path: &Path, link: u32, name: &str) -> Result<Self> {
        let shown = path.display().to_string();
        let file = File::create(path).map_err(|source| Error::Open {
            endpoint: shown.clone(),
            source,
        })?;
        let mut writer = PcapNgWriter::new(BufWriter::new(file))
            .map_err(pcap_err(format!("writing {shown}")))?;
        let mut idb = InterfaceDescriptionBlock::new(DataLink::from(link), SNAPLEN);
        // pcap-file 2 writes timestamps in nanoseconds: say so, or readers assume µs.
        idb.options.push(InterfaceDescriptionOption::IfTsResol(9));
        idb.options
            .push(InterfaceDescriptionOption::IfName(name.to_owned().into()));
        writer
            .write_block(&Block::InterfaceDescription(idb))
            .map_err(pcap_err(format!("writing {shown}")))?;
        Ok(CaptureWriter {
            writer,
            path: shown,
        })
    }

    fn packet(&mut self, time: Duration, data: &[u8]) -> Result<()> {
        let epb = EnhancedPacketBlock {
            interface_id: 0,
            timestamp: time,
            original_len: data.len() as u32,
            data: data.into(),
            options: vec![],
        };
        self.writer
            .write_block(&Block::EnhancedPacket(epb))
            .map_err(pcap_err(format!("writing {}", self.path)))?;
        Ok(())
    }

    /// Writes one UDP datagram as Ethernet/IPv4/UDP (on an Ethernet interface).
    ///
    /// # Errors
    /// Writing the file.
    pub fn udp(
        &mut self,
        time: Duration,
        src: SocketAddrV4,
        dst: SocketAddrV4,
        payload: &[u8],
    ) -> Result<()> {
        let frame = ethernet_udp(src, dst, payload);
        self.packet(time, &frame)
    }

    /// Writes one chunk of a byte stream (on a stream interface).
    ///
    /// # Errors
    /// Writing the file.
    pub fn chunk(&mut self, time: Duration, bytes: &[u8]) -> Result<()> {
        self.packet(time, bytes)
    }

    /// Flushes what is buffered to the file.
    ///
    /// # Errors
    /// Writing the file.
    pub fn flush(&mut self) -> Result<()> {
        let path = self.path.clone();
        self.writer.get_mut().flush().map_err(|source| Error::Io {
            what: format!("writing {path}"),
            source,
        })
    }
}

/// The largest UDP payload one IPv4 packet holds.
pub const MAX_UDP_PAYLOAD: usize = 65_507;

/// An Ethernet II frame (MACs zero) holding an IPv4 packet holding a UDP datagram; the payload
/// is cut at [`MAX_UDP_PAYLOAD`].
///
/// ```
/// use std::net::SocketAddrV4;
/// let src: SocketAddrV4 = "127.0.0.1:40000".parse().unwrap();
/// let dst: SocketAddrV4 = "127.0.0.1:5001".parse().unwrap();
/// let f = protolink::capture::ethernet_udp(src, dst, b"hi");
/// assert_eq!(f.len(), 14 + 20 + 8 + 2);
/// assert_eq!(&f[12..14], &[0x08, 0x00]);
/// assert_eq!(&f[36..38], &5001u16.to_be_bytes());
/// ```
pub fn ethernet_udp(src: SocketAddrV4, dst: SocketAddrV4, payload: &[u8]) -> Vec<u8> {
    let payload = &payload[..payload.len().min(MAX_UDP_PAYLOAD)];
    let udp_len = 8 + payload.len();
    let ip_len = 20 + udp_len;
    let mut f = Vec::with_capacity(14 + ip_len);
    f.extend_from_slice(&[0; 12]);
    f.extend_from_slice(&[0x08, 0x00]);
    let mut ip = [0u8; 20];
    ip[0] = 0x45;
    ip[2..4].copy_from_slice(&(ip_len as u16).to_be_bytes());
    ip[6] = 0x40; // don't fragment
    ip[8] = 64; // TTL
    ip[9] = 17; // UDP
    ip[12..16].copy_from_slice(&src.ip().octets());
    ip[16..20].copy_from_slice(&dst.ip().octets());
    let sum = ipv4_checksum(&ip);
    ip[10..12].copy_from_slice(&sum.to_be_bytes());
    f.extend_from_slice(&ip);
    f.extend_from_slice(&src.port().to_be_bytes());
    f.extend_from_slice(&dst.port().to_be_bytes());
    f.extend_from_slice(&(udp_len as u16).to_be_bytes());
    f.extend_from_slice(&[0, 0]);
    f.extend_from_slice(payload);
    f
}

fn ipv4_checksum(header: &[u8]) -> u16 {
    let mut sum: u32 = header
        .chunks(2)
        .map(|w| u32::from(u16::from_be_bytes([w[0], *w.get(1).unwrap_or(&0)])))
        .sum();
    while sum > 0xFFFF {
        sum = (sum & 0xFFFF) + (sum >> 16);
    }
    !(sum as u16)
}

// ---------------------------------------------------------------------------------------------
// Reading

/// Whether the first bytes of a file are a pcapng or classic pcap magic number.
///
/// ```
/// use protolink::capture::is_capture;
/// assert!(is_capture(&[0x0A, 0x0D, 0x0D, 0x0A]));
/// assert!(is_capture(&[0xD4, 0xC3, 0xB2, 0xA1]));
/// assert!(!is_capture(&[0x7E, 0x52, 0x68, 0x69]));
/// ```
pub fn is_capture(head: &[u8]) -> bool {
    magic(head).is_some()
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    PcapNg,
    Pcap,
}

fn magic(head: &[u8]) -> Option<Format> {
    match head.get(..4)? {
        [0x0A, 0x0D, 0x0D, 0x0A] => Some(Format::PcapNg),
        [0xD4, 0xC3, 0xB2, 0xA1]
        | [0xA1, 0xB2, 0xC3, 0xD4]
        | [0x4D, 0x3C, 0xB2, 0xA1]
        | [0xA1, 0xB2, 0x3C, 0x4D] => Some(Format::Pcap),
        _ => None,
    }
}

/// Whether the file at `path` is a capture (by its magic number, never its name).
pub fn file_is_capture(path: &Path) -> bool {
    let mut head = [0u8; 4];
    File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && is_capture(&head)
}

enum Inner {
    PcapNg {
        reader: PcapNgReader<BufReader<File>>,
        /// Per interface: link type and the factor from the stored units to nanoseconds.
        interfaces: Vec<(u32, TsUnit)>,
    },
    Pcap {
        reader: PcapReader<BufReader<File>>,
        link: u32,
    },
}

#[derive(Debug, Clone, Copy)]
enum TsUnit {
    /// 10^-n seconds.
    Decimal(u8),
    /// 2^-n seconds.
    Binary(u8),
}

impl TsUnit {
    fn from_option(v: Option<u8>) -> Self {
        match v {
            None => TsUnit::Decimal(6),
            Some(b) if b & 0x80 != 0 => TsUnit::Binary(b & 0x7F),
            Some(b) => TsUnit::Decimal(b),
        }
    }

    /// `raw` stored units (pcap-file 2 hands them over as "nanoseconds") as a duration.
    fn to_duration(self, raw: u128) -> Duration {
        let raw = raw.min(u128::from(u64::MAX)) as u64;
        match self {
            TsUnit::Decimal(n) if n <= 9 => {
                Duration::from_nanos(raw.saturating_mul(10u64.pow(9 - u32::from(n))))
            }
            TsUnit::Decimal(n) => {
                let div = 10u128.saturating_pow(u32::from(n) - 9);
                Duration::from_nanos((u128::from(raw) / div) as u64)
            }
            TsUnit::Binary(n) => {
                let secs = raw as f64 / 2f64.powi(i32::from(n));
                Duration::try_from_secs_f64(secs).unwrap_or(Duration::ZERO)
            }
        }
    }
}

/// A capture being read, record by record (bounded memory: one record at a time).
pub struct CaptureReader {
    inner: Inner,
    frame: u64,
    path: String,
}

impl std::fmt::Debug for CaptureReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CaptureReader")
            .field("path", &self.path)
            .finish()
    }
}

impl CaptureReader {
    /// Opens a pcapng or classic pcap file, told apart by its magic number.
    ///
    /// # Errors
    /// Opening the file, or a file that is neither format.
    pub fn open(path: &Path) -> Result<Self> {
        let shown = path.display().to_string();
        let open_err = |source| Error::Open {
            endpoint: shown.clone(),
            source,
        };
        let mut file = File::open(path).map_err(open_err)?;
        let mut head = [0u8; 4];
        let n = file.read(&mut head).map_err(open_err)?;
        file.seek(SeekFrom::Start(0)).map_err(open_err)?;
        let what = format!("reading the capture {shown}");
        let inner = match magic(&head[..n]) {
            Some(Format::PcapNg) => Inner::PcapNg {
                reader: PcapNgReader::new(BufReader::new(file)).map_err(pcap_err(what))?,
                interfaces: Vec::new(),
            },
            Some(Format::Pcap) => {
                let reader = PcapReader::new(BufReader::new(file)).map_err(pcap_err(what))?;
                let link = u32::from(reader.header().datalink);
                Inner::Pcap { reader, link }
            }
            None => {
                return Err(Error::Unsupported(format!(
                    "{shown} is neither a pcapng nor a pcap capture (its first bytes are no capture magic number)"
                )));
            }
        };
        Ok(CaptureReader {
            inner,
            frame: 0,
            path: shown,
        })
    }

    /// The next packet record, or `None` at the end of the file.
    ///
    /// # Errors
    /// A damaged or cut file.
    pub fn next_record(&mut self) -> Result<Option<Record>> {
        let what = format!(
            "reading the capture {} after frame {}",
            self.path, self.frame
        );
        loop {
            let (time, link, interface, data) = match &mut self.inner {
                Inner::Pcap { reader, link } => match reader.next_packet() {
                    None => return Ok(None),
                    Some(Err(e)) => return Err(pcap_err(what)(e)),
                    Some(Ok(p)) => (p.timestamp, *link, 0, p.data.into_owned()),
                },
                Inner::PcapNg { reader, interfaces } => match reader.next_block() {
                    None => return Ok(None),
                    Some(Err(e)) => return Err(pcap_err(what)(e)),
                    Some(Ok(Block::SectionHeader(_))) => {
                        interfaces.clear();
                        continue;
                    }
                    Some(Ok(Block::InterfaceDescription(idb))) => {
                        let tsresol = idb.options.iter().find_map(|o| match o {
                            InterfaceDescriptionOption::IfTsResol(r) => Some(*r),
                            _ => None,
                        });
                        interfaces.push((u32::from(idb.linktype), TsUnit::from_option(tsresol)));
                        continue;
                    }
                    Some(Ok(Block::EnhancedPacket(epb))) => {
                        let Some(&(link, unit)) = interfaces.get(epb.interface_id as usize) else {
                            return Err(Error::Unsupported(format!(
                                "{what} failed: a packet names interface {} which the file never describes",
                                epb.interface_id
                            )));
                        };
                        (
                            unit.to_duration(epb.timestamp.as_nanos()),
                            link,
                            epb.interface_id,
                            epb.data.into_owned(),
                        )
                    }
                    Some(Ok(Block::SimplePacket(spb))) => {
                        let link = interfaces.first().map_or(1, |i| i.0);
                        (Duration::ZERO, link, 0, spb.data.into_owned())
                    }
                    Some(Ok(_)) => continue,
                },
            };
            self.frame += 1;
            let payload = parse_payload(link, interface, &data);
            return Ok(Some(Record {
                frame: self.frame,
                time,
                payload,
            }));
        }
    }
}

/// Finds the UDP or TCP payload (or our stream chunk) in a packet of link type `link`.
///
/// ```
/// use protolink::capture::{ethernet_udp, parse_payload, Payload, Transport};
/// let src = "127.0.0.1:40000".parse().unwrap();
/// let dst = "127.0.0.1:5001".parse().unwrap();
/// let p = parse_payload(1, 0, &ethernet_udp(src, dst, b"hi"));
/// assert_eq!(p, Payload::Ip { transport: Transport::Udp, src, dst, bytes: b"hi".to_vec() });
/// ```
pub fn parse_payload(link: u32, interface: u32, data: &[u8]) -> Payload {
    if let Some(kind) = StreamKind::from_link_type(link) {
        return Payload::Stream {
            interface,
            kind,
            bytes: data.to_vec(),
        };
    }
    let ip = match link {
        // Ethernet, with one optional 802.1Q tag.
        1 => match data.get(12..14) {
            Some([0x08, 0x00]) => data.get(14..),
            Some([0x81, 0x00]) if data.get(16..18) == Some(&[0x08, 0x00]) => data.get(18..),
            _ => None,
        },
        // BSD loopback: a 4-byte address family (2 = IPv4) in either byte order.
        0 | 108 => match data.get(..4) {
            Some([2, 0, 0, 0] | [0, 0, 0, 2]) => data.get(4..),
            _ => None,
        },
        // Raw IP, IPv4.
        12 | 14 | 101 | 228 => Some(data),
        // Linux cooked capture.
        113 => match data.get(14..16) {
            Some([0x08, 0x00]) => data.get(16..),
            _ => None,
        },
        _ => None,
    };
    ip.and_then(parse_ipv4).unwrap_or(Payload::Other)
}

fn parse_ipv4(ip: &[u8]) -> Option<Payload> {
    let first = *ip.first()?;
    if first >> 4 != 4 {
        return None;
    }
    let ihl = usize::from(first & 0x0F) * 4;
    let total = usize::from(u16::from_be_bytes([*ip.get(2)?, *ip.get(3)?]));
    // Fragments other than a whole datagram are not reassembled.
    let frag = u16::from_be_bytes([*ip.get(6)?, *ip.get(7)?]);
    if frag & 0x3FFF != 0 {
        return None;
    }
    let proto = *ip.get(9)?;
    let a = ip.get(12..20)?;
    let src_ip = Ipv4Addr::new(a[0], a[1], a[2], a[3]);
    let dst_ip = Ipv4Addr::new(a[4], a[5], a[6], a[7]);
    let body = ip.get(ihl..total.max(ihl).min(ip.len()))?;
    let port = |at: usize| Some(u16::from_be_bytes([*body.get(at)?, *body.get(at + 1)?]));
    let (src_port, dst_port) = (port(0)?, port(2)?);
    let (transport, bytes) = match proto {
        17 => {
            // The UDP length, never past the captured bytes (a cut packet keeps what it has).
            let end = usize::from(port(4)?).min(body.len()).max(8);
            (Transport::Udp, body.get(8..end)?)
        }
        6 => {
            let off = usize::from(*body.get(12)? >> 4) * 4;
            (Transport::Tcp, body.get(off..)?)
        }
        _ => return None,
    };
    Some(Payload::Ip {
        transport,
        src: SocketAddrV4::new(src_ip, src_port),
        dst: SocketAddrV4::new(dst_ip, dst_port),
        bytes: bytes.to_vec(),
    })
}
