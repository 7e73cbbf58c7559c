//! AEOLUS on UART0.
//!
//! STUB: to be implemented.

use super::Shared;
use embedded_hal_nb::serial::{Read, Write};

/// The AEOLUS link.
pub struct AeolusLink {}

impl AeolusLink {
    /// Reads what arrived on the port, answers, and sends what is due at `now_ms`.
    pub fn poll<P: Read<u8> + Write<u8>>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        let _ = (now_ms, port, shared);
    }
}

impl AeolusLink {
    /// The link at boot.
    pub fn new(now_ms: u64) -> Self {
        let _ = now_ms;
        AeolusLink {}
    }
}
