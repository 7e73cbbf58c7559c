//! The AOK slice paths (`CommandDecoder::feed`, `MessageDecoder::feed` on chunks, and the pull
//! form `next_event` called on the rest until it finds nothing) against `feed` one byte a call:
//! on any byte stream, in chunks the input chooses, with the PC's pending request switched
//! between chunks, all give the same items, counters, pending request and bytes held after
//! every chunk, and the same `finish`.
#![no_main]
use aeolus_proto::Decode as _;
use aok_proto::{CommandDecoder, FirmwareVersion, MessageDecoder, WaypointSlot, Expect};
use libfuzzer_sys::fuzz_target;

fn chunks<'a>(cuts: &'a [u8], data: &'a [u8]) -> impl Iterator<Item = (u8, &'a [u8])> + 'a {
    let mut rest = data;
    let mut i = 0;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let c = cuts.get(i % cuts.len().max(1)).copied().unwrap_or(0x1F);
        // 0..=31 bytes a chunk; every fourth chunk has one or more.
        let n = if i % 4 == 3 {
            (c as usize % 32).max(1)
        } else {
            c as usize % 32
        }
        .min(rest.len());
        i += 1;
        let (chunk, tail) = rest.split_at(n);
        rest = tail;
        Some((c, chunk))
    })
}

/// `next_event` on what each call left, until it finds nothing in what is left.
fn until_all<T>(mut next_event: impl FnMut(&[u8]) -> (usize, Option<T>), bytes: &[u8]) -> Vec<T> {
    let (mut rest, mut out) = (bytes, Vec::new());
    loop {
        let (n, ev) = next_event(rest);
        assert!(n <= rest.len());
        let found = ev.is_some();
        assert!(found || n == rest.len());
        out.extend(ev);
        rest = &rest[n..];
        if !found && rest.is_empty() {
            return out;
        }
    }
}

fuzz_target!(|input: &[u8]| {
    // First byte: firmware and how many chunk sizes follow; then the sizes; then data.
    let Some((&cfg, rest)) = input.split_first() else {
        return;
    };
    let (cuts, data) = rest.split_at((cfg as usize & 7).min(rest.len()));

    let mut slow = CommandDecoder::new();
    let mut fast = CommandDecoder::new();
    let mut until = CommandDecoder::new();
    for (_, chunk) in chunks(cuts, data) {
        let mut want = Vec::new();
        for &b in chunk {
            slow.feed(&[b], |ev| {
                want.push(ev);
            });
        }
        let mut got = Vec::new();
        fast.feed(chunk, |c| got.push(c));
        assert_eq!(got, want);
        assert_eq!(fast.stats(), slow.stats());
        assert_eq!(fast.held_bytes(), slow.held_bytes());
        assert_eq!(until_all(|b| until.next_event(b), chunk), want);
        assert_eq!(until.stats(), slow.stats());
        assert_eq!(until.held_bytes(), slow.held_bytes());
    }
    let (mut want, mut got) = (Vec::new(), Vec::new());
    slow.finish(|ev| want.push(ev));
    fast.finish(|ev| got.push(ev));
    assert_eq!(got, want);
    assert_eq!(fast.stats(), slow.stats());

    let fw = match (cfg >> 3) & 3 {
        0 => FirmwareVersion::new(0, 30),
        1 => FirmwareVersion::new(0, 31),
        _ => FirmwareVersion::LATEST,
    };
    let mut slow = MessageDecoder::new(fw);
    let mut fast = MessageDecoder::new(fw);
    let mut until = MessageDecoder::new(fw);
    for (c, chunk) in chunks(cuts, data) {
        let mut want = Vec::new();
        for &b in chunk {
            slow.feed(&[b], |ev| {
                want.push(ev);
            });
        }
        let mut got = Vec::new();
        fast.feed(chunk, |m| got.push(m));
        assert_eq!(got, want);
        assert_eq!(fast.stats(), slow.stats());
        assert_eq!(fast.held_bytes(), slow.held_bytes());
        assert_eq!(fast.expecting(), slow.expecting());
        assert_eq!(until_all(|b| until.next_event(b), chunk), want);
        assert_eq!(until.stats(), slow.stats());
        assert_eq!(until.held_bytes(), slow.held_bytes());
        assert_eq!(until.expecting(), slow.expecting());
        // The chunk-size byte also picks the next pending request.
        let e = match c >> 5 {
            0 => None,
            1 => Some(Expect::Ack),
            2 | 3 => Some(Expect::Parameter(c & 3)),
            4 => Some(Expect::Bulk((c & 3).wrapping_sub(15))),
            5 => Some(Expect::Waypoint(
                WaypointSlot::from_wire(c & 0x1F).unwrap_or(WaypointSlot::FbcTarget),
            )),
            _ => Some(Expect::Nothing),
        };
        if let Some(e) = e {
            slow.expect(e);
            fast.expect(e);
            until.expect(e);
        }
    }
    let (mut want, mut got) = (Vec::new(), Vec::new());
    slow.finish(|ev| want.push(ev));
    fast.finish(|ev| got.push(ev));
    assert_eq!(got, want);
    assert_eq!(fast.stats(), slow.stats());
});
