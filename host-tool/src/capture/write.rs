//! Writing pcapng: one interface, then one Enhanced Packet Block per record, as data arrives.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::net::SocketAddrV4;
use std::path::Path;
use std::time::Duration;

use pcap_file::DataLink;
use pcap_file::pcapng::PcapNgWriter;
use pcap_file::pcapng::blocks::Block;
use pcap_file::pcapng::blocks::enhanced_packet::EnhancedPacketBlock;
use pcap_file::pcapng::blocks::interface_description::{
    InterfaceDescriptionBlock, InterfaceDescriptionOption,
};

use super::{SNAPLEN, pcap_err};
use crate::error::{Error, Result};

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

impl CaptureWriter {
    /// Creates `path` with one interface of link type `link` (Ethernet for UDP, or a
    /// [`super::StreamKind::link_type`]), named `name`.
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
