//! What the C message structs share: each has its place in the stream (`offset`, `wire_len`),
//! written when one is decoded, and all but AOK's have raw data (`data`, `data_len`), read
//! when one is encoded.

use core::ptr::null;

use crate::aeolus::pl_aeolus_message;
use crate::aok::pl_aok_item;
use crate::aydp::pl_aydp_message;
use crate::gdl90::pl_gdl90_message;

/// A C message struct: it has a message's place.
pub(crate) trait Placed {
    /// Writes the message's place in the stream.
    fn place(&mut self, offset: u64, wire_len: u32);
}

/// A C message struct as an encoder reads it.
pub(crate) trait Raw {
    /// Its raw data as the caller gave it (`data`, `data_len`): NULL and 0 for a struct
    /// without.
    fn raw(&self) -> (*const u8, usize);
}

/// [`Placed`] for every C message struct and [`Raw`] for those with raw data: the same
/// fields in each.
macro_rules! messages {
    (placed: $($msg:ty),*; raw: $($raw:ty),*) => {
        $(impl Placed for $msg {
            fn place(&mut self, offset: u64, wire_len: u32) {
                (self.offset, self.wire_len) = (offset, wire_len);
            }
        })*
        $(impl Raw for $raw {
            fn raw(&self) -> (*const u8, usize) {
                (self.data, self.data_len)
            }
        })*
    };
}
messages!(
    placed: pl_aeolus_message, pl_aydp_message, pl_aok_item, pl_gdl90_message;
    raw: pl_aeolus_message, pl_aydp_message, pl_gdl90_message
);

impl Raw for pl_aok_item {
    fn raw(&self) -> (*const u8, usize) {
        (null(), 0)
    }
}
