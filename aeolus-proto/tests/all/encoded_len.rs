//! `max_encoded_len` is the exact worst case: two flags plus the ID, the data and the CRC,
//! every one of them escaped; a frame that escapes all of them fills it to the byte.

use aeolus_proto::{CrcMode, EncodeError, encode_frame, max_encoded_len};
use proptest::prelude::Just;

#[test]
fn max_encoded_len_is_two_flags_and_everything_else_doubled() {
    assert_eq!(max_encoded_len(0), 8);
    assert_eq!(max_encoded_len(1), 10);
    assert_eq!(max_encoded_len(32), 72);
    assert_eq!(max_encoded_len(208), 424);
}

/// ID 0x7D and one data byte 0x7D: the CRC (section 4.3) of `7D 7D` is 0x7D7D, so every
/// byte between the flags is escaped.
#[test]
fn a_frame_that_escapes_every_byte_fills_max_encoded_len_exactly() {
    // Sized at run time (a `Vec`), so a wrong length fails this test rather than its build.
    let mut out = vec![0u8; max_encoded_len(1)];
    let n = encode_frame(0x7D, &[0x7D], &[], CrcMode::Compute, &mut out).unwrap();
    assert_eq!(n, max_encoded_len(1));
    assert_eq!(
        out,
        [0x7E, 0x7D, 0x5D, 0x7D, 0x5D, 0x7D, 0x5D, 0x7D, 0x5D, 0x7E]
    );
    let mut short = vec![0u8; max_encoded_len(1) - 1];
    assert_eq!(
        encode_frame(0x7D, &[0x7D], &[], CrcMode::Compute, &mut short),
        Err(EncodeError::BufferTooSmall {
            needed: max_encoded_len(1),
        })
    );
}

proptest::proptest! {
    /// A buffer short of a frame is refused with `needed` = the worst case of its data, which
    /// then always takes it, whatever the ID, the data (split anywhere into head and tail,
    /// escapes included) and the CRC mode.
    #[test]
    fn buffer_too_small_names_a_length_that_holds_the_frame(
        id in proptest::prelude::any::<u8>(),
        data in proptest::collection::vec(
            proptest::prop_oneof![Just(0x7D_u8), Just(0x7E_u8), proptest::prelude::any::<u8>()],
            0..40,
        ),
        cut in 0usize..40,
        omit in proptest::prelude::any::<bool>(),
        short_by in 1usize..4,
    ) {
        let (head, tail) = data.split_at(cut.min(data.len()));
        let mode = if omit { CrcMode::Omit } else { CrcMode::Compute };
        let worst = max_encoded_len(data.len());
        let mut big = vec![0u8; worst];
        let len = encode_frame(id, head, tail, mode, &mut big).unwrap();
        let mut short = vec![0u8; len.saturating_sub(short_by)];
        proptest::prop_assert_eq!(
            encode_frame(id, head, tail, mode, &mut short),
            Err(EncodeError::BufferTooSmall { needed: worst })
        );
        let mut exact = vec![0u8; len];
        proptest::prop_assert_eq!(encode_frame(id, head, tail, mode, &mut exact), Ok(len));
        proptest::prop_assert_eq!(&exact[..], &big[..len]);
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 2000, ..Default::default() })]
    /// `encode_frame` copies a word at a time while no byte of it needs escaping and a byte
    /// at a time around one that does; whatever the data (escapes dense, sparse or at any
    /// offset of a word), wherever it is split into head and tail and however much room the
    /// output has beyond the frame, it writes exactly what the byte iterator yields.
    #[test]
    fn encode_frame_writes_what_the_byte_iterator_yields(
        id in proptest::prelude::any::<u8>(),
        data in proptest::collection::vec(
            proptest::prop_oneof![
                8 => proptest::prelude::any::<u8>(),
                1 => Just(0x7D_u8),
                1 => Just(0x7E_u8),
            ],
            0..90,
        ),
        cut in 0usize..90,
        omit in proptest::prelude::any::<bool>(),
        spare in 0usize..9,
    ) {
        let (head, tail) = data.split_at(cut.min(data.len()));
        let mode = if omit { CrcMode::Omit } else { CrcMode::Compute };
        let want: Vec<u8> = aeolus_proto::FrameBytes::new(id, &data, mode).collect();
        let mut out = vec![0u8; want.len() + spare];
        let n = encode_frame(id, head, tail, mode, &mut out);
        proptest::prop_assert_eq!(n, Ok(want.len()));
        proptest::prop_assert_eq!(&out[..want.len()], &want[..]);
    }
}
