//! The writers' `flush` reaches the transport, once per call, and hands its error back as
//! `WriteError::Transport`, blocking and async.

use crate::transport;

use aeolus_proto::{WriteError, embedded_io as bio, embedded_io_async as aio};
use embedded_io::ErrorKind;
use transport::{Flushes, block_on};

#[test]
fn a_blocking_flush_reaches_the_transport_and_returns_its_error() {
    let mut w = bio::FrameWriter::new(Flushes { count: 0, ok: 1 });
    assert_eq!(w.flush(), Ok(()));
    assert_eq!(w.flush(), Err(WriteError::Transport(ErrorKind::TimedOut)));
    assert_eq!(w.into_inner().count, 2);
}

#[test]
fn an_async_flush_reaches_the_transport_and_returns_its_error() {
    let mut w = aio::FrameWriter::new(Flushes { count: 0, ok: 1 });
    assert_eq!(block_on(w.flush()), Ok(()));
    assert_eq!(
        block_on(w.flush()),
        Err(WriteError::Transport(ErrorKind::TimedOut))
    );
    assert_eq!(w.into_inner().count, 2);
}
