//! The `embedded-io` and `embedded-io-async` readers deliver exactly what `Decoder::feed`
//! delivers byte by byte, then what `finish` delivers at the end of the stream, whatever
//! the read sizes (1 byte up to more than the buffer), with pending reads, transport errors in
//! mid-message and EOF; the writers produce exactly the bytes of `Encoder::encode`.

use crate::bulk::{Reach, piece};
use crate::streamgen;
use crate::transport;

use aydp_proto::{
    Decode, Decoder, Encoder, Error, IoError, Profile, Raw, Stats, Timestamp, embedded_io as bio,
    embedded_io_async as aio,
};
use embedded_io::ErrorKind;
use proptest::prelude::*;
use streamgen::Rng;
use transport::{Sink, Wire, block_on, sink};

#[derive(Debug, Clone, PartialEq, Eq)]
enum Event {
    Frame(Vec<u8>),
    Protocol(Error),
    /// `Err(Truncated)` from `finish`; the reader's `UnexpectedEof` (its count is checked apart).
    Truncated,
    Eof,
}

/// The reference: every byte fed on its own, then `finish`.
fn reference<const N: usize>(profile: Profile, stream: &[u8]) -> (Vec<Event>, Stats) {
    let mut d = Decoder::<N>::new(profile);
    let mut out = Vec::new();
    let conv = |e: Result<aydp_proto::Frame<'_>, Error>| match e {
        Ok(f) => Event::Frame(f.as_bytes().to_vec()),
        Err(Error::Truncated) => Event::Truncated,
        Err(e) => Event::Protocol(e),
    };
    for b in stream {
        d.feed(core::slice::from_ref(b), |e| out.push(conv(e)));
    }
    d.finish(|e| out.push(conv(e)));
    out.push(Event::Eof);
    (out, d.stats())
}

fn event(
    r: Result<aydp_proto::Frame<'_>, IoError<ErrorKind>>,
    cap: usize,
) -> Result<Event, ErrorKind> {
    Ok(match r {
        Ok(f) => Event::Frame(f.as_bytes().to_vec()),
        Err(IoError::Protocol(e)) => Event::Protocol(e),
        Err(IoError::UnexpectedEof { pending }) => {
            // At most the capacity, or a header (6 bytes) in a decoder too small for one.
            assert!((1..=cap.max(6)).contains(&pending), "pending {pending}");
            Event::Truncated
        }
        Err(IoError::Eof) => Event::Eof,
        Err(IoError::Transport(k)) => return Err(k),
        Err(IoError::WriteZero) => panic!("a reader never reports WriteZero"),
    })
}

