//! AOK on UART2.
//!
//! STUB: to be implemented.

use super::Shared;
use embedded_hal_nb::serial::{Read, Write};

/// The AOK link.
pub struct AokLink {}

impl AokLink {
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

impl AokLink {
    /// The link at boot (loads the start parameter set from the persisted record).
    pub fn new(shared: &Shared) -> Self {
        let _ = shared;
        AokLink {}
    }
}
