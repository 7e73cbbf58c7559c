//! Little-endian field codecs (DECISIONS.md A1) used by the message layouts.

use super::CalibrationStatus;

/// A value that sits at a fixed offset of a message's data.
pub(crate) trait Field: Sized {
    /// Bytes on the wire.
    const SIZE: usize;
    /// Reads the value at `off`; the caller has checked the length, so the fallback of zeros is
    /// never used (it only keeps the code free of panic paths).
    fn read(data: &[u8], off: usize) -> Self;
    /// Writes the value at `off`.
    fn write(&self, out: &mut [u8], off: usize);
}

#[inline(always)]
fn take<const W: usize>(data: &[u8], off: usize) -> [u8; W] {
    let mut bytes = [0u8; W];
    if let Some(src) = data.get(off..off.wrapping_add(W)) {
        bytes.copy_from_slice(src);
    }
    bytes
}

#[inline(always)]
fn put<const W: usize>(out: &mut [u8], off: usize, bytes: [u8; W]) {
    if let Some(dst) = out.get_mut(off..off.wrapping_add(W)) {
        dst.copy_from_slice(&bytes);
    }
}

macro_rules! le_field {
    ($($t:ty),*) => {$(
        impl Field for $t {
            const SIZE: usize = core::mem::size_of::<$t>();
            #[inline(always)]
            fn read(data: &[u8], off: usize) -> Self {
                <$t>::from_le_bytes(take(data, off))
            }
            #[inline(always)]
            fn write(&self, out: &mut [u8], off: usize) {
                put(out, off, self.to_le_bytes())
            }
        }
    )*};
}
le_field!(u8, f32, f64);

impl Field for bool {
    const SIZE: usize = 1;
    /// Any non-zero byte reads as `true`; `true` is written as 1.
    #[inline(always)]
    fn read(data: &[u8], off: usize) -> Self {
        u8::read(data, off) != 0
    }
    #[inline(always)]
    fn write(&self, out: &mut [u8], off: usize) {
        u8::from(*self).write(out, off)
    }
}

impl Field for CalibrationStatus {
    const SIZE: usize = 1;
    #[inline(always)]
    fn read(data: &[u8], off: usize) -> Self {
        CalibrationStatus::from_i8(u8::read(data, off) as i8)
    }
    #[inline(always)]
    fn write(&self, out: &mut [u8], off: usize) {
        (self.to_i8() as u8).write(out, off)
    }
}

impl<T: Field + Copy + Default, const K: usize> Field for [T; K] {
    const SIZE: usize = T::SIZE * K;
    #[inline(always)]
    fn read(data: &[u8], off: usize) -> Self {
        // Built element by element: no zeroed array to fill afterwards.
        core::array::from_fn(|i| T::read(data, off + i * T::SIZE))
    }
    #[inline(always)]
    fn write(&self, out: &mut [u8], off: usize) {
        for (i, v) in self.iter().enumerate() {
            v.write(out, off + i * T::SIZE);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Field;

    /// The layouts' compile-time check (`_FITS`) adds each field's offset and `SIZE`: an
    /// array's size must be its elements' sizes summed.
    #[test]
    fn an_array_field_is_its_elements_long() {
        assert_eq!(<[u8; 6] as Field>::SIZE, 6);
        assert_eq!(<[f32; 3] as Field>::SIZE, 12);
        assert_eq!(<[f32; 9] as Field>::SIZE, 36);
        assert_eq!(<[f64; 2] as Field>::SIZE, 16);
    }
}
