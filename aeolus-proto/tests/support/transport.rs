//! In-memory `embedded-io` / `embedded-io-async` transports for the reader and writer tests:
//! reads of chosen sizes, a pending poll before every other async read, transport errors at
//! chosen offsets; a sink that takes a few bytes per write, fails once, or accepts nothing; a sink that counts its flushes.
//! One copy for the three protocol crates: `aydp-proto` and `aok-proto` include this file by path.
#![allow(dead_code)]

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};

use embedded_io::ErrorKind;

/// An in-memory transport: reads of the sizes in `sizes` (cycled), a `Pending` before every
/// other async read, and an error (once) before the read that would start at each offset in
/// `errors`.
pub struct Wire {
    data: Vec<u8>,
    pos: usize,
    sizes: Vec<usize>,
    call: usize,
    errors: Vec<usize>,
    pub errors_given: usize,
    pending: bool,
}

impl Wire {
    pub fn new(data: &[u8], sizes: &[usize], errors: &[usize]) -> Self {
        Wire {
            data: data.to_vec(),
            pos: 0,
            sizes: sizes.to_vec(),
            call: 0,
            errors: errors.to_vec(),
            errors_given: 0,
            pending: false,
        }
    }

    fn read_now(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        if let Some(i) = self.errors.iter().position(|&at| at <= self.pos) {
            self.errors.remove(i);
            self.errors_given += 1;
            return Err(ErrorKind::Other);
        }
        let size = self.sizes[self.call % self.sizes.len()].max(1);
        self.call += 1;
        let n = size.min(buf.len()).min(self.data.len() - self.pos);
        buf[..n].copy_from_slice(&self.data[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}

impl embedded_io::ErrorType for Wire {
    type Error = ErrorKind;
}

impl embedded_io::Read for Wire {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        self.read_now(buf)
    }
}

impl embedded_io_async::Read for Wire {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        // Not ready on every other call, as a UART waiting for its next byte.
        self.pending = !self.pending;
        if self.pending {
            YieldOnce(false).await;
        }
        self.read_now(buf)
    }
}

/// A future that is pending once.
pub struct YieldOnce(pub bool);
impl Future for YieldOnce {
    type Output = ();
    fn poll(mut self: std::pin::Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<()> {
        if self.0 {
            Poll::Ready(())
        } else {
            self.0 = true;
            cx.waker().wake_by_ref();
            Poll::Pending
        }
    }
}

pub fn block_on<F: Future>(f: F) -> F::Output {
    let mut f = pin!(f);
    let mut cx = Context::from_waker(Waker::noop());
    // Far more polls than any test's future needs: a future that never completes (a loop of
    // the code under test that makes no progress) fails the test instead of hanging it.
    const MAX_POLLS: u32 = 1_000_000;
    for _ in 0..MAX_POLLS {
        if let Poll::Ready(v) = f.as_mut().poll(&mut cx) {
            return v;
        }
    }
    panic!("the future did not complete in {MAX_POLLS} polls: a loop makes no progress")
}

/// A transport that takes at most `max` bytes per write, and fails once at `fail_at`.
pub struct Sink {
    pub out: Vec<u8>,
    pub max: usize,
    pub fail_at: Option<usize>,
    pub zero: bool,
}

impl embedded_io::ErrorType for Sink {
    type Error = ErrorKind;
}

impl Sink {
    fn write_now(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        if self.fail_at.is_some_and(|at| self.out.len() >= at) {
            self.fail_at = None;
            return Err(ErrorKind::BrokenPipe);
        }
        if self.zero {
            return Ok(0);
        }
        let n = buf.len().min(self.max);
        self.out.extend_from_slice(&buf[..n]);
        Ok(n)
    }
}

impl embedded_io::Write for Sink {
    fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        self.write_now(buf)
    }
    fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

impl embedded_io_async::Write for Sink {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        YieldOnce(false).await;
        self.write_now(buf)
    }
    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

pub fn sink(max: usize) -> Sink {
    Sink {
        out: Vec::new(),
        max,
        fail_at: None,
        zero: false,
    }
}

/// A sink that counts flushes and fails every flush after the first `ok`.
pub struct Flushes {
    pub count: usize,
    pub ok: usize,
}

impl embedded_io::ErrorType for Flushes {
    type Error = ErrorKind;
}

impl Flushes {
    fn flush_now(&mut self) -> Result<(), ErrorKind> {
        self.count += 1;
        if self.count > self.ok {
            Err(ErrorKind::TimedOut)
        } else {
            Ok(())
        }
    }
}

impl embedded_io::Write for Flushes {
    fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), ErrorKind> {
        self.flush_now()
    }
}

impl embedded_io_async::Write for Flushes {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        Ok(buf.len())
    }
    async fn flush(&mut self) -> Result<(), ErrorKind> {
        self.flush_now()
    }
}
