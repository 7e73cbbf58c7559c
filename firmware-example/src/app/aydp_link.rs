//! AYDP on UART1.
//!
//! STUB: to be implemented.

use super::Shared;
use embedded_hal_nb::serial::{Read, Write};

/// The AYDP link.
pub struct AydpLink {}

impl AydpLink {
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

impl AydpLink {
    /// The link at boot.
    pub fn new(now_ms: u64) -> Self {
        let _ = now_ms;
        AydpLink {}
    }
}
