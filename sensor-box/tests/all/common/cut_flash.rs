//! A NOR flash that can lose power anywhere: the model the power-cut tests run the store on.
//!
//! [`CutFlash`] counts every byte of every erase and every program as one step. Armed with
//! [`CutFlash::cut_at`]`(k)`, it does the first `k` steps and then loses power:
//!
//! * an erase cut short leaves the bytes before the cut erased and, from the cut on, each byte
//!   of the erase range either as it was or erased ([`Tear`] picks: all as they were, or a
//!   per-byte mix drawn from the seed);
//! * a program cut short leaves the bytes before the cut's write unit programmed and the unit
//!   holding the cut half-programmed: it reads back as the old bits, the new bits, or a mix
//!   (some of the bits to clear cleared), as [`Tear`] says;
//! * after the cut every call fails until [`CutFlash::reboot`].
//!
//! Programming ANDs (bits only go from 1 to 0), as on real NOR flash and in `MemFlash`.
//! Host tests only: it lives in the tests, never in a firmware binary.

use embedded_storage::nor_flash::{ErrorType, NorFlash, ReadNorFlash};
use sensor_box::storage::Error;

/// What the unit (or the rest of the erase range) holding the cut reads back as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tear {
    /// The half-programmed unit reads its old bits; a cut erase leaves the rest as it was.
    Old,
    /// The half-programmed unit reads the new bits; a cut erase leaves the rest as it was.
    New,
    /// Some bits of the unit programmed, others not; a cut erase leaves a mix of erased and
    /// untouched bytes (both drawn from the seed).
    Mixed(u64),
}

/// NOR flash in a `Vec`, `W`-byte program units, `E`-byte erase pages, that loses power at a
/// chosen step.
#[derive(Debug, Clone)]
pub struct CutFlash<const W: usize = 4, const E: usize = 1024> {
    /// The flash contents.
    pub mem: Vec<u8>,
    /// Steps (bytes erased or programmed) done since the last [`CutFlash::reboot`].
    pub steps: u64,
    /// Erase calls done since the last reboot.
    pub erases: u64,
    /// Bytes erased since the last reboot.
    pub erased_bytes: u64,
    cut: Option<u64>,
    tear: Tear,
    dead: bool,
}

impl<const W: usize, const E: usize> CutFlash<W, E> {
    /// A flash of `len` bytes, all `fill`.
    pub fn new(len: usize, fill: u8) -> Self {
        CutFlash {
            mem: vec![fill; len],
            steps: 0,
            erases: 0,
            erased_bytes: 0,
            cut: None,
            tear: Tear::Old,
            dead: false,
        }
    }

    /// Loses power when `k` more steps have been done, tearing as `tear` says.
    pub fn cut_at(&mut self, k: u64, tear: Tear) {
        self.cut = Some(self.steps + k);
        self.tear = tear;
    }

    /// Whether the power was cut.
    pub fn is_dead(&self) -> bool {
        self.dead
    }

    /// Power comes back: calls work again, the counters restart.
    pub fn reboot(&mut self) {
        self.dead = false;
        self.cut = None;
        self.steps = 0;
        self.erases = 0;
        self.erased_bytes = 0;
    }

    /// How many steps an operation of `n` bytes may do before the cut (`n`: all of them).
    fn allowed(&self, n: usize) -> usize {
        match self.cut {
            Some(at) => usize::try_from(at.saturating_sub(self.steps)).map_or(n, |a| a.min(n)),
            None => n,
        }
    }

    fn range(&self, offset: u32, len: usize) -> Result<core::ops::Range<usize>, Error> {
        let start = offset as usize;
        let end = start.checked_add(len).ok_or(Error::OutOfBounds)?;
        if end > self.mem.len() {
            return Err(Error::OutOfBounds);
        }
        Ok(start..end)
    }
}

/// xorshift64*: a deterministic stream from a seed.
fn mix(seed: u64, i: u64) -> u64 {
    let mut x = seed ^ i.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    x.wrapping_mul(0x2545_F491_4F6C_DD1D)
}

impl<const W: usize, const E: usize> ErrorType for CutFlash<W, E> {
    type Error = Error;
}

impl<const W: usize, const E: usize> ReadNorFlash for CutFlash<W, E> {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Error> {
        if self.dead {
            return Err(Error::Device);
        }
        let r = self.range(offset, bytes.len())?;
        bytes.copy_from_slice(&self.mem[r]);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.mem.len()
    }
}

impl<const W: usize, const E: usize> NorFlash for CutFlash<W, E> {
    const WRITE_SIZE: usize = W;
    const ERASE_SIZE: usize = E;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Error> {
        if self.dead {
            return Err(Error::Device);
        }
        if from > to {
            return Err(Error::OutOfBounds);
        }
        let r = self.range(from, (to - from) as usize)?;
        if r.start % E != 0 || r.end % E != 0 {
            return Err(Error::NotAligned);
        }
        self.erases += 1;
        let n = r.len();
        let done = self.allowed(n);
        self.mem[r.start..r.start + done].fill(0xFF);
        self.steps += done as u64;
        self.erased_bytes += done as u64;
        if done == n {
            return Ok(());
        }
        if let Tear::Mixed(seed) = self.tear {
            for i in r.start + done..r.end {
                if mix(seed, i as u64) & 1 == 0 {
                    self.mem[i] = 0xFF;
                }
            }
        }
        self.dead = true;
        Err(Error::Device)
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Error> {
        if self.dead {
            return Err(Error::Device);
        }
        let r = self.range(offset, bytes.len())?;
        if r.start % W != 0 || r.end % W != 0 {
            return Err(Error::NotAligned);
        }
        let n = bytes.len();
        let done = self.allowed(n);
        // Whole units before the cut are programmed.
        let whole = done - done % W;
        for (d, s) in self.mem[r.start..r.start + whole].iter_mut().zip(bytes) {
            *d &= *s;
        }
        self.steps += done as u64;
        if done == n {
            return Ok(());
        }
        // The unit holding the cut: half-programmed.
        let unit = r.start + whole..r.start + whole + W;
        for (i, (d, s)) in self.mem[unit.clone()]
            .iter_mut()
            .zip(&bytes[whole..whole + W])
            .enumerate()
        {
            *d = match self.tear {
                Tear::Old => *d,
                Tear::New => *d & *s,
                Tear::Mixed(seed) => *d & (*s | mix(seed, (unit.start + i) as u64) as u8),
            };
        }
        self.dead = true;
        Err(Error::Device)
    }
}
