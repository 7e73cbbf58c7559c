//! Position fix quality (type 4) and fix detail (type 5) (Y8), with `uflt16` fields (Y7).

use super::{exact, fixed_emit, fixed_payload, too_short};
use crate::encode::Payload;
use crate::error::{EncodeError, Error, Result};
use crate::header::{array_at, put};
use crate::layout::{fix_detail as fd, fix_quality as fq, satellite as sat};
use crate::uflt16;

/// Position fix quality (type 4): 8 bytes.
///
/// ```
/// use aydp_proto::FixQuality;
/// let q = FixQuality { fix_type: 3, mean_dop: 1.5, hdop: 1.0, vdop: 2.0, satellites: 9 };
/// let mut data = [0u8; FixQuality::LEN];
/// q.emit(&mut data).unwrap();
/// assert_eq!(FixQuality::parse(&data), Ok(q));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FixQuality {
    /// Fix type.
    pub fix_type: u8,
    /// Mean dilution of precision (uflt16 on the wire).
    pub mean_dop: f32,
    /// Horizontal DOP (uflt16).
    pub hdop: f32,
    /// Vertical DOP (uflt16).
    pub vdop: f32,
    /// Number of satellites.
    pub satellites: u8,
}

fn uf(b: &[u8], at: usize) -> Result<f32> {
    uflt16::decode(u16::from_le_bytes(array_at(b, at)))
}

impl FixQuality {
    /// Base type.
    pub const TYPE: u8 = 4;
    /// Data length.
    pub const LEN: usize = fq::LEN;
    /// The layout: `(field, wire type, data offset)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::FixQuality;
    /// assert_eq!(FixQuality::FIELDS[1], ("mean_dop", "uflt16", 1));
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = fq::FIELDS;

    /// Parse exactly 8 data bytes; a negative `uflt16` is an error.
    ///
    /// ```
    /// use aydp_proto::{Error, FixQuality};
    /// let q = FixQuality::parse(&[3, 0x00, 0x3E, 0x00, 0x3C, 0x00, 0x40, 9]).unwrap();
    /// assert_eq!((q.fix_type, q.mean_dop, q.hdop, q.vdop, q.satellites), (3, 1.5, 1.0, 2.0, 9));
    /// // 0x8000 as the mean DOP: a negative uflt16.
    /// assert_eq!(FixQuality::parse(&[3, 0x00, 0x80, 0, 0, 0, 0, 9]), Err(Error::NegativeUflt16));
    /// ```
    pub fn parse(data: &[u8]) -> Result<Self> {
        let b = exact::<{ Self::LEN }>(data, Self::TYPE)?;
        Ok(Self {
            fix_type: b[fq::FIX_TYPE],
            mean_dop: uf(b, fq::MEAN_DOP)?,
            hdop: uf(b, fq::HDOP)?,
            vdop: uf(b, fq::VDOP)?,
            satellites: b[fq::SATELLITES],
        })
    }

    /// The 8 data bytes (DOPs rounded to binary16, negatives clamped to 0).
    ///
    /// ```
    /// use aydp_proto::FixQuality;
    /// let q = FixQuality { fix_type: 3, mean_dop: 1.5, hdop: 1.0, vdop: 2.0, satellites: 9 };
    /// let mut data = [0u8; FixQuality::LEN];
    /// assert_eq!(q.emit(&mut data), Ok(FixQuality::LEN));
    /// assert_eq!(data, [3, 0x00, 0x3E, 0x00, 0x3C, 0x00, 0x40, 9]);
    /// let negative = FixQuality { hdop: -1.0, ..q };
    /// negative.emit(&mut data).unwrap();
    /// assert_eq!(&data[3..5], &[0x00, 0x00]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        let mut out = [0u8; Self::LEN];
        out[fq::FIX_TYPE] = self.fix_type;
        put(
            &mut out,
            fq::MEAN_DOP,
            &uflt16::encode(self.mean_dop).to_le_bytes(),
        );
        put(&mut out, fq::HDOP, &uflt16::encode(self.hdop).to_le_bytes());
        put(&mut out, fq::VDOP, &uflt16::encode(self.vdop).to_le_bytes());
        out[fq::SATELLITES] = self.satellites;
        out
    }
}

