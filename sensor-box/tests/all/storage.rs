//! The NOR flash stores: NOR semantics, bounds and alignment, windows.

use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};
use sensor_box::storage::{Error, FlashWindow, MemFlash};

#[test]
fn erase_sets_ff_and_write_only_clears_bits() {
    let mut mem = [0u8; 2048];
    let mut f = MemFlash::new(&mut mem);
    assert_eq!(f.capacity(), 2048);
    f.erase(1024, 2048).unwrap();
    let mut buf = [0u8; 8];
    f.read(1024, &mut buf).unwrap();
    assert_eq!(buf, [0xFF; 8]);
    f.write(1024, &[0xF0, 0x0F, 0xAA, 0x55]).unwrap();
    // A second write ANDs: bits can only go from 1 to 0.
    f.write(1024, &[0xFF, 0xFF, 0x0F, 0xFF]).unwrap();
    f.read(1024, &mut buf[..4]).unwrap();
    assert_eq!(&buf[..4], &[0xF0, 0x0F, 0x0A, 0x55]);
    // The first page was not erased.
    f.read(0, &mut buf).unwrap();
    assert_eq!(buf, [0; 8]);
}

#[test]
fn bounds_and_alignment_are_checked() {
    let mut mem = [0u8; 2048];
    let mut f = MemFlash::new(&mut mem);
    let mut buf = [0u8; 4];
    assert_eq!(f.read(2046, &mut buf), Err(Error::OutOfBounds));
    assert_eq!(f.read(u32::MAX, &mut buf), Err(Error::OutOfBounds));
    assert_eq!(f.write(2, &[0; 4]), Err(Error::NotAligned));
    assert_eq!(f.write(0, &[0; 3]), Err(Error::NotAligned));
    assert_eq!(f.write(2048, &[0; 4]), Err(Error::OutOfBounds));
    assert_eq!(f.erase(0, 100), Err(Error::NotAligned));
    assert_eq!(f.erase(1024, 0), Err(Error::OutOfBounds));
    assert_eq!(f.erase(0, 3072), Err(Error::OutOfBounds));
    f.read(2044, &mut buf).unwrap();
}

#[test]
fn capacity_is_whole_pages() {
    let mut mem = [0u8; 1023];
    let mut f = MemFlash::new(&mut mem);
    assert_eq!(f.capacity(), 0);
    assert_eq!(f.read(0, &mut [0u8; 1]), Err(Error::OutOfBounds));
}

#[test]
fn window_translates_and_confines() {
    let mut mem = [0x11u8; 4096];
    {
        let mut w = FlashWindow::new(MemFlash::new(&mut mem), 1024, 2048).unwrap();
        assert_eq!(w.capacity(), 2048);
        w.erase(0, 1024).unwrap();
        w.write(4, &[1, 2, 3, 4]).unwrap();
        let mut buf = [0u8; 8];
        w.read(0, &mut buf).unwrap();
        assert_eq!(buf, [0xFF, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4]);
        assert_eq!(w.read(2045, &mut [0u8; 4]), Err(Error::OutOfBounds));
        assert_eq!(w.erase(1024, 3072), Err(Error::OutOfBounds));
        assert_eq!(w.write(2, &[0; 4]), Err(Error::NotAligned));
    }
    assert_eq!(mem[1023], 0x11, "before the window");
    assert_eq!(&mem[1024..1032], &[0xFF, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4]);
    assert_eq!(mem[2048], 0x11, "erase stayed inside the window");
    assert!(FlashWindow::new(MemFlash::new(&mut mem), 100, 1024).is_err());
    assert!(FlashWindow::new(MemFlash::new(&mut mem), 3072, 2048).is_err());
}

#[test]
fn errors_display_and_map() {
    for e in [Error::OutOfBounds, Error::NotAligned, Error::Device] {
        assert!(!e.to_string().is_empty());
        assert_eq!(Error::from_flash(&e), e);
    }
}
