//! Direct output control (type 7, Y8): count u16, then count × (device u8, channel u8, f32).

use super::{fixed_emit, too_short};
use crate::encode::Payload;
use crate::error::{EncodeError, Error, Result};
use crate::header::{array_at, put};
use crate::layout::{direct_output, output_entry as entry};

/// One output setting.
///
/// ```
/// use aydp_proto::OutputEntry;
/// let e = OutputEntry { device: 1, channel: 2, value: 10.0 };
/// let mut data = [0u8; OutputEntry::LEN];
/// assert_eq!(e.emit(&mut data), Ok(OutputEntry::LEN));
/// assert_eq!(data, [0x01, 0x02, 0x00, 0x00, 0x20, 0x41]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct OutputEntry {
    /// Output device.
    pub device: u8,
    /// Channel within the device.
    pub channel: u8,
    /// Calibrated output value.
    pub value: f32,
}

fixed_emit!(OutputEntry);

impl OutputEntry {
    /// Bytes per entry.
    pub const LEN: usize = entry::LEN;
    /// The layout: `(field, wire type, offset in the entry)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::OutputEntry;
    /// // Offsets inside one entry of a direct output control.
    /// assert_eq!(OutputEntry::FIELDS[2], ("value", "f32", 2));
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = entry::FIELDS;

    /// The 6 bytes of this entry.
    ///
    /// ```
    /// use aydp_proto::OutputEntry;
    /// let e = OutputEntry { device: 1, channel: 2, value: -1.0 };
    /// let mut data = [0u8; OutputEntry::LEN];
    /// assert_eq!(e.emit(&mut data), Ok(OutputEntry::LEN));
    /// assert_eq!(data, [1, 2, 0x00, 0x00, 0x80, 0xBF]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        let mut out = [0u8; Self::LEN];
        out[entry::DEVICE] = self.device;
        out[entry::CHANNEL] = self.channel;
        put(&mut out, entry::VALUE, &self.value.to_le_bytes());
        out
    }

    fn from_chunk(b: &[u8]) -> Self {
        let a: [u8; Self::LEN] = array_at(b, 0);
        Self {
            device: a[0],
            channel: a[1],
            value: f32::from_le_bytes(array_at(&a, entry::VALUE)),
        }
    }
}

/// Direct output control (type 7): a validated, zero-copy view over the message data.
///
/// The document says a channel named twice takes the last value; [`DirectOutput::entries`]
/// yields entries in order, so applying them in order gives exactly that.
///
/// ```
/// use aydp_proto::{DirectOutput, OutputEntry};
/// let data = [0x01, 0x00, 0x01, 0x02, 0x00, 0x00, 0x20, 0x41];
/// let out = DirectOutput::parse(&data).unwrap();
/// let e: Vec<OutputEntry> = out.entries().collect();
/// assert_eq!(e, vec![OutputEntry { device: 1, channel: 2, value: 10.0 }]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DirectOutput<'a> {
    data: &'a [u8],
}

impl<'a> DirectOutput<'a> {
    /// Base type.
    pub const TYPE: u8 = 7;
    /// The head's length: the first [`OutputEntry`] starts here.
    pub const HEADER_LEN: usize = direct_output::ENTRIES;
    /// The layout: `(field, wire type, data offset)` per field of the head, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::{DirectOutput, OutputEntry};
    /// assert_eq!(DirectOutput::FIELDS, [("count", "u16", 0)]);
    /// // The count, then that many entries.
    /// assert_eq!(DirectOutput::HEADER_LEN + 2 * OutputEntry::LEN, 14);
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = direct_output::FIELDS;

    /// Validate: the u16 count must match the data length exactly.
    ///
    /// ```
    /// use aydp_proto::{DirectOutput, Error};
    /// // Count 1 (u16), then device 1, channel 2, value 10.0.
    /// assert_eq!(DirectOutput::parse(&[1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41]).unwrap().len(), 1);
    /// let mismatch = Error::CountMismatch { msg_type: 7, count: 2 };
    /// assert_eq!(DirectOutput::parse(&[2, 0, 1, 2, 0x00, 0x00, 0x20, 0x41]), Err(mismatch));
    /// let short = Error::PayloadTooShort { msg_type: 7, expected: 2, actual: 1 };
    /// assert_eq!(DirectOutput::parse(&[1]), Err(short));
    /// ```
    pub fn parse(data: &'a [u8]) -> Result<Self> {
        let Some(rest) = data.get(2..) else {
            return Err(too_short(Self::TYPE, 2, data.len()));
        };
        let count = u16::from_le_bytes(array_at(data, direct_output::COUNT)) as usize;
        if rest.len() != count * OutputEntry::LEN {
            return Err(Error::CountMismatch {
                msg_type: Self::TYPE,
                count,
            });
        }
        Ok(Self { data })
    }

    /// Number of entries.
    ///
    /// ```
    /// use aydp_proto::DirectOutput;
    /// assert_eq!(DirectOutput::parse(&[1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41]).unwrap().len(), 1);
    /// ```
    pub fn len(&self) -> usize {
        u16::from_le_bytes(array_at(self.data, direct_output::COUNT)) as usize
    }

