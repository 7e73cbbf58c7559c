//! A direct-output message counts its entries: `len` is the count field, and the entries are
//! the 6-byte records after it (device, channel, f32 value).

use aydp_proto::DirectOutput;

#[test]
fn len_is_the_count_and_entries_follow_it() {
    let data = [2, 0, 1, 2, 0, 0, 0x20, 0x41, 3, 4, 0, 0, 0x80, 0x3F];
    let d = DirectOutput::parse(&data).unwrap();
    assert_eq!((d.len(), d.is_empty()), (2, false));
    assert_eq!(d.entries().size_hint(), (2, Some(2)));
    let entries: Vec<(u8, u8, f32)> = d
        .entries()
        .map(|e| (e.device, e.channel, e.value))
        .collect();
    assert_eq!(entries, [(1, 2, 10.0), (3, 4, 1.0)]);
    assert_eq!(d.as_bytes(), &data);
}

#[test]
fn the_builder_writes_the_same_bytes_that_parse_reads() {
    use aydp_proto::{DirectOutputBuilder, OutputEntry};
    let a = OutputEntry {
        device: 1,
        channel: 2,
        value: 10.0,
    };
    let b = OutputEntry {
        device: 3,
        channel: 4,
        value: 1.0,
    };
    let mut one = [0u8; 6];
    assert_eq!(a.emit(&mut one), Ok(6));
    assert_eq!(one, [1, 2, 0, 0, 0x20, 0x41]);
    let mut buf = [0u8; 2 + 2 * 6 + 5];
    let mut builder = DirectOutputBuilder::new(&mut buf);
    assert_eq!(builder.push(a), Ok(()));
    assert_eq!(builder.push(b), Ok(()));
    // A third entry needs 6 more bytes; 5 are left.
    assert_eq!(
        builder.push(a),
        Err(aydp_proto::EncodeError::BufferTooSmall { needed: 2 + 3 * 6 })
    );
    let out = builder.finish();
    assert_eq!(
        out.as_bytes(),
        [2, 0, 1, 2, 0, 0, 0x20, 0x41, 3, 4, 0, 0, 0x80, 0x3F]
    );
    assert_eq!(out.entries().collect::<Vec<_>>(), [a, b]);
}
