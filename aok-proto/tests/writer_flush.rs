#![cfg(all(feature = "embedded-io", feature = "embedded-io-async"))]
//! The writers' `flush` reaches the transport, once per call, and hands its error back as
//! `IoError::Transport`, blocking and async.

#[path = "../../aeolus-proto/tests/support/transport.rs"]
mod transport;

use aok_proto::{IoError, embedded_io as bio, embedded_io_async as aio};
use embedded_io::ErrorKind;
use transport::block_on;

/// A transport that counts flushes and fails the flushes after the first `ok`.
struct Flushes {
    count: usize,
    ok: usize,
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

#[test]
fn a_blocking_flush_reaches_the_transport_and_returns_its_error() {
    let mut w = bio::Writer::new(Flushes { count: 0, ok: 1 });
    assert_eq!(w.flush(), Ok(()));
    assert_eq!(w.flush(), Err(IoError::Transport(ErrorKind::TimedOut)));
    assert_eq!(w.into_inner().count, 2);
}

#[test]
fn an_async_flush_reaches_the_transport_and_returns_its_error() {
    let mut w = aio::Writer::new(Flushes { count: 0, ok: 1 });
    assert_eq!(block_on(w.flush()), Ok(()));
    assert_eq!(
        block_on(w.flush()),
        Err(IoError::Transport(ErrorKind::TimedOut))
    );
    assert_eq!(w.into_inner().count, 2);
}
