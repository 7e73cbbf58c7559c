//! `Registry::set`, the device's own writes: the range holds at both ends inclusive, then the
//! index and the element type are checked, and read-only does not apply (the device owns its
//! values). Nothing changes on an error.

use aydp_proto::registry::{Cell, Registry, RegistryError, Slot};

#[test]
fn set_checks_the_range_inclusive_then_bounds_then_type() {
    let mut direct = 0u8;
    let mut name = [0u8; 4];
    let mut gains = [0.0f32; 4];
    let mut rate = 0.0f64;
    let mut slots = [
        Slot::value(0x0000, Cell::u8(&mut direct)).with_range(0.0, 1.0),
        Slot::value(0x0001, Cell::Chars(&mut name)).read_only(),
        Slot::array(0x0010, Cell::F32(&mut gains)).with_range(-100.0, 100.0),
        Slot::value(0x0020, Cell::f64(&mut rate)),
    ];
    let mut reg = Registry::new(&mut slots);
    let results = [
        reg.set(0x0000, 0, 1u8),
        reg.set(0x0000, 0, 2u8),
        reg.set(0x0010, 0, -100.0f32),
        reg.set(0x0010, 3, 100.0f32),
        reg.set(0x0010, 1, 100.5f32),
        reg.set(0x0010, 2, -100.5f32),
        reg.set(0x0010, 4, 1.0f32),
        reg.set(0x0010, 1, 1u8),
        reg.set(0x0001, 2, b'x'),
        reg.set(0x0020, 0, 1e300f64),
        reg.set(0x0099, 0, 1u8),
    ];
    use RegistryError::{OutOfBounds, OutOfRange, UnknownAddress, WrongSize};
    let want = [
        Ok(()),
        Err(OutOfRange(0x0000)),
        Ok(()),
        Ok(()),
        Err(OutOfRange(0x0010)),
        Err(OutOfRange(0x0010)),
        Err(OutOfBounds(0x0010)),
        Err(WrongSize(0x0010)),
        Ok(()),
        Ok(()),
        Err(UnknownAddress(0x0099)),
    ];
    assert_eq!(results, want);
    assert_eq!(reg.get::<u8>(0x0000, 0), Some(1));
    assert_eq!(gains, [-100.0, 0.0, 0.0, 100.0]);
    assert_eq!((direct, name, rate), (1, [0, 0, b'x', 0], 1e300));
}

#[test]
fn apply_takes_a_text_up_to_its_full_length_and_a_whole_array_only() {
    use aydp_proto::{SystemValueUpdate, UpdateMode};
    let mut name = [0u8; 4];
    let mut gains = [0.0f32; 2];
    let mut slots = [
        Slot::value(0x0001, Cell::Chars(&mut name)),
        Slot::array(0x0010, Cell::F32(&mut gains)),
    ];
    let mut reg = Registry::new(&mut slots);
    let text = |data| SystemValueUpdate {
        address: 0x0001,
        mode: UpdateMode::Single,
        data,
    };
    // A text as long as its cell fits; one byte more does not.
    assert_eq!(reg.apply(&text(b"abcd")), Ok(()));
    assert_eq!(
        reg.apply(&text(b"abcde")),
        Err(RegistryError::WrongSize(0x0001))
    );
    let whole = [1.0f32.to_le_bytes(), 2.0f32.to_le_bytes()].concat();
    let array = |count, data| SystemValueUpdate {
        address: 0x0010,
        mode: UpdateMode::Array { count },
        data,
    };
    // The whole array, and only with its own count, even when the bytes are the right size.
    assert_eq!(
        reg.apply(&array(1, &whole)),
        Err(RegistryError::OutOfBounds(0x0010))
    );
    assert_eq!(
        reg.apply(&array(3, &whole)),
        Err(RegistryError::OutOfBounds(0x0010))
    );
    assert_eq!(reg.apply(&array(2, &whole)), Ok(()));
    assert_eq!(name, *b"abcd");
    assert_eq!(gains, [1.0, 2.0]);
}

#[test]
fn a_cell_is_empty_only_without_elements() {
    let mut none: [f32; 0] = [];
    let mut one = [0u8; 1];
    assert!(Cell::F32(&mut none).is_empty());
    assert!(!Cell::Chars(&mut one).is_empty());
}