fixed_payload!(FixQuality);
fixed_emit!(Satellite);

/// One satellite of a fix detail message: 7 bytes on the wire.
///
/// ```
/// use aydp_proto::Satellite;
/// let s = Satellite { id: 7, azimuth: 180.0, elevation: 45.0, snr: 38.0 };
/// let mut data = [0u8; Satellite::LEN];
/// s.emit(&mut data).unwrap();
/// assert_eq!(Satellite::parse(&data), Ok(s));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Satellite {
    /// Satellite ID.
    pub id: u8,
    /// Azimuth (uflt16).
    pub azimuth: f32,
    /// Elevation (uflt16).
    pub elevation: f32,
    /// Signal to noise ratio (uflt16).
    pub snr: f32,
}

impl Satellite {
    /// Bytes per satellite.
    pub const LEN: usize = sat::LEN;
    /// The layout: `(field, wire type, offset in the entry)` per field, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::Satellite;
    /// // Offsets inside one entry of a fix detail.
    /// assert_eq!(Satellite::FIELDS[3], ("snr", "uflt16", 5));
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = sat::FIELDS;

    /// Parse 7 bytes.
    ///
    /// ```
    /// use aydp_proto::{Error, Satellite};
    /// let s = Satellite::parse(&[7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]).unwrap();
    /// assert_eq!((s.id, s.azimuth, s.elevation, s.snr), (7, 180.0, 45.0, 38.0));
    /// assert_eq!(Satellite::parse(&[7, 0x00, 0x80, 0, 0, 0, 0]), Err(Error::NegativeUflt16));
    /// ```
    pub fn parse(b: &[u8; Self::LEN]) -> Result<Self> {
        Ok(Self {
            id: b[sat::ID],
            azimuth: uf(b, sat::AZIMUTH)?,
            elevation: uf(b, sat::ELEVATION)?,
            snr: uf(b, sat::SNR)?,
        })
    }

    /// The 7 bytes.
    ///
    /// ```
    /// use aydp_proto::Satellite;
    /// let s = Satellite { id: 7, azimuth: 180.0, elevation: 45.0, snr: 38.0 };
    /// let mut data = [0u8; Satellite::LEN];
    /// assert_eq!(s.emit(&mut data), Ok(Satellite::LEN));
    /// assert_eq!(data, [7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]);
    /// ```
    pub(crate) fn data(&self) -> [u8; Self::LEN] {
        let mut out = [0u8; Self::LEN];
        out[sat::ID] = self.id;
        put(
            &mut out,
            sat::AZIMUTH,
            &uflt16::encode(self.azimuth).to_le_bytes(),
        );
        put(
            &mut out,
            sat::ELEVATION,
            &uflt16::encode(self.elevation).to_le_bytes(),
        );
        put(&mut out, sat::SNR, &uflt16::encode(self.snr).to_le_bytes());
        out
    }
}

/// A bounded list of satellites, as collected from a [`FixDetail`].
pub type SatelliteList<const M: usize> = heapless::Vec<Satellite, M>;

/// Position fix detail (type 5): count u8, then count × 7 bytes. A zero-copy, validated view.
///
/// ```
/// use aydp_proto::{FixDetail, FixDetailBuilder, Satellite};
/// let mut buf = [0u8; 64];
/// let mut b = FixDetailBuilder::new(&mut buf);
/// b.push(Satellite { id: 3, azimuth: 90.0, elevation: 30.0, snr: 40.0 }).unwrap();
/// let detail = b.finish();
/// assert_eq!(detail.len(), 1);
/// let again = FixDetail::parse(detail.as_bytes()).unwrap();
/// let list = again.to_list::<16>().unwrap();
/// assert_eq!(list[0].id, 3);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FixDetail<'a> {
    data: &'a [u8],
}

