//! 1 MiB of random bytes into each decoder: no panic, and the invariants hold.

#[path = "support/events.rs"]
mod events;
use events::{idle_all, push_all};

use aok_proto::pc::{Expect, PcDecoder};
use aok_proto::{Command, DeviceDecoder, FirmwareVersion, Message, WaypointSlot};

const MIB: usize = 1 << 20;

/// xorshift64*, fixed seed: deterministic.
struct Rng(u64);
impl Rng {
    fn byte(&mut self) -> u8 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 56) as u8
    }
}

#[test]
fn device_decoder_survives_random_bytes() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut dec = DeviceDecoder::new();
    let mut ok = 0u32;
    for i in 0..MIB {
        for cmd in push_all(&mut dec, rng.byte()).into_iter().flatten() {
            ok += 1;
            // Whatever was accepted re-encodes and re-parses to itself.
            let mut buf = [0u8; 19];
            let n = cmd.emit(&mut buf).unwrap();
            assert_eq!(Command::parse(&buf[..n]), Ok((cmd, n)));
        }
        if i % 4099 == 0 {
            ok += idle_all(&mut dec).iter().filter(|e| e.is_ok()).count() as u32;
        }
        assert!(dec.held_bytes() < 19);
    }
    let s = dec.stats();
    assert_eq!(s.frames_ok, ok);
    assert!(s.frames_ok > 0 && s.checksum_errors > 0 && s.unknown_bytes > 0);
    assert!(s.bytes_discarded as usize <= MIB);
}

#[test]
fn pc_decoder_survives_random_bytes() {
    for fw in [FirmwareVersion::new(0, 30), FirmwareVersion::LATEST] {
        let mut rng = Rng(0xdead_beef_cafe_f00d);
        let mut dec = PcDecoder::new(fw);
        let expects = [
            Expect::Nothing,
            Expect::Ack,
            Expect::Parameter(12),
            Expect::Bulk(0),
            Expect::Waypoint(WaypointSlot::FbcTarget),
        ];
        let mut n_msgs = 0u32;
        for i in 0..MIB {
            if i % 1000 == 0 {
                dec.expect(expects[(i / 1000) % expects.len()]);
            }
            for m in push_all(&mut dec, rng.byte()).into_iter().flatten() {
                n_msgs += 1;
                if let Message::Waypoint(w) = m {
                    let mut buf = [0u8; 19];
                    assert_eq!(m.emit(fw.reply_form(), &mut buf), Ok(19));
                    assert_eq!(buf[1], w.slot.wire());
                }
            }
            if i % 5003 == 0 {
                n_msgs += idle_all(&mut dec).iter().filter(|e| e.is_ok()).count() as u32;
            }
            assert!(dec.held_bytes() < 19);
        }
        assert_eq!(dec.stats().frames_ok, n_msgs);
        assert!(n_msgs > 0);
    }
}

/// The typed parses on random slices of every length: no panic, a success takes no more
/// bytes than it was given and re-encodes to exactly those bytes, and `Truncated` means the
/// slice was too short (the same bytes with enough after them never give it).
#[test]
fn parsers_survive_random_slices() {
    let mut rng = Rng(42);
    let mut buf = [0u8; 24];
    let (mut commands, mut messages, mut headerless) = (0u32, 0u32, 0u32);
    for _ in 0..(MIB / 24) {
        buf.iter_mut().for_each(|b| *b = rng.byte());
        let len = usize::from(rng.byte()) % 25;
        let slice = &buf[..len];
        let mut out = [0u8; 24];
        match Command::parse(slice) {
            Ok((c, n)) => {
                commands += 1;
                assert!(n <= len, "{c:?} took {n} of {len} bytes");
                assert_eq!(c.emit(&mut out), Ok(n), "{c:?}");
                assert_eq!(out[..n], slice[..n], "{c:?}");
            }
            Err(aok_proto::Error::Truncated) => {
                assert_ne!(
                    Command::parse(&buf),
                    Err(aok_proto::Error::Truncated),
                    "{buf:02x?}"
                )
            }
            Err(_) => {}
        }
        match Message::parse(slice) {
            Ok((m, n)) => {
                messages += 1;
                assert!(n <= len, "{m:?} took {n} of {len} bytes");
                assert_eq!(
                    m.emit(aok_proto::ReplyForm::Headed, &mut out),
                    Ok(n),
                    "{m:?}"
                );
                assert_eq!(out[..n], slice[..n], "{m:?}");
            }
            Err(aok_proto::Error::Truncated) => {
                assert_ne!(
                    Message::parse(&buf),
                    Err(aok_proto::Error::Truncated),
                    "{buf:02x?}"
                )
            }
            Err(_) => {}
        }
        match aok_proto::ParameterValue::parse_headerless(slice, 1) {
            Ok(p) => {
                headerless += 1;
                assert_eq!(p.number, 1);
                let m = Message::Parameter(p);
                assert_eq!(m.emit(aok_proto::ReplyForm::Headerless, &mut out), Ok(5));
                assert_eq!(out[..5], slice[..5], "{p:?}");
            }
            Err(e) => assert!(
                len < 5 || matches!(e, aok_proto::Error::ChecksumMismatch { .. }),
                "{e:?} from {len} bytes"
            ),
        }
    }
    // Random bytes reach the success paths too (ack bytes, unchecked short commands, one
    // checksum in 256), so the round-trip assertions above were exercised.
    assert!(
        commands > 100 && messages > 100 && headerless > 50,
        "{commands} {messages} {headerless}"
    );
}
