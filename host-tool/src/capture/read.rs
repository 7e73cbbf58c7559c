//! Reading pcapng and classic pcap, told apart by the magic number, one record at a time, and
//! finding the UDP or TCP payload (or a stream chunk) in each.

use std::fs::File;
use std::io::{BufReader, Chain, Cursor, ErrorKind, Read, Seek, SeekFrom};
use std::net::{Ipv4Addr, SocketAddrV4};
use std::path::{Path, PathBuf};
use std::time::Duration;

use byteorder_slice::{BigEndian, LittleEndian};
use pcap_file::pcap::PcapReader;
use pcap_file::pcapng::PcapNgReader;
use pcap_file::pcapng::blocks::Block;
use pcap_file::pcapng::blocks::interface_description::InterfaceDescriptionOption;
use pcap_file::{Endianness, PcapError, TsResolution};

use super::resync::{Framing, Resume, next_start};
use super::{Payload, Record, StreamKind, Transport, pcap_err};
use crate::error::{Error, Result};

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

/// The bytes a reader parses: the file from where the reading starts, after the header it
/// needs first when that is not where the file starts (a damaged capture read on past its
/// damage: the section header or file header again, then the file from there).
type Bytes = BufReader<Chain<Cursor<Vec<u8>>, File>>;

enum Inner {
    PcapNg {
        reader: PcapNgReader<Bytes>,
        /// Per interface: link type and the factor from the stored units to nanoseconds.
        interfaces: Vec<(u32, TsUnit)>,
    },
    Pcap {
        reader: PcapReader<Bytes>,
        link: u32,
    },
}