impl<'a> FixDetail<'a> {
    /// Base type.
    pub const TYPE: u8 = 5;
    /// The head's length: the first [`Satellite`] entry starts here.
    pub const HEADER_LEN: usize = fd::ENTRIES;
    /// The layout: `(field, wire type, data offset)` per field of the head, for tools that describe the
    /// wire format (the Wireshark dissector `protolink wireshark` writes). Little-endian;
    /// `uflt16` is binary16 without a sign.
    ///
    /// ```
    /// use aydp_proto::{FixDetail, Satellite};
    /// assert_eq!(FixDetail::FIELDS, [("count", "u8", 0)]);
    /// // The count, then that many entries.
    /// assert_eq!(FixDetail::HEADER_LEN + 2 * Satellite::LEN, 15);
    /// ```
    pub const FIELDS: &'static [(&'static str, &'static str, usize)] = fd::FIELDS;

    /// Validate: the count must match the length and no `uflt16` may be negative.
    ///
    /// ```
    /// use aydp_proto::{Error, FixDetail};
    /// assert_eq!(FixDetail::parse(&[1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]).unwrap().len(), 1);
    /// // A count of 2 with one entry's bytes.
    /// let mismatch = Error::CountMismatch { msg_type: 5, count: 2 };
    /// assert_eq!(FixDetail::parse(&[2, 0, 0, 0, 0, 0, 0, 0]), Err(mismatch));
    /// ```
    pub fn parse(data: &'a [u8]) -> Result<Self> {
        let Some((&count, rest)) = data.split_first() else {
            return Err(too_short(Self::TYPE, 1, 0));
        };
        let count = count as usize;
        if rest.len() != count * Satellite::LEN {
            return Err(Error::CountMismatch {
                msg_type: Self::TYPE,
                count,
            });
        }
        for chunk in rest.chunks_exact(Satellite::LEN) {
            for field in [sat::AZIMUTH, sat::ELEVATION, sat::SNR] {
                uflt16::decode(u16::from_le_bytes(array_at(chunk, field)))?;
            }
        }
        Ok(Self { data })
    }

    /// Number of satellites.
    ///
    /// ```
    /// use aydp_proto::FixDetail;
    /// assert_eq!(FixDetail::parse(&[1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]).unwrap().len(), 1);
    /// ```
    pub fn len(&self) -> usize {
        self.data.first().copied().unwrap_or(0) as usize
    }

    /// Whether the list is empty.
    ///
    /// ```
    /// use aydp_proto::FixDetail;
    /// assert!(FixDetail::parse(&[0]).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The data bytes.
    ///
    /// ```
    /// use aydp_proto::FixDetail;
    /// let data = [1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50];
    /// assert_eq!(FixDetail::parse(&data).unwrap().as_bytes(), &data);
    /// ```
    pub fn as_bytes(&self) -> &'a [u8] {
        self.data
    }

    /// Iterate over the satellites without copying the message.
    ///
    /// ```
    /// use aydp_proto::FixDetail;
    /// let detail = FixDetail::parse(&[1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]).unwrap();
    /// let ids: Vec<(u8, f32)> = detail.satellites().map(|s| (s.id, s.snr)).collect();
    /// assert_eq!(ids, [(7, 38.0)]);
    /// ```
    pub fn satellites(&self) -> Satellites<'a> {
        Satellites {
            chunks: self
                .data
                .get(1..)
                .unwrap_or(&[])
                .chunks_exact(Satellite::LEN),
        }
    }

    /// Collect into a bounded list; fails if more than `M` satellites.
    ///
    /// ```
    /// use aydp_proto::{Error, FixDetail};
    /// let detail = FixDetail::parse(&[1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]).unwrap();
    /// assert_eq!(detail.to_list::<4>().unwrap()[0].id, 7);
    /// assert_eq!(detail.to_list::<0>(), Err(Error::TooManySatellites(1)));
    /// ```
    pub fn to_list<const M: usize>(&self) -> Result<SatelliteList<M>> {
        let mut out = SatelliteList::<M>::new();
        for s in self.satellites() {
            out.push(s)
                .map_err(|_| Error::TooManySatellites(self.len()))?;
        }
        Ok(out)
    }
}

