//! `TxQueue::push_with` (a frame encoded straight into the queue) against `push` of the same
//! frame encoded into a buffer: the same answer and the same bytes out, at every position of
//! the ring (wrap-around), for every reserve, up to full.

use sensor_box::port::TxQueue;

/// A port that takes at most `room` bytes per write and keeps them.
struct Sink {
    out: Vec<u8>,
    room: usize,
}

impl embedded_io::ErrorType for Sink {
    type Error = core::convert::Infallible;
}

impl embedded_io::WriteReady for Sink {
    fn write_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(self.room > 0)
    }
}

impl embedded_io::Write for Sink {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        let n = buf.len().min(self.room);
        self.out.extend_from_slice(&buf[..n]);
        self.room -= n;
        Ok(n)
    }

    fn flush(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// A frame of `len` bytes starting at `seed`, written by an "encoder" that fails when the
/// slice is too short (as `Message::encode` does).
fn frame(len: usize, seed: u8) -> impl Fn(&mut [u8]) -> Option<usize> {
    move |out: &mut [u8]| {
        let dst = out.get_mut(..len)?;
        for (i, b) in dst.iter_mut().enumerate() {
            *b = seed.wrapping_add(i as u8);
        }
        Some(len)
    }
}

#[test]
fn push_with_equals_encode_then_push_at_every_position() {
    const N: usize = 16;
    for start in 0..N {
        for fill in 0..=N {
            for len in 1..=N + 1 {
                for reserve in [0, 1, 5] {
                    let (mut a, mut b) = (TxQueue::<N>::new(), TxQueue::<N>::new());
                    // Hold `fill` bytes from position `start` (an empty ring starts at 0).
                    for q in [&mut a, &mut b] {
                        if fill > 0 {
                            assert!(q.push(&vec![0xAA; start + 1]));
                            let mut skip = Sink {
                                out: Vec::new(),
                                room: start,
                            };
                            q.drain(&mut skip).unwrap();
                            assert!(q.push(&vec![0x55; fill - 1]));
                        }
                    }
                    let mut buf = [0u8; 64];
                    let n = frame(len, 7)(&mut buf).unwrap();
                    let fits = b.free() >= n + reserve;
                    let pushed_b = fits && b.push(&buf[..n]);
                    let pushed_a = a.push_with::<64>(reserve, frame(len, 7));
                    assert_eq!(
                        pushed_a, pushed_b,
                        "start {start} fill {fill} len {len} reserve {reserve}"
                    );
                    assert_eq!(a.len(), b.len());
                    let (mut sa, mut sb) = (
                        Sink {
                            out: Vec::new(),
                            room: usize::MAX,
                        },
                        Sink {
                            out: Vec::new(),
                            room: usize::MAX,
                        },
                    );
                    a.drain(&mut sa).unwrap();
                    b.drain(&mut sb).unwrap();
                    assert_eq!(sa.out, sb.out);
                }
            }
        }
    }
}
