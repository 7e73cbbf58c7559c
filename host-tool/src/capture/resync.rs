//! Where a damaged capture goes on: past a block (pcapng) or record (classic pcap) that cannot
//! be read, the first place where a whole one starts and is followed by another whole one or
//! by the end of the file. The file is searched a window at a time, so memory stays at one
//! window whatever the damage.
//!
//! A pcapng block starts at a multiple of 4 (every block's length is one) with a known block
//! type, a length of 12 bytes or more that the same length ends (its trailer), and, for an
//! enhanced packet, an interface the file described before. A classic pcap record starts
//! with a fraction of a second below one second, and a saved length no longer than the
//! original length, which the header's snapshot length bounds.

use std::fs::File;
use std::io::{ErrorKind, Read, Seek, SeekFrom};

/// Bytes of the file read per step of a search.
const WINDOW: usize = 64 * 1024;

/// The bytes a candidate's first check reads: a pcapng block's type, length and interface, a
/// pcap record's header.
const HEAD: usize = 16;

/// The pcapng block types a search accepts: interface description, packet (obsolete), simple
/// packet, name resolution, interface statistics, enhanced packet.
const PCAPNG_TYPES: [u32; 6] = [1, 2, 3, 4, 5, 6];

/// The pcapng section header's block type (the same in both byte orders).
const SECTION_HEADER: [u8; 4] = [0x0A, 0x0D, 0x0D, 0x0A];

/// What the blocks or records of the damaged file look like.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Framing {
    /// pcapng blocks of a section in this byte order, after `interfaces` interface
    /// descriptions.
    PcapNg {
        /// The section's byte order.
        big_endian: bool,
        /// The interfaces the section described so far.
        interfaces: usize,
    },
    /// Classic pcap records.
    Pcap {
        /// The file's byte order.
        big_endian: bool,
        /// The header's snapshot length: no record is longer.
        snaplen: u32,
        /// Times in nanoseconds (else microseconds).
        nanos: bool,
    },
}

/// A place a damaged capture goes on from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Resume {
    /// Its byte offset in the file.
    pub(super) at: u64,
    /// A pcapng section header starts there (a new section, in its own byte order).
    pub(super) section: bool,
}

impl Framing {
    /// The step between two places a block or record may start.
    fn alignment(self) -> u64 {
        match self {
            Framing::PcapNg { .. } => 4,
            Framing::Pcap { .. } => 1,
        }
    }

    fn u32_at(big_endian: bool, head: &[u8], at: usize) -> Option<u32> {
        let b: [u8; 4] = head.get(at..at + 4)?.try_into().ok()?;
        Some(if big_endian {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        })
    }

    /// The length a block or record starting with `head` claims, with whether it is a
    /// section header and, for pcapng, the byte order of its trailer; `None` when `head`
    /// cannot start one or it would be longer than `max`.
    fn claim(self, head: &[u8], max: u64) -> Option<(u64, bool, bool)> {
        match self {
            Framing::PcapNg {
                big_endian,
                interfaces,
            } => {
                let (len, section, order) = if head.get(..4)? == SECTION_HEADER {
                    let order = match head.get(8..12)? {
                        [0x1A, 0x2B, 0x3C, 0x4D] => true,
                        [0x4D, 0x3C, 0x2B, 0x1A] => false,
                        _ => return None,
                    };
                    (Self::u32_at(order, head, 4)?, true, order)
                } else {
                    let kind = Self::u32_at(big_endian, head, 0)?;
                    if !PCAPNG_TYPES.contains(&kind) {
                        return None;
                    }
                    let packet_of_no_interface = match kind {
                        6 => Self::u32_at(big_endian, head, 8)? as usize >= interfaces,
                        2 | 3 => interfaces == 0,
                        _ => false,
                    };
                    if packet_of_no_interface {
                        return None;
                    }
                    (Self::u32_at(big_endian, head, 4)?, false, big_endian)
                };
                let len = u64::from(len);
                (len >= 12 && len % 4 == 0 && len <= max).then_some((len, section, order))
            }
            Framing::Pcap {
                big_endian,
                snaplen,
                nanos,
            } => {
                let fraction = Self::u32_at(big_endian, head, 4)?;
                let saved = Self::u32_at(big_endian, head, 8)?;
                let original = Self::u32_at(big_endian, head, 12)?;
                let second = if nanos { 1_000_000_000 } else { 1_000_000 };
                let len = 16 + u64::from(saved);
                (fraction < second && saved <= original && original <= snaplen && len <= max)
                    .then_some((len, false, big_endian))
            }
        }
    }
}