    /// Whether there are no entries.
    ///
    /// ```
    /// use aydp_proto::DirectOutput;
    /// assert!(DirectOutput::parse(&[0, 0]).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The data bytes.
    ///
    /// ```
    /// use aydp_proto::DirectOutput;
    /// let data = [1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41];
    /// assert_eq!(DirectOutput::parse(&data).unwrap().as_bytes(), &data);
    /// ```
    pub fn as_bytes(&self) -> &'a [u8] {
        self.data
    }

    /// The entries, in message order, without copying.
    ///
    /// ```
    /// use aydp_proto::{DirectOutput, OutputEntry};
    /// let out = DirectOutput::parse(&[1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41]).unwrap();
    /// let first = out.entries().next();
    /// assert_eq!(first, Some(OutputEntry { device: 1, channel: 2, value: 10.0 }));
    /// ```
    pub fn entries(&self) -> Entries<'a> {
        Entries {
            chunks: self
                .data
                .get(2..)
                .unwrap_or(&[])
                .chunks_exact(OutputEntry::LEN),
        }
    }
}

impl Payload for DirectOutput<'_> {
    fn base_type(&self) -> u8 {
        Self::TYPE
    }
    fn buffer_len(&self) -> usize {
        self.data.len()
    }
    fn data_byte(&self, index: usize) -> u8 {
        self.data.get(index).copied().unwrap_or(0)
    }
    fn write_data(&self, out: &mut [u8]) {
        put(out, 0, self.data);
    }
}

/// Iterator over [`DirectOutput`] entries.
///
/// ```
/// use aydp_proto::DirectOutput;
/// let out = DirectOutput::parse(&[1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41]).unwrap();
/// let mut entries = out.entries();
/// assert_eq!(entries.len(), 1);
/// assert_eq!(entries.next().map(|e| e.value), Some(10.0));
/// assert_eq!(entries.next(), None);
/// ```
#[derive(Debug, Clone)]
pub struct Entries<'a> {
    chunks: core::slice::ChunksExact<'a, u8>,
}

impl Iterator for Entries<'_> {
    type Item = OutputEntry;
    fn next(&mut self) -> Option<OutputEntry> {
        self.chunks.next().map(OutputEntry::from_chunk)
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        self.chunks.size_hint()
    }
}

impl ExactSizeIterator for Entries<'_> {}

/// Builds a [`DirectOutput`] in a caller's buffer.
///
/// ```
/// use aydp_proto::{DirectOutputBuilder, Encoder, OutputEntry, Profile};
/// let mut data = [0u8; 32];
/// let mut b = DirectOutputBuilder::new(&mut data);
/// b.push(OutputEntry { device: 1, channel: 2, value: 10.0 }).unwrap();
/// let out = b.finish();
/// let mut frame = [0u8; 32];
/// let n = Encoder::new(Profile::Spec).encode(&out, None, &mut frame).unwrap();
/// assert_eq!(&frame[..n], &[0xFF, 0x87, 0x0F, 0, 0, 0, 0x01, 0x00, 0x01, 0x02, 0, 0, 0x20, 0x41, 0x14]);
/// ```
#[derive(Debug)]
pub struct DirectOutputBuilder<'b> {
    buf: &'b mut [u8],
    count: u16,
}

impl<'b> DirectOutputBuilder<'b> {
    /// Start an empty list in `buf` (needs at least 2 bytes to finish).
    ///
    /// ```
    /// use aydp_proto::DirectOutputBuilder;
    /// let mut buf = [0xAA; 8];
    /// assert_eq!(DirectOutputBuilder::new(&mut buf).finish().as_bytes(), &[0, 0]);
    /// ```
    pub fn new(buf: &'b mut [u8]) -> Self {
        Self { buf, count: 0 }
    }

    /// Append an entry; fails ([`EncodeError::BufferTooSmall`], [`EncodeError::TooLong`]) if the
    /// buffer is full or 65 535 entries are held.
    ///
    /// ```
    /// use aydp_proto::{DirectOutputBuilder, EncodeError, OutputEntry};
    /// let mut buf = [0u8; 8];
    /// let mut builder = DirectOutputBuilder::new(&mut buf);
    /// assert_eq!(builder.push(OutputEntry::default()), Ok(()));
    /// assert_eq!(builder.push(OutputEntry::default()), Err(EncodeError::BufferTooSmall { needed: 14 }));
    /// ```
    pub fn push(&mut self, entry: OutputEntry) -> core::result::Result<(), EncodeError> {
        if self.count == u16::MAX {
            return Err(EncodeError::TooLong);
        }
        let at = 2 + self.count as usize * OutputEntry::LEN;
        let Some(dst) = self.buf.get_mut(at..at + OutputEntry::LEN) else {
            return Err(EncodeError::BufferTooSmall {
                needed: at + OutputEntry::LEN,
            });
        };
        put(dst, 0, &entry.data());
        self.count += 1;
        Ok(())
    }

    /// The finished view.
    ///
    /// ```
    /// use aydp_proto::{DirectOutputBuilder, OutputEntry};
    /// let mut buf = [0u8; 8];
    /// let mut builder = DirectOutputBuilder::new(&mut buf);
    /// builder.push(OutputEntry { device: 1, channel: 2, value: 10.0 }).unwrap();
    /// assert_eq!(builder.finish().as_bytes(), &[1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41]);
    /// ```
    pub fn finish(self) -> DirectOutput<'b> {
        let n = 2 + self.count as usize * OutputEntry::LEN;
        put(self.buf, 0, &self.count.to_le_bytes());
        let buf: &'b [u8] = self.buf;
        DirectOutput {
            data: buf.get(..n).unwrap_or(&[]),
        }
    }
}