fn blocking<const N: usize, const R: usize>(
    profile: Profile,
    stream: &[u8],
    sizes: &[usize],
    errors: &[usize],
) -> (Vec<Event>, Stats, usize) {
    let mut r = bio::FrameReader::<_, N, R>::new(
        Wire::new(stream, sizes, errors),
        aydp_proto::Decoder::new(profile),
    );
    let (mut out, mut transport) = (Vec::new(), 0);
    loop {
        match event(r.read(), N) {
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

fn asynchronous<const N: usize, const R: usize>(
    profile: Profile,
    stream: &[u8],
    sizes: &[usize],
    errors: &[usize],
) -> (Vec<Event>, Stats, usize) {
    let mut r = aio::FrameReader::<_, N, R>::new(
        Wire::new(stream, sizes, errors),
        aydp_proto::Decoder::new(profile),
    );
    let (mut out, mut transport) = (Vec::new(), 0);
    loop {
        match event(block_on(r.read()), N) {
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

fn check<const N: usize, const R: usize>(
    profile: Profile,
    stream: &[u8],
    sizes: &[usize],
    errors: &[usize],
) {
    let (want, want_stats) = reference::<N>(profile, stream);
    let injected = errors.iter().filter(|&&e| e <= stream.len()).count();
    let (got, stats, transport) = blocking::<N, R>(profile, stream, sizes, errors);
    assert_eq!(
        got, want,
        "blocking N={N} R={R}, sizes {sizes:?}, errors {errors:?}"
    );
    assert_eq!(stats, want_stats);
    assert_eq!(transport, injected);
    let (got, stats, transport) = asynchronous::<N, R>(profile, stream, sizes, errors);
    assert_eq!(
        got, want,
        "async N={N} R={R}, sizes {sizes:?}, errors {errors:?}"
    );
    assert_eq!(stats, want_stats);
    assert_eq!(transport, injected);
}

fn check_all(profile: Profile, stream: &[u8], sizes: &[usize], errors: &[usize]) {
    check::<128, 64>(profile, stream, sizes, errors);
    check::<128, 7>(profile, stream, sizes, errors);
    check::<128, 1>(profile, stream, sizes, errors);
    check::<40, 200>(profile, stream, sizes, errors);
    check::<23, 16>(profile, stream, sizes, errors);
    // Smaller than a header: the byte-at-a-time rules.
    check::<3, 4>(profile, stream, sizes, errors);
}

fn framed_stream() -> impl Strategy<Value = (Profile, Vec<u8>)> {
    prop_oneof![Just(Profile::Spec), Just(Profile::Reference)].prop_flat_map(|p| {
        prop::collection::vec(piece(p, Reach::Long), 0..12)
            .prop_map(move |pieces| (p, pieces.concat()))
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn readers_deliver_what_push_and_flush_deliver(
        (profile, stream) in framed_stream(),
        sizes in prop::collection::vec(1usize..100, 1..6),
        errors in prop::collection::vec(0usize..600, 0..3),
    ) {
        check_all(profile, &stream, &sizes, &errors);
    }
}

/// Noise, three messages (one with a false start in front), half a message.
fn fixed_stream() -> Vec<u8> {
    let enc = Encoder::new(Profile::Spec);
    let mut s = vec![0x00, 0xFF, 0xFF];
    let mut buf = [0u8; 64];
    let n = enc
        .encode(
            &Raw {
                msg_type: 9,
                data: &[2],
            },
            None,
            &mut buf,
        )
        .unwrap();
    s.extend_from_slice(&buf[..n]);
    s.extend_from_slice(&[0xFF, 0x00, 0x28, 0, 0, 0]); // a false start asking for 40 bytes
    let n = enc
        .encode(
            &Raw {
                msg_type: 3,
                data: &[1; 20],
            },
            Some(Timestamp::new(7, 8)),
            &mut buf,
        )
        .unwrap();
    s.extend_from_slice(&buf[..n]);
    s.extend_from_slice(&[0xFF, 0x80, 0x07, 0, 0, 0, 0x78]);
    s.extend_from_slice(&[0xFF, 0x89, 0x08]);
    s
}

#[test]
fn every_read_size_from_one_byte_to_the_whole_stream() {
    let s = fixed_stream();
    for size in 1..=s.len() + 1 {
        check::<64, 64>(Profile::Spec, &s, &[size], &[]);
        check::<64, 5>(Profile::Spec, &s, &[size], &[]);
    }
}

#[test]
fn transport_errors_in_mid_message_lose_nothing() {
    let s = fixed_stream();
    for at in 0..=s.len() {
        check::<64, 8>(Profile::Spec, &s, &[3], &[at]);
        check::<64, 8>(Profile::Spec, &s, &[1, 5], &[at, at + 2]);
    }
}

#[test]
fn eof_mid_message_is_reported_with_its_length() {
    let s = fixed_stream();
    let mut r = bio::FrameReader::<_, 64, 16>::new(
        Wire::new(&s, &[16], &[]),
        aydp_proto::Decoder::new(Profile::Spec),
    );
    let mut frames = 0;
    let last = loop {
        match r.read() {
            Ok(_) => frames += 1,
            Err(IoError::Protocol(_)) => {}
            Err(e) => break e,
        }
    };
    assert_eq!(last, IoError::UnexpectedEof { pending: 3 });
    assert_eq!(r.read().err(), Some(IoError::Eof));
    // The false start fails when the normal message completes its 40 bytes? No: the false
    // start is 40 bytes long, so it swallows the position message and fails its checksum;
    // the rescan still finds both messages behind it.
    assert_eq!(frames, 3);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn writers_write_what_encode_writes(
        seed in any::<u64>(),
        expedited in any::<bool>(),
        reference in any::<bool>(),
        max in 1usize..40,
    ) {
        let profile = if reference { Profile::Reference } else { Profile::Spec };
        let mut rng = Rng(seed);
        let data: Vec<u8> = (0..rng.below(90)).map(|_| rng.byte()).collect();
        let payload = Raw { msg_type: (rng.below(127)) as u8, data: &data };
        let ts = (!expedited).then(|| Timestamp::new(i64::from(rng.next_u64() as u32), 5));
        let mut want = vec![0u8; 200];
        if reference && expedited {
            // The Reference profile has no expedited header: refused, and nothing written.
            let refused = Err(aydp_proto::WriteError::Protocol(aydp_proto::EncodeError::ExpeditedInReference));
            prop_assert_eq!(
                Encoder::new(profile).encode(&payload, ts, &mut want),
                Err(aydp_proto::EncodeError::ExpeditedInReference)
            );
            let mut w = bio::FrameWriter::new(sink(max), profile);
            prop_assert_eq!(w.write_message(&payload, ts), refused);
            prop_assert!(w.into_inner().out.is_empty());
            let mut w = aio::FrameWriter::new(sink(max), profile);
            prop_assert_eq!(block_on(w.write_message(&payload, ts)), refused);
            prop_assert!(w.into_inner().out.is_empty());
            return Ok(());
        }
        let n = Encoder::new(profile).encode(&payload, ts, &mut want).unwrap();
        want.truncate(n);
        let mut w = bio::FrameWriter::new(sink(max), profile);
        prop_assert_eq!(w.write_message(&payload, ts), Ok(n));
        prop_assert_eq!(&w.into_inner().out, &want);
        let mut w = aio::FrameWriter::new(sink(max), profile);
        prop_assert_eq!(block_on(w.write_message(&payload, ts)), Ok(n));
        prop_assert_eq!(&w.into_inner().out, &want);
    }
}

#[test]
fn writer_errors_are_kept_apart() {
    let long = [0u8; 100];
    let mut w = bio::FrameWriter::new(
        Sink {
            fail_at: Some(40),
            ..sink(8)
        },
        Profile::Spec,
    );
    assert_eq!(
        w.write_expedited(&Raw {
            msg_type: 3,
            data: &long
        }),
        Err(aydp_proto::WriteError::Transport(ErrorKind::BrokenPipe))
    );
    // A type byte beyond 126 is the protocol's error, and nothing is written.
    let mut w = aio::FrameWriter::new(sink(8), Profile::Spec);
    assert_eq!(
        block_on(w.write_expedited(&Raw {
            msg_type: 200,
            data: &[]
        })),
        Err(aydp_proto::WriteError::Protocol(
            aydp_proto::EncodeError::BadType(200)
        ))
    );
    assert!(w.get_mut().out.is_empty());
    let mut w = aio::FrameWriter::new(
        Sink {
            zero: true,
            ..sink(8)
        },
        Profile::Spec,
    );
    assert_eq!(
        block_on(w.write_expedited(&Raw {
            msg_type: 3,
            data: &long
        })),
        Err(aydp_proto::WriteError::WriteZero)
    );
}
