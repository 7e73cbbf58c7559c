//! The noisy channels of the corruption figures.

use crate::rng::Rng;

/// What the channel does to the stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Channel {
    /// (a) Inserts 0..=max bytes of protocol-flavoured garbage before every frame.
    Garbage {
        /// Most garbage bytes inserted before one frame.
        max: usize,
    },
    /// (b) Flips every bit independently with this probability (bit error rate).
    BitFlips {
        /// Bit error rate.
        ber: f64,
    },
    /// (c) Drops every byte independently with this probability.
    Drops {
        /// Probability that a byte is lost.
        rate: f64,
    },
}

impl core::fmt::Display for Channel {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Channel::Garbage { max } => write!(f, "(a) garbage 0..={max} B between frames"),
            Channel::BitFlips { ber } => write!(f, "(b) bit flips, BER {ber:e}"),
            Channel::Drops { rate } => write!(f, "(c) byte drops, rate {rate:e}"),
        }
    }
}

impl Channel {
    /// Passes one frame's wire bytes through the channel, appending the result to `out`.
    /// `garbage` makes the protocol's garbage for case (a). Returns whether the frame's own
    /// bytes arrived untouched.
    pub fn pass(
        &self,
        rng: &mut Rng,
        frame: &[u8],
        out: &mut Vec<u8>,
        garbage: &mut dyn FnMut(&mut Rng, usize) -> Vec<u8>,
    ) -> bool {
        match *self {
            Channel::Garbage { max } => {
                let n = rng.below(max as u64 + 1) as usize;
                out.extend(garbage(rng, n));
                out.extend_from_slice(frame);
                true
            }
            Channel::BitFlips { ber } => {
                let mut intact = true;
                for &b in frame {
                    let mut b2 = b;
                    for bit in 0..8 {
                        if rng.chance(ber) {
                            b2 ^= 1 << bit;
                        }
                    }
                    intact &= b2 == b;
                    out.push(b2);
                }
                intact
            }
            Channel::Drops { rate } => {
                let mut intact = true;
                for &b in frame {
                    if rng.chance(rate) {
                        intact = false;
                    } else {
                        out.push(b);
                    }
                }
                intact
            }
        }
    }
}
