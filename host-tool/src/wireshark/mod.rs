//! The Wireshark Lua dissector (printed by `protolink wireshark`), generated from the protocol crates' own
//! layout tables (`aeolus_proto::message::*::FIELDS`, `aydp_proto::Position::FIELDS` and the
//! other typed messages' `FIELDS`, `aok_proto::Command::FRAMES` and `Message::FRAMES`), which
//! each crate builds from its private layout, so it cannot drift from the code.
//!
//! The dissector reads AEOLUS on UDP ports 5001 and 5002 and on the AEOLUS stream link type
//! (USER0, 147): every message per datagram, escapes undone (the unescaped frame is shown as its
//! own data source), the CRC-16 checked and flagged (`aeolus.crc_status`: `ok`, `none` for a
//! frame sent without CRC, `bad`), every field of every fixed-size message, TOAST and COMMAND
//! text, the raw messages' bytes. On USER0 a frame split across chunks is joined: it is
//! dissected in the chunk that closes it, as `decode` reports it. AYDP (USER1 Spec, USER2 and
//! TCP/UDP 6321 Reference) is in [`aydp`], AOK (USER3, USER4) in [`aok`]. A copy is kept in
//! `tools/wireshark/protolink.lua`.
//!
//! Each part's hand-written Lua (framing, checksums, the scan, walking the tables) is a file
//! in `lua/` that `include_str!` reads; the code here writes the tables from the layouts
//! between those files, and fills their few `@NAME@` slots with the crates' constants.

pub mod aeolus;
pub(crate) mod aok;
pub(crate) mod aydp;

use std::fmt::Display;

use crate::error::Result;

/// The dissector's Lua source: AEOLUS (with the head), then AYDP, then AOK.
///
/// # Errors
/// [`Error::Unsupported`](crate::error::Error::Unsupported) if a layout names a field type
/// the generator does not know (a test keeps this from ever shipping).
pub(crate) fn lua() -> Result<String> {
    let mut s = String::new();
    aeolus::lua(&mut s)?;
    aydp::lua(&mut s);
    aok::lua(&mut s);
    Ok(s)
}

/// `template` (a hand-written part of the dissector in `lua/`) with every `@NAME@` slot
/// replaced by its value.
fn fill(template: &str, slots: &[(&str, &dyn Display)]) -> String {
    let mut text = template.to_string();
    for (name, value) in slots {
        text = text.replace(&format!("@{name}@"), &value.to_string());
    }
    text
}
