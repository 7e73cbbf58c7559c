//! The AOK PC-side decoder (the device's stream) on any byte stream, with the pending request
//! switched by the input itself: no panic, whatever arrives.
#![no_main]
use aeolus_proto::Decode as _;
use aok_proto::{FirmwareVersion, MessageDecoder, ReplyForm, WaypointSlot, Expect};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&cfg, rest)) = data.split_first() else { return };
    let fw = if cfg & 1 == 0 { FirmwareVersion::new(0, 30) } else { FirmwareVersion::LATEST };
    let mut d = MessageDecoder::new(fw);
    for (i, &b) in rest.iter().enumerate() {
        if i % 37 == (cfg as usize >> 1) % 37 {
            d.expect(match b & 3 {
                0 => Expect::Ack,
                1 => Expect::Parameter(b),
                2 => Expect::Bulk(b),
                _ => Expect::Waypoint(WaypointSlot::from_wire(b).unwrap_or(WaypointSlot::FbcTarget)),
            });
        }
        d.feed(&[b], |ev| {
            let Ok(m) = ev else { return };
            let mut out = [0u8; 32];
            let form = if fw == FirmwareVersion::LATEST { ReplyForm::Headed } else { ReplyForm::Headerless };
            let n = m.emit(&mut out, form).unwrap();
            assert_eq!(n, m.buffer_len(form));
        });
    }
    d.finish(|_| {});
});
