//! Shared pieces of the cross-crate tests and of the corruption-figures program:
//! a seeded RNG, the noisy channels, naive decoders, and the scoring of what a decoder
//! delivered against what was sent; and the app's side of an AEOLUS box on UDP; headless
//! Chromium for the browser tests of `protolink web`; skips that are never silent.

pub mod aeolus_gen;
pub mod aeolus_udp;
#[cfg(feature = "browser")]
pub mod browser;
#[cfg(feature = "browser")]
mod cdp;
pub mod channel;
pub mod examples;
pub mod gdl90_hand;
pub mod naive;
pub mod protocols;
pub mod resync;
pub mod rng;
pub mod score;
pub mod skip;
pub mod tshark;
