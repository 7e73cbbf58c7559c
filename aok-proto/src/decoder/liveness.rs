//! Every entry point of both decoders returns, whatever the stream: each of their loops
//! consumes a byte or hands out an event per turn. A unit test rather than an integration
//! test because the library's unit tests run first: a rule that stops consuming (a loop that
//! makes no progress) fails here, at a deadline far above the microseconds the work takes,
//! instead of hanging the integration tests behind it.

extern crate std;

use crate::{Command, CommandDecoder, DebugValue, Error, FirmwareVersion, Message, MessageDecoder};
use crate::{Decode, ParameterValue, ReplyForm};
use std::vec::Vec;

#[path = "../../../frame-io/tests/support/deadline.rs"]
mod deadline;
use deadline::returns;

/// The PC's commands: noise, a motor test, a parameter set, a motor test with a bad checksum,
/// and a parameter set cut short by the end of the stream.
fn to_device() -> Vec<u8> {
    let mut s = std::vec![0x00, 0x31, 0x05, 0x31 ^ 0x05];
    let mut buf = [0u8; 7];
    let set = Command::SetParameter(ParameterValue {
        number: 12,
        value: 1500,
    });
    let n = set.emit(&mut buf).unwrap_or(0);
    s.extend_from_slice(&buf[..n]);
    s.extend_from_slice(&[0x32, 0x01, 0x00]);
    s.extend_from_slice(&buf[..3]);
    s
}

/// The device's messages: noise, a debug frame, a copy with a bad checksum, another debug
/// frame, and one cut short by the end of the stream.
fn to_pc() -> Vec<u8> {
    let mut buf = [0u8; 7];
    let v = DebugValue {
        number: 86,
        value: -2,
    };
    let n = Message::Debug(v)
        .emit(&mut buf, ReplyForm::Headed)
        .unwrap_or(0);
    let mut s = std::vec![0x00];
    s.extend_from_slice(&buf[..n]);
    let mut bad = buf;
    bad[6] ^= 0x01;
    s.extend_from_slice(&bad);
    s.extend_from_slice(&buf[..n]);
    s.extend_from_slice(&buf[..3]);
    s
}

fn device_byte_by_byte() -> Vec<Result<Command, Error>> {
    let mut dec = CommandDecoder::new();
    let mut got = Vec::new();
    for b in to_device() {
        dec.feed(core::slice::from_ref(&b), |ev| got.push(ev));
    }
    dec.finish(|ev| got.push(ev));
    got
}

fn device_by_feed_at_every_cut() -> Vec<Vec<Result<Command, Error>>> {
    let s = to_device();
    (0..=s.len())
        .map(|cut| {
            let (a, b) = s.split_at(cut);
            let mut dec = CommandDecoder::new();
            let mut got = Vec::new();
            dec.feed(a, |ev| got.push(ev));
            dec.feed(b, |ev| got.push(ev));
            dec.finish(|ev| got.push(ev));
            got
        })
        .collect()
}

fn pc_byte_by_byte() -> Vec<Result<Message, Error>> {
    let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
    let mut got = Vec::new();
    for b in to_pc() {
        dec.feed(core::slice::from_ref(&b), |ev| got.push(ev));
    }
    dec.finish(|ev| got.push(ev));
    got
}

fn pc_by_feed_at_every_cut() -> Vec<Vec<Result<Message, Error>>> {
    let s = to_pc();
    (0..=s.len())
        .map(|cut| {
            let (a, b) = s.split_at(cut);
            let mut dec = MessageDecoder::new(FirmwareVersion::LATEST);
            let mut got = Vec::new();
            dec.feed(a, |ev| got.push(ev));
            dec.feed(b, |ev| got.push(ev));
            dec.finish(|ev| got.push(ev));
            got
        })
        .collect()
}

#[test]
fn the_device_decoder_returns_with_the_streams_events() {
    let reference = returns("feed byte by byte and finish", device_byte_by_byte);
    assert_eq!(
        reference.iter().filter(|e| e.is_ok()).count(),
        2,
        "{reference:?}"
    );
    assert!(reference.contains(&Err(Error::Truncated)), "{reference:?}");
    for (cut, got) in returns("feed", device_by_feed_at_every_cut)
        .iter()
        .enumerate()
    {
        assert_eq!(got, &reference, "cut at {cut}");
    }
}

#[test]
fn the_pc_decoder_returns_with_the_streams_events() {
    let reference = returns("feed byte by byte and finish", pc_byte_by_byte);
    assert_eq!(
        reference.iter().filter(|e| e.is_ok()).count(),
        2,
        "{reference:?}"
    );
    assert!(reference.contains(&Err(Error::Truncated)), "{reference:?}");
    for (cut, got) in returns("feed", pc_by_feed_at_every_cut).iter().enumerate() {
        assert_eq!(got, &reference, "cut at {cut}");
    }
}

/// The end of the stream gives up the fronts it cannot complete and rescans what followed them,
/// and ends: a mutant that reports the same bytes again makes the readers of
/// `tests/all/io.rs` spin (a hang, not a failure); this fails at once instead (unit tests run
/// before the integration tests). The pull form's `end` (and so `finish`) gives exactly the events of
/// the quiet line's rule step.
#[test]
fn the_end_gives_up_the_bytes_held_once() {
    use crate::decoder::Rules;
    use frame_io::Event;
    let mut d = CommandDecoder::new();
    assert_eq!(Decode::decode(&mut d, &[0x31]), (1, None));
    assert_eq!(Decode::end(&mut d), Some(Event::Truncated(1)));
    assert_eq!(Decode::end(&mut d), None);
    assert_eq!(Decode::end(&mut d), None);
    let mut p = MessageDecoder::new(FirmwareVersion::LATEST);
    assert_eq!(Decode::decode(&mut p, &[0x1c, 0x56]), (2, None));
    // The reference: the quiet line's rule step itself, a front given up at a time.
    let mut by_step = p.clone();
    let mut want = std::vec::Vec::new();
    while let Some(event) = by_step.quiet_next() {
        want.push(event);
    }
    let mut got = std::vec::Vec::new();
    let mut given_up = 0;
    while let Some(event) = Decode::end(&mut p) {
        match event {
            Event::Found(m) => got.push(Ok(m)),
            Event::Error(e) => got.push(Err(e)),
            Event::Truncated(n) => {
                given_up += n;
                got.push(Err(crate::Error::Truncated));
            }
        }
        assert!(given_up <= 2, "more bytes given up than were held");
    }
    assert_eq!(got, want);
    assert_eq!((p.held_bytes(), p.stats()), (0, by_step.stats()));
    assert_eq!(Decode::end(&mut p), None);
}