impl Payload for FixDetail<'_> {
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

/// Iterator over the satellites of a [`FixDetail`].
///
/// ```
/// use aydp_proto::FixDetail;
/// let detail = FixDetail::parse(&[1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]).unwrap();
/// let mut satellites = detail.satellites();
/// assert_eq!(satellites.next().map(|s| s.azimuth), Some(180.0));
/// assert_eq!(satellites.next(), None);
/// ```
#[derive(Debug, Clone)]
pub struct Satellites<'a> {
    chunks: core::slice::ChunksExact<'a, u8>,
}

impl Iterator for Satellites<'_> {
    type Item = Satellite;
    fn next(&mut self) -> Option<Satellite> {
        let chunk = self.chunks.next()?;
        let b: [u8; Satellite::LEN] = array_at(chunk, 0);
        // Validated by `FixDetail::parse`; a negative value cannot occur here.
        Satellite::parse(&b).ok()
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        self.chunks.size_hint()
    }
}

/// Builds a [`FixDetail`] into a caller's buffer.
///
/// ```
/// use aydp_proto::{FixDetailBuilder, Satellite};
/// let mut buf = [0u8; 8];
/// let mut b = FixDetailBuilder::new(&mut buf);
/// assert!(b.push(Satellite::default()).is_ok());
/// assert!(b.push(Satellite::default()).is_err()); // buffer full
/// ```
#[derive(Debug)]
pub struct FixDetailBuilder<'b> {
    buf: &'b mut [u8],
    count: u8,
}

impl<'b> FixDetailBuilder<'b> {
    /// Start an empty list in `buf` (needs at least 1 byte to finish).
    ///
    /// ```
    /// use aydp_proto::FixDetailBuilder;
    /// let mut buf = [0xAA; 8];
    /// assert_eq!(FixDetailBuilder::new(&mut buf).finish().as_bytes(), &[0]);
    /// ```
    pub fn new(buf: &'b mut [u8]) -> Self {
        Self { buf, count: 0 }
    }

    /// Append a satellite; fails ([`EncodeError::BufferTooSmall`], [`EncodeError::TooLong`]) if
    /// the buffer is full or 255 are already held.
    ///
    /// ```
    /// use aydp_proto::{EncodeError, FixDetailBuilder, Satellite};
    /// let mut buf = [0u8; 8];
    /// let mut builder = FixDetailBuilder::new(&mut buf);
    /// assert_eq!(builder.push(Satellite::default()), Ok(()));
    /// assert_eq!(builder.push(Satellite::default()), Err(EncodeError::BufferTooSmall { needed: 15 }));
    /// ```
    pub fn push(&mut self, sat: Satellite) -> core::result::Result<(), EncodeError> {
        let at = 1 + self.count as usize * Satellite::LEN;
        if self.count == u8::MAX {
            return Err(EncodeError::TooLong);
        }
        let Some(dst) = self.buf.get_mut(at..at + Satellite::LEN) else {
            return Err(EncodeError::BufferTooSmall {
                needed: at + Satellite::LEN,
            });
        };
        put(dst, 0, &sat.data());
        self.count += 1;
        Ok(())
    }

    /// The finished view.
    ///
    /// ```
    /// use aydp_proto::{FixDetailBuilder, Satellite};
    /// let mut buf = [0u8; 16];
    /// let mut builder = FixDetailBuilder::new(&mut buf);
    /// builder.push(Satellite { id: 7, azimuth: 180.0, elevation: 45.0, snr: 38.0 }).unwrap();
    /// assert_eq!(builder.finish().as_bytes(), &[1, 7, 0xA0, 0x59, 0xA0, 0x51, 0xC0, 0x50]);
    /// ```
    pub fn finish(self) -> FixDetail<'b> {
        let n = 1 + self.count as usize * Satellite::LEN;
        if let Some(c) = self.buf.first_mut() {
            *c = self.count;
        }
        let buf: &'b [u8] = self.buf;
        FixDetail {
            data: buf.get(..n).unwrap_or(&[]),
        }
    }
}
