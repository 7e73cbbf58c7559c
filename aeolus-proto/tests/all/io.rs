//! The `embedded-io` and `embedded-io-async` readers deliver exactly what `Decoder::push`
//! delivers byte by byte, whatever the read sizes (1 byte up to more than the buffer), with
//! pending reads, transport errors in mid-frame and EOF; the writers produce exactly the bytes
//! of `encode_frame`.

use crate::common;
use crate::transport;

use aeolus_proto::Decode;
use aeolus_proto::{
    CrcMode, Decoder, Error, IoError, embedded_io as bio, embedded_io_async as aio, encode_frame,
    max_encoded_len, message::Message,
};
use common::arb_message;
use embedded_io::ErrorKind;
use proptest::prelude::*;
use transport::{Sink, Wire, block_on, sink};

/// One thing a reader (or the byte-at-a-time reference) reports.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Event {
    Frame(Vec<u8>, bool),
    Protocol(Error),
    UnexpectedEof(usize),
    Eof,
}

/// The reference: every byte through `push`, then the end of the stream.
fn reference<const N: usize>(stream: &[u8]) -> (Vec<Event>, aeolus_proto::Stats) {
    let mut d = Decoder::<N>::new();
    let mut out = Vec::new();
    for &b in stream {
        d.feed(&[b], |ev| match ev {
            Ok(f) => out.push(Event::Frame(f.raw().to_vec(), f.has_crc())),
            Err(e) => out.push(Event::Protocol(e)),
        });
    }
    if d.held_bytes() > 0 {
        out.push(Event::UnexpectedEof(d.held_bytes()));
        d.reset();
    }
    out.push(Event::Eof);
    (out, d.stats())
}

fn event(r: Result<aeolus_proto::Frame<'_>, IoError<ErrorKind>>) -> Result<Event, ErrorKind> {
    Ok(match r {
        Ok(f) => Event::Frame(f.raw().to_vec(), f.has_crc()),
        Err(IoError::Protocol(e)) => Event::Protocol(e),
        Err(IoError::UnexpectedEof { pending }) => Event::UnexpectedEof(pending),
        Err(IoError::Eof) => Event::Eof,
        Err(IoError::Transport(k)) => return Err(k),
        Err(IoError::WriteZero) => panic!("a reader never reports WriteZero"),
    })
}

/// Runs the blocking reader to EOF; returns its events, its counters and the transport
/// errors it passed on.
fn blocking<const N: usize, const R: usize>(
    stream: &[u8],
    sizes: &[usize],
    errors: &[usize],
) -> (Vec<Event>, aeolus_proto::Stats, usize) {
    let mut r = bio::FrameReader::<_, N, R>::new(Wire::new(stream, sizes, errors), Decoder::new());
    let (mut out, mut transport) = (Vec::new(), 0);
    loop {
        match event(r.read()) {
            Ok(ev) => {
                let end = ev == Event::Eof;
                out.push(ev);
                if end {
                    break;
                }
            }
            Err(_) => transport += 1,
        }
    }
    assert_eq!(r.get_ref().errors_given, transport);
    (out, r.decoder().stats(), transport)
}

fn asynchronous<const N: usize, const R: usize>(
    stream: &[u8],
    sizes: &[usize],
    errors: &[usize],
) -> (Vec<Event>, aeolus_proto::Stats, usize) {
    let mut r = aio::FrameReader::<_, N, R>::new(Wire::new(stream, sizes, errors), Decoder::new());
    let (mut out, mut transport) = (Vec::new(), 0);
    loop {
        match event(block_on(r.read())) {
            Ok(ev) => {
                let end = ev == Event::Eof;
                out.push(ev);
                if end {
                    break;
                }
            }
            Err(_) => transport += 1,
        }
    }
    (out, r.decoder().stats(), transport)
}

fn check<const N: usize, const R: usize>(stream: &[u8], sizes: &[usize], errors: &[usize]) {
    let (want, want_stats) = reference::<N>(stream);
    let injected = errors.iter().filter(|&&e| e <= stream.len()).count();
    let (got, stats, transport) = blocking::<N, R>(stream, sizes, errors);
    assert_eq!(got, want, "blocking, sizes {sizes:?}, errors {errors:?}");
    assert_eq!(stats, want_stats);
    assert_eq!(transport, injected);
    let (got, stats, transport) = asynchronous::<N, R>(stream, sizes, errors);
    assert_eq!(got, want, "async, sizes {sizes:?}, errors {errors:?}");
    assert_eq!(stats, want_stats);
    assert_eq!(transport, injected);
}

fn encoded(msg: &Message<'_>, crc: CrcMode) -> Vec<u8> {
    let mut buf = vec![0u8; max_encoded_len(msg.buffer_len())];
    let n = msg.encode(&mut buf, crc).unwrap();
    buf.truncate(n);
    buf
}

/// A stream piece: a frame (with or without CRC), the same with one byte flipped, or noise.
fn arb_piece() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        4 => (arb_message(), any::<bool>()).prop_map(|(m, omit)| {
            encoded(&m, if omit { CrcMode::Omit } else { CrcMode::Compute })
        }),
        1 => (arb_message(), any::<prop::sample::Index>(), any::<u8>()).prop_map(|(m, i, x)| {
            let mut f = encoded(&m, CrcMode::Compute);
            let at = i.index(f.len());
            f[at] ^= x | 1;
            f
        }),
        1 => prop::collection::vec(prop_oneof![Just(0x7Eu8), Just(0x7D), Just(0x5E), any::<u8>()], 0..12),
    ]
}

