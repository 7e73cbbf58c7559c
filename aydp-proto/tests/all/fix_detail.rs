//! A fix detail (a count, then 7 bytes per satellite) built with `FixDetailBuilder`, read back
//! through `FixDetail`: the count, the satellites in order, the iterator's exact size, the
//! bounded list, and the builder's two limits.

use aydp_proto::{Error, FixDetail, FixDetailBuilder, Satellite};

/// Three satellites whose fields are exact in uflt16 (small integers).
fn sats() -> [Satellite; 3] {
    [
        (3, 10.0, 20.0, 30.0),
        (9, 90.0, 45.0, 41.0),
        (27, 270.0, 5.0, 12.0),
    ]
    .map(|(id, azimuth, elevation, snr)| Satellite {
        id,
        azimuth,
        elevation,
        snr,
    })
}

fn built(buf: &mut [u8]) -> FixDetail<'_> {
    let mut b = FixDetailBuilder::new(buf);
    for s in sats() {
        b.push(s).unwrap();
    }
    b.finish()
}

#[test]
fn the_builder_writes_the_count_then_seven_bytes_a_satellite() {
    let mut buf = [0u8; 64];
    let fix = built(&mut buf);
    assert_eq!(fix.len(), 3);
    assert!(!fix.is_empty());
    let bytes = fix.as_bytes();
    assert_eq!(bytes.len(), 1 + 3 * 7);
    assert_eq!(bytes[0], 3);
    for (i, s) in sats().iter().enumerate() {
        let mut one = [0u8; 7];
        s.emit(&mut one).unwrap();
        assert_eq!(&bytes[1 + 7 * i..8 + 7 * i], &one, "satellite {i}");
    }
}

#[test]
fn the_satellites_come_back_in_order_with_an_exact_size() {
    let mut buf = [0u8; 64];
    let fix = built(&mut buf);
    let mut it = fix.satellites();
    assert_eq!(it.size_hint(), (3, Some(3)));
    assert_eq!(it.next(), Some(sats()[0]));
    assert_eq!(it.size_hint(), (2, Some(2)));
    assert_eq!(it.collect::<Vec<_>>(), sats()[1..]);
    let list = fix.to_list::<4>().unwrap();
    assert_eq!(list.as_slice(), sats());
    assert_eq!(fix.to_list::<2>(), Err(Error::TooManySatellites(3)));
}

#[test]
fn an_empty_detail_has_no_satellites() {
    let mut buf = [0u8; 1];
    let fix = FixDetailBuilder::new(&mut buf).finish();
    assert_eq!(fix.len(), 0);
    assert!(fix.is_empty());
    assert_eq!(fix.as_bytes(), [0]);
    assert_eq!(fix.satellites().next(), None);
}

#[test]
fn the_builder_refuses_a_satellite_past_its_buffer() {
    let mut buf = [0u8; 1 + 7 + 6];
    let mut b = FixDetailBuilder::new(&mut buf);
    assert_eq!(b.push(sats()[0]), Ok(()));
    assert_eq!(
        b.push(sats()[1]),
        Err(aydp_proto::EncodeError::BufferTooSmall { needed: 1 + 2 * 7 })
    );
    let fix = b.finish();
    assert_eq!(fix.len(), 1);
    assert_eq!(fix.satellites().collect::<Vec<_>>(), [sats()[0]]);
}

#[test]
fn the_builder_holds_at_most_255_satellites() {
    let mut buf = vec![0u8; 1 + 256 * 7];
    let mut b = FixDetailBuilder::new(&mut buf);
    for i in 0..255 {
        assert_eq!(b.push(sats()[i % 3]), Ok(()), "satellite {i}");
    }
    assert_eq!(b.push(sats()[0]), Err(aydp_proto::EncodeError::TooLong));
    let fix = b.finish();
    assert_eq!(fix.len(), 255);
    assert_eq!(fix.satellites().count(), 255);
}