/// Reads at `at` into `buf` until it is full or the file ends; the bytes read.
fn read_at(file: &mut File, at: u64, buf: &mut [u8]) -> std::io::Result<usize> {
    file.seek(SeekFrom::Start(at))?;
    let mut n = 0;
    while n < buf.len() {
        match file.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// Whether a whole block or record of `len` bytes starts at `at` (its trailer, for pcapng, is
/// its length) in the file of `file_len` bytes.
fn whole(
    file: &mut File,
    framing: Framing,
    at: u64,
    len: u64,
    big_endian: bool,
    file_len: u64,
) -> std::io::Result<bool> {
    if at.saturating_add(len) > file_len {
        return Ok(false);
    }
    if let Framing::PcapNg { .. } = framing {
        let mut trailer = [0u8; 4];
        if read_at(file, at + len - 4, &mut trailer)? < 4 {
            return Ok(false);
        }
        return Ok(Framing::u32_at(big_endian, &trailer, 0) == u32::try_from(len).ok());
    }
    Ok(true)
}

/// The first place at or after `from` where a whole block or record of `framing` starts,
/// followed by another whole one or by the end of the file (`file_len` bytes); none longer
/// than `max`. `None` when no such place is left.
///
/// # Errors
/// Reading the file.
pub(super) fn next_start(
    file: &mut File,
    file_len: u64,
    from: u64,
    framing: Framing,
    max: u64,
) -> std::io::Result<Option<Resume>> {
    let step = framing.alignment();
    let mut window = vec![0u8; WINDOW + HEAD];
    let mut at = from.div_ceil(step) * step;
    while at < file_len {
        let n = read_at(file, at, &mut window)?;
        let last = n < window.len();
        // The last window tries every place left; the others leave their last HEAD bytes
        // to the next window, which starts there.
        let tried = if last { n } else { WINDOW };
        let mut i = 0;
        while i < tried {
            let place = at + i as u64;
            let head = window.get(i..n).unwrap_or_default();
            if let Some((len, section, order)) = framing.claim(head, max)
                && whole(file, framing, place, len, order, file_len)?
                && followed(file, framing, place + len, order, section, file_len, max)?
            {
                return Ok(Some(Resume { at: place, section }));
            }
            i += step as usize;
        }
        if last {
            break;
        }
        at += tried as u64;
    }
    Ok(None)
}

/// Whether the end of the file or a whole block or record starts at `next`.
fn followed(
    file: &mut File,
    framing: Framing,
    next: u64,
    big_endian: bool,
    section: bool,
    file_len: u64,
    max: u64,
) -> std::io::Result<bool> {
    if next == file_len {
        return Ok(true);
    }
    // After a section header: the section's own byte order, no interface described yet.
    let framing = match framing {
        Framing::PcapNg { interfaces, .. } => Framing::PcapNg {
            big_endian,
            interfaces: if section { 0 } else { interfaces },
        },
        pcap => pcap,
    };
    let mut head = [0u8; HEAD];
    let n = read_at(file, next, &mut head)?;
    match framing.claim(head.get(..n).unwrap_or_default(), max) {
        Some((len, _, order)) => whole(file, framing, next, len, order, file_len),
        None => Ok(false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(kind: u32, body: &[u8]) -> Vec<u8> {
        let len = (12 + body.len()) as u32;
        let mut b = kind.to_le_bytes().to_vec();
        b.extend(len.to_le_bytes());
        b.extend(body);
        b.extend(len.to_le_bytes());
        b
    }

    #[test]
    fn a_search_skips_damage_and_lands_on_a_whole_block() -> std::io::Result<()> {
        let path = std::env::temp_dir().join(format!("protolink-resync-{}", std::process::id()));
        let mut bytes = block(6, &[0, 0, 0, 0, 1, 2, 3, 4]);
        let damaged = bytes.len() as u64;
        bytes.extend([0xFF; 40]);
        let good = bytes.len() as u64;
        bytes.extend(block(6, &[0, 0, 0, 0, 9, 9, 9, 9]));
        bytes.extend(block(5, &[0; 4]));
        std::fs::write(&path, &bytes)?;
        let mut file = File::open(&path)?;
        let len = bytes.len() as u64;
        let framing = Framing::PcapNg {
            big_endian: false,
            interfaces: 1,
        };
        let found = next_start(&mut file, len, damaged, framing, 1 << 20)?;
        assert_eq!(
            found,
            Some(Resume {
                at: good,
                section: false
            })
        );
        // No interface described: an enhanced packet cannot start there, the statistics can.
        let framing = Framing::PcapNg {
            big_endian: false,
            interfaces: 0,
        };
        let found = next_start(&mut file, len, damaged, framing, 1 << 20)?;
        assert_eq!(found.map(|r| r.at), Some(good + 20));
        // Past the last block: nothing.
        assert_eq!(next_start(&mut file, len, len - 3, framing, 1 << 20)?, None);
        std::fs::remove_file(&path)
    }

    fn record(second: u32, fraction: u32, data: &[u8]) -> Vec<u8> {
        let len = data.len() as u32;
        let mut r = Vec::new();
        for field in [second, fraction, len, len] {
            r.extend(field.to_le_bytes());
        }
        r.extend(data);
        r
    }

    #[test]
    fn a_pcap_search_lands_on_a_record_followed_by_another() -> std::io::Result<()> {
        let path =
            std::env::temp_dir().join(format!("protolink-resync-pcap-{}", std::process::id()));
        let mut bytes = vec![0xFF; 23];
        let good = bytes.len() as u64;
        bytes.extend(record(1_700_000_000, 999_999, b"abc"));
        bytes.extend(record(1_700_000_001, 0, b"de"));
        std::fs::write(&path, &bytes)?;
        let mut file = File::open(&path)?;
        let len = bytes.len() as u64;
        let framing = Framing::Pcap {
            big_endian: false,
            snaplen: 65_535,
            nanos: false,
        };
        let found = next_start(&mut file, len, 0, framing, 1 << 20)?;
        assert_eq!(found.map(|r| r.at), Some(good));
        // A snapshot length shorter than the records: none can start anywhere.
        let short = Framing::Pcap {
            big_endian: false,
            snaplen: 1,
            nanos: false,
        };
        assert_eq!(next_start(&mut file, len, 0, short, 1 << 20)?, None);
        std::fs::remove_file(&path)
    }
}