/// The file from `at`, after `header`.
fn bytes_from(path: &Path, header: Vec<u8>, at: u64) -> std::io::Result<Bytes> {
    let mut file = File::open(path)?;
    file.seek(SeekFrom::Start(at))?;
    Ok(BufReader::new(Cursor::new(header).chain(file)))
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

/// The length of a classic pcap's file header.
const PCAP_HEADER_LEN: u64 = 24;

/// The length of a classic pcap record's header (before its data).
const PCAP_RECORD_HEADER_LEN: u64 = 16;

/// The most `pcap-file` holds of a file at once (its `ReadBuffer`): a block or record
/// longer than this cannot be read, whether the file holds all of it or not.
const READ_BUFFER: u64 = 8_000_000;

/// A capture being read, record by record (bounded memory: one record at a time).
///
/// A block or record that cannot be read is damage: the reader says so once
/// ([`Error::CaptureDamaged`]) and reads on from the next whole block or record. A file that
/// ends inside a block with no whole block after it is cut ([`Error::CaptureCut`]).
pub struct CaptureReader {
    inner: Inner,
    frame: u64,
    /// The file's offset of the next block (pcapng) or record (pcap): the end of the last
    /// whole one read.
    offset: u64,
    path: String,
    /// The file, for its length when a block cannot be read, and to read on past damage.
    file: PathBuf,
    /// The current section header (pcapng) or the file header (pcap): its offset and length,
    /// what a reader past damage reads first.
    header: (u64, u64),
    /// No block or record is left to read: damage or a cut ran to the end of the file.
    ended: bool,
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
        let mut head = [0u8; 12];
        let n = read_head(&mut file, &mut head).map_err(open_err)?;
        drop(file);
        let bytes = bytes_from(path, Vec::new(), 0).map_err(open_err)?;
        let what = format!("reading the capture {shown}");
        let (inner, offset) = match magic(&head[..n]) {
            Some(Format::PcapNg) => (
                Inner::PcapNg {
                    reader: PcapNgReader::new(bytes).map_err(pcap_err(what))?,
                    interfaces: Vec::new(),
                },
                section_header_len(&head),
            ),
            Some(Format::Pcap) => {
                let reader = PcapReader::new(bytes).map_err(pcap_err(what))?;
                let link = u32::from(reader.header().datalink);
                (Inner::Pcap { reader, link }, PCAP_HEADER_LEN)
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
            offset,
            path: shown,
            file: path.to_path_buf(),
            header: (0, offset),
            ended: false,
        })
    }

    /// The byte offset in the file where the next block (pcapng) or record (pcap) starts: the
    /// end of the last whole one read. A capture cut there would give the same records.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// The next packet record, or `None` at the end of the file.
    ///
    /// # Errors
    /// [`Error::CaptureDamaged`] for a block or record that cannot be read: the next call
    /// reads on from the next whole one (or, when none is left, ends). [`Error::CaptureCut`]
    /// for a file that ends inside a block or record with no whole one after it (what
    /// `record` leaves when it is killed mid-write): every record before it has been read.
    /// Otherwise reading the file failed.
    pub fn next_record(&mut self) -> Result<Option<Record>> {
        if self.ended {
            return Ok(None);
        }
        loop {
            let start = self.offset;
            let (time, link, interface, data) = match &mut self.inner {
                Inner::Pcap { reader, link } => match reader.next_packet() {
                    None => return Ok(None),
                    Some(Err(e)) => return Err(self.failed(start, &e)),
                    Some(Ok(p)) => {
                        self.offset += PCAP_RECORD_HEADER_LEN + p.data.len() as u64;
                        (p.timestamp, *link, 0, p.data.into_owned())
                    }
                },
                Inner::PcapNg { reader, interfaces } => {
                    let block = match next_block(reader) {
                        None => return Ok(None),
                        Some(Err(e)) => return Err(self.failed(start, &e)),
                        Some(Ok((len, block))) => {
                            self.offset += u64::from(len);
                            block
                        }
                    };
                    match block {
                        Block::SectionHeader(_) => {
                            interfaces.clear();
                            self.header = (start, self.offset - start);
                            continue;
                        }
                        Block::InterfaceDescription(idb) => {
                            let tsresol = idb.options.iter().find_map(|o| match o {
                                InterfaceDescriptionOption::IfTsResol(r) => Some(*r),
                                _ => None,
                            });
                            interfaces
                                .push((u32::from(idb.linktype), TsUnit::from_option(tsresol)));
                            continue;
                        }
                        Block::EnhancedPacket(epb) => {
                            let Some(&(link, unit)) = interfaces.get(epb.interface_id as usize)
                            else {
                                // A packet of an interface the file never describes: damage
                                // that the block's framing survived.
                                return Err(self.failed(
                                    start,
                                    &PcapError::InvalidField(
                                        "a packet names an interface the file never describes",
                                    ),
                                ));
                            };
                            (
                                unit.to_duration(epb.timestamp.as_nanos()),
                                link,
                                epb.interface_id,
                                epb.data.into_owned(),
                            )
                        }
                        Block::SimplePacket(spb) => {
                            let link = interfaces.first().map_or(1, |i| i.0);
                            (Duration::ZERO, link, 0, spb.data.into_owned())
                        }
                        _ => continue,
                    }
                }
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

    /// The error of the block or record at `start` that could not be read, the reader set
    /// to read on past it: [`Error::CaptureDamaged`] when a whole block or record follows
    /// somewhere (the reading goes on there) or when no file end explains the error (the
    /// reading ends); [`Error::CaptureCut`] when the file ends inside the block
    /// (`pcap-file` read every byte left and wanted more) and no whole one follows it.
    fn failed(&mut self, start: u64, e: &PcapError) -> Error {
        let file_len = std::fs::metadata(&self.file).map_or(u64::MAX, |m| m.len());
        let shown = format!(
            "reading the capture {} after frame {}",
            self.path, self.frame
        );
        let cut_short = matches!(e, PcapError::IoError(io) if io.kind() == ErrorKind::UnexpectedEof)
            && file_len.saturating_sub(start) < READ_BUFFER;
        let resume = match self.resume_after(start, file_len) {
            Ok(resume) => resume,
            Err(io) => {
                self.ended = true;
                return Error::Io {
                    what: shown,
                    source: io,
                };
            }
        };
        let frames = self.frame;
        match resume {
            Some(at) => Error::CaptureDamaged {
                path: self.path.clone(),
                offset: start,
                skipped: at - start,
                frames,
                resumed: true,
            },
            None if cut_short => {
                self.ended = true;
                Error::CaptureCut {
                    path: self.path.clone(),
                    offset: start,
                    frames,
                }
            }
            None => {
                self.ended = true;
                Error::CaptureDamaged {
                    path: self.path.clone(),
                    offset: start,
                    skipped: file_len.saturating_sub(start),
                    frames,
                    resumed: false,
                }
            }
        }
    }

    /// Finds the first whole block or record after the damage at `start` and reads on from
    /// there; `None` when none is left.
    fn resume_after(&mut self, start: u64, file_len: u64) -> std::io::Result<Option<u64>> {
        let framing = match &self.inner {
            Inner::PcapNg { reader, interfaces } => Framing::PcapNg {
                big_endian: reader.section().endianness == Endianness::Big,
                interfaces: interfaces.len(),
            },
            Inner::Pcap { reader, .. } => {
                let header = reader.header();
                Framing::Pcap {
                    big_endian: header.endianness == Endianness::Big,
                    snaplen: header.snaplen,
                    nanos: header.ts_resolution == TsResolution::NanoSecond,
                }
            }
        };
        let mut file = File::open(&self.file)?;
        let Some(Resume { at, section }) = next_start(
            &mut file,
            file_len,
            start.saturating_add(1),
            framing,
            READ_BUFFER,
        )?
        else {
            return Ok(None);
        };
        // The header the reader needs before the bytes at `at`: none when a section
        // header starts there (the reader reads it as the file's first block).
        let header = if section {
            Vec::new()
        } else {
            let (from, len) = self.header;
            let mut header = vec![0u8; usize::try_from(len).unwrap_or(0)];
            file.seek(SeekFrom::Start(from))?;
            file.read_exact(&mut header)?;
            header
        };
        let bytes = bytes_from(&self.file, header, at)?;
        let invalid = |e: PcapError| std::io::Error::new(ErrorKind::InvalidData, e.to_string());
        self.offset = at;
        match &mut self.inner {
            Inner::PcapNg { reader, interfaces } => {
                *reader = PcapNgReader::new(bytes).map_err(invalid)?;
                if section {
                    // The reader took the new section's header; its interfaces follow.
                    interfaces.clear();
                    let mut head = [0u8; 12];
                    file.seek(SeekFrom::Start(at))?;
                    file.read_exact(&mut head)?;
                    let len = section_header_len(&head);
                    self.header = (at, len);
                    self.offset = at + len;
                }
            }
            Inner::Pcap { reader, .. } => {
                *reader = PcapReader::new(bytes).map_err(invalid)?;
            }
        }
        Ok(Some(at))
    }
}

/// The next block of a pcapng and its length in the file.
fn next_block(
    reader: &mut PcapNgReader<Bytes>,
) -> Option<std::result::Result<(u32, Block<'_>), PcapError>> {
    // The byte order of the section the block is in (a section header block, which starts a
    // new section, is read whatever the order).
    let order = reader.section().endianness;
    let raw = match reader.next_raw_block()? {
        Ok(raw) => raw,
        Err(e) => return Some(Err(e)),
    };
    let len = raw.initial_len;
    let block = match order {
        Endianness::Big => raw.try_into_block::<BigEndian>(),
        Endianness::Little => raw.try_into_block::<LittleEndian>(),
    };
    Some(block.map(|b| (len, b)))
}

/// Reads up to `head.len()` bytes from the start of `file` (fewer only at its end).
fn read_head(file: &mut File, head: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < head.len() {
        match file.read(&mut head[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

/// The length of a pcapng's first block, its section header: the block length at bytes 4..8,
/// in the byte order its magic at 8..12 gives (a file too short for it is refused by the
/// reader before the length counts).
fn section_header_len(head: &[u8; 12]) -> u64 {
    let len = [head[4], head[5], head[6], head[7]];
    match head[8..12] {
        [0x4D, 0x3C, 0x2B, 0x1A] => u64::from(u32::from_le_bytes(len)),
        _ => u64::from(u32::from_be_bytes(len)),
    }
}

/// Finds the UDP or TCP payload (or our stream chunk) in a packet of link type `link`.
pub(crate) fn parse_payload(link: u32, interface: u32, data: &[u8]) -> Payload {
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

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn parse_payload_reads_a_udp_frame_example() -> Result<(), Box<dyn std::error::Error>> {
        use crate::capture::{Payload, Transport, ethernet_udp};
        let src = "127.0.0.1:40000".parse().unwrap();
        let dst = "127.0.0.1:5001".parse().unwrap();
        let p = parse_payload(1, 0, &ethernet_udp(src, dst, b"hi"));
        assert_eq!(
            p,
            Payload::Ip {
                transport: Transport::Udp,
                src,
                dst,
                bytes: b"hi".to_vec()
            }
        );
        Ok(())
    }
}