fn arb_stream() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(arb_piece(), 0..8).prop_map(|p| p.concat())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn readers_deliver_what_push_delivers(
        stream in arb_stream(),
        sizes in prop::collection::vec(1usize..80, 1..6),
        errors in prop::collection::vec(0usize..400, 0..3),
        cut in 0usize..40,
    ) {
        // A stream cut short, too: EOF lands anywhere, in a frame or between frames.
        let cut = stream.len().saturating_sub(cut);
        for s in [&stream[..], &stream[..cut]] {
            check::<{ aeolus_proto::MAX_FIXED_FRAME }, 64>(s, &sizes, &errors);
            check::<{ aeolus_proto::MAX_FIXED_FRAME }, 7>(s, &sizes, &errors);
            check::<{ aeolus_proto::MAX_FIXED_FRAME }, 1>(s, &sizes, &errors);
            // A small decoder: overflows on the long messages.
            check::<24, 16>(s, &sizes, &errors);
        }
    }
}

/// Three frames, one with escapes and one without CRC, then half a frame.
fn fixed_stream() -> Vec<u8> {
    let mut s = vec![0x00, 0x13];
    s.extend(encoded(
        &Message::Toast(aeolus_proto::message::Text::new("AEOLUS on").unwrap()),
        CrcMode::Compute,
    ));
    s.extend(encoded(
        &Message::Unknown {
            id: 0x7E,
            data: &[0x7D, 0x7E, 1],
        },
        CrcMode::Compute,
    ));
    s.extend(encoded(&Message::Log(&[9; 20]), CrcMode::Omit));
    s.extend_from_slice(&[0x7E, 0x52, b'h']);
    s
}

#[test]
fn every_read_size_from_one_byte_to_the_whole_stream() {
    let s = fixed_stream();
    for size in 1..=s.len() + 1 {
        check::<64, 64>(&s, &[size], &[]);
        check::<64, 5>(&s, &[size], &[]);
    }
}

#[test]
fn transport_errors_in_mid_frame_lose_nothing() {
    let s = fixed_stream();
    for at in 0..=s.len() {
        check::<64, 8>(&s, &[3], &[at]);
        check::<64, 8>(&s, &[1, 5], &[at, at + 2]);
    }
}

#[test]
fn eof_mid_frame_is_reported_then_eof() {
    let s = fixed_stream();
    let (events, _, _) = blocking::<64, 16>(&s, &[16], &[]);
    let n = events.len();
    // The half frame: flag, ID, one data byte (the flag is counted apart).
    assert_eq!(events[n - 2], Event::UnexpectedEof(2));
    assert_eq!(events[n - 1], Event::Eof);
    assert_eq!(
        events
            .iter()
            .filter(|e| matches!(e, Event::Frame(..)))
            .count(),
        3
    );
    // A clean end: no UnexpectedEof.
    let (events, _, _) = blocking::<64, 16>(&s[..s.len() - 3], &[16], &[]);
    assert_eq!(events.last(), Some(&Event::Eof));
    assert!(!events.contains(&Event::UnexpectedEof(2)));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    #[test]
    fn writers_write_what_encode_frame_writes(msg in arb_message(), omit in any::<bool>(), max in 1usize..40) {
        let crc = if omit { CrcMode::Omit } else { CrcMode::Compute };
        let want = encoded(&msg, crc);
        let mut w = bio::FrameWriter::new(sink(max));
        prop_assert_eq!(w.write_message(&msg, crc), Ok(want.len()));
        prop_assert_eq!(&w.into_inner().out, &want);
        let mut w = aio::FrameWriter::new(sink(max));
        prop_assert_eq!(block_on(w.write_message(&msg, crc)), Ok(want.len()));
        prop_assert_eq!(&w.into_inner().out, &want);
        // write_frame with the raw data gives the same bytes.
        let mut data = vec![0u8; msg.buffer_len()];
        let n = msg.emit(&mut data).unwrap();
        let mut buf = vec![0u8; max_encoded_len(n)];
        let m = encode_frame(msg.id(), &data[..n], &[], crc, &mut buf).unwrap();
        let mut w = bio::FrameWriter::new(sink(max));
        prop_assert_eq!(w.write_frame(msg.id(), &data[..n], crc), Ok(m));
        prop_assert_eq!(&w.into_inner().out[..], &buf[..m]);
    }
}

#[test]
fn writer_errors_are_the_transports() {
    let msg = Message::Log(&[0x7E; 100]);
    let mut w = bio::FrameWriter::new(Sink {
        fail_at: Some(40),
        ..sink(8)
    });
    assert_eq!(
        w.write_message(&msg, CrcMode::Compute),
        Err(aeolus_proto::WriteError::Transport(ErrorKind::BrokenPipe))
    );
    let mut w = aio::FrameWriter::new(Sink {
        zero: true,
        ..sink(8)
    });
    assert_eq!(
        block_on(w.write_message(&msg, CrcMode::Compute)),
        Err(aeolus_proto::WriteError::WriteZero)
    );
    assert_eq!(block_on(w.flush()), Ok(()));
}
