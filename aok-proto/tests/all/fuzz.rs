//! 1 MiB of random bytes into each decoder: no panic, and the invariants hold; and the three
//! ways through the contract agree on it: `feed` one byte at a time (the reference), `feed`
//! with whole segments and the pull form (`decode`), the same events and counters.

use crate::events;
use events::{Events, decode_all, feed_byte, finish_all};

use aok_proto::WaypointSlot;
use aok_proto::{Command, CommandDecoder, Error, Expect, FirmwareVersion, Message, MessageDecoder};

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

/// The bulk path (`feed` with a whole segment) and the pull form beside the reference:
/// each takes the same segments and gives its events in its own list.
struct Others<D: Events> {
    whole: D,
    pull: D,
    by_whole: Vec<Result<D::Item, Error>>,
    by_pull: Vec<Result<D::Item, Error>>,
}

impl<D: Events + Clone> Others<D> {
    fn new(d: &D) -> Self {
        Self {
            whole: d.clone(),
            pull: d.clone(),
            by_whole: Vec::new(),
            by_pull: Vec::new(),
        }
    }
    fn segment(&mut self, bytes: &[u8]) {
        self.by_whole.extend(self.whole.feed_vec(bytes));
        self.by_pull.extend(decode_all(&mut self.pull, bytes));
    }
    fn finish(&mut self) {
        self.by_whole.extend(finish_all(&mut self.whole));
        self.by_pull.extend(finish_all(&mut self.pull));
    }
}

#[test]
fn device_decoder_survives_random_bytes() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let bytes: Vec<u8> = (0..MIB).map(|_| rng.byte()).collect();
    let mut dec = CommandDecoder::new();
    let mut others = Others::new(&dec);
    let mut reference = Vec::new();
    let mut start = 0;
    let mut ok = 0u32;
    for (i, &b) in bytes.iter().enumerate() {
        let events = feed_byte(&mut dec, b);
        reference.extend(events.iter().cloned());
        for cmd in events.into_iter().flatten() {
            ok += 1;
            // Whatever was accepted re-encodes and re-parses to itself.
            let mut buf = [0u8; 19];
            let n = cmd.emit(&mut buf).unwrap();
            assert_eq!(Command::parse(&buf[..n]), Ok((cmd, n)));
        }
        if i % 4099 == 0 {
            let end = finish_all(&mut dec);
            ok += end.iter().filter(|e| e.is_ok()).count() as u32;
            reference.extend(end);
            others.segment(&bytes[start..=i]);
            others.finish();
            start = i + 1;
            assert_eq!(others.whole.stats(), dec.stats(), "feed whole, byte {i}");
            assert_eq!(others.pull.stats(), dec.stats(), "decode, byte {i}");
        }
        assert!(dec.held_bytes() < 19);
    }
    others.segment(&bytes[start..]);
    let s = dec.stats();
    assert_eq!(s.frames_ok, ok);
    assert!(s.frames_ok > 0 && s.checksum_errors > 0 && s.unknown_bytes > 0);
    assert!(s.bytes_discarded as usize <= MIB);
    assert!(
        others.by_whole == reference,
        "feed whole differs from feed byte by byte"
    );
    assert!(
        others.by_pull == reference,
        "decode differs from feed byte by byte"
    );
    assert_eq!(others.whole.stats(), s);
    assert_eq!(others.pull.stats(), s);
}

#[test]
fn pc_decoder_survives_random_bytes() {
    for fw in [FirmwareVersion::new(0, 30), FirmwareVersion::LATEST] {
        let mut rng = Rng(0xdead_beef_cafe_f00d);
        let bytes: Vec<u8> = (0..MIB).map(|_| rng.byte()).collect();
        let mut dec = MessageDecoder::new(fw);
        let mut others = Others::new(&dec);
        let mut reference = Vec::new();
        let mut start = 0;
        let expects = [
            Expect::Nothing,
            Expect::Ack,
            Expect::Parameter(12),
            Expect::Bulk(0),
            Expect::Waypoint(WaypointSlot::FbcTarget),
        ];
        let mut n_msgs = 0u32;
        for (i, &b) in bytes.iter().enumerate() {
            if i % 1000 == 0 {
                let e = expects[(i / 1000) % expects.len()];
                others.segment(&bytes[start..i]);
                start = i;
                dec.expect(e);
                others.whole.expect(e);
                others.pull.expect(e);
            }
            let events = feed_byte(&mut dec, b);
            reference.extend(events.iter().cloned());
            for m in events.into_iter().flatten() {
                n_msgs += 1;
                if let Message::Waypoint(w) = m {
                    let mut buf = [0u8; 19];
                    assert_eq!(m.emit(&mut buf, fw.reply_form()), Ok(19));
                    assert_eq!(buf[1], w.slot.wire());
                }
            }
            if i % 5003 == 0 {
                let end = finish_all(&mut dec);
                n_msgs += end.iter().filter(|e| e.is_ok()).count() as u32;
                reference.extend(end);
                others.segment(&bytes[start..=i]);
                others.finish();
                start = i + 1;
                assert_eq!(others.whole.stats(), dec.stats(), "feed whole, byte {i}");
                assert_eq!(others.pull.stats(), dec.stats(), "decode, byte {i}");
            }
            assert!(dec.held_bytes() < 19);
        }
        others.segment(&bytes[start..]);
        assert_eq!(dec.stats().frames_ok, n_msgs);
        assert!(n_msgs > 0);
        assert!(
            others.by_whole == reference,
            "feed whole differs from feed byte by byte"
        );
        assert!(
            others.by_pull == reference,
            "decode differs from feed byte by byte"
        );
        assert_eq!(others.whole.stats(), dec.stats());
        assert_eq!(others.pull.stats(), dec.stats());
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
                    m.emit(&mut out, aok_proto::ReplyForm::Headed),
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
                assert_eq!(m.emit(&mut out, aok_proto::ReplyForm::Headerless), Ok(5));
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
