//! The readers and writers keep the parts they were built with: the profile and capacity of
//! the decoder, a decoder handed over with its counters, the encoder's profile, the transport.

use aydp_proto::{Decode, Decoder, Profile, embedded_io as bio, embedded_io_async as aio};

/// A frame of type 0x09 (flag 0x80) with one data byte, 0x02.
const FRAME: [u8; 8] = [0xFF, 0x89, 0x08, 0, 0, 0, 0x02, 0x7C];

#[test]
fn a_reader_decodes_with_the_profile_and_decoder_it_was_given() {
    let r =
        bio::FrameReader::<_, 32>::new(&FRAME[..], aydp_proto::Decoder::new(Profile::Reference));
    assert_eq!(
        (r.decoder().profile(), r.decoder().capacity()),
        (Profile::Reference, 32)
    );
    let r =
        aio::FrameReader::<_, 24>::new(&FRAME[..], aydp_proto::Decoder::new(Profile::Reference));
    assert_eq!(
        (r.decoder().profile(), r.decoder().capacity()),
        (Profile::Reference, 24)
    );

    let used = || {
        let mut d = Decoder::<32>::new(Profile::Spec);
        d.feed(&FRAME, |_| {});
        d
    };
    let mut r = bio::FrameReader::<_, 32>::new(&FRAME[..], used());
    assert_eq!(r.decoder().stats().frames_ok, 1);
    assert_eq!(r.read().map(|f| f.data().to_vec()), Ok(vec![0x02]));
    assert_eq!(r.decoder().stats().frames_ok, 2);
    assert_eq!(r.get_ref().len(), 0);
    let mut r = aio::FrameReader::<_, 32>::new(&FRAME[..], used());
    assert_eq!(r.decoder().stats().frames_ok, 1);
    assert_eq!(r.get_mut().len(), 8);
}

#[test]
fn a_writer_encodes_with_its_profile() {
    let mut buf = [0u8; 8];
    let w = bio::FrameWriter::new(&mut buf[..], Profile::Reference);
    assert_eq!(w.encoder().profile(), Profile::Reference);
    let mut buf = [0u8; 8];
    let mut w = aio::FrameWriter::new(&mut buf[..], Profile::Reference);
    assert_eq!(w.encoder().profile(), Profile::Reference);
    assert_eq!(w.get_mut().len(), 8);
}
