//! An open endpoint seen through `embedded_hal_nb::serial::{Read, Write}`, so the `aok-proto`
//! client (written for firmware and host alike) can drive it.

use std::collections::VecDeque;
use std::time::Duration;

use embedded_hal_nb::serial::{ErrorKind, ErrorType, Read, Write};

use crate::endpoint::{Input, Link};
use crate::error::Error;

/// How long one `read` waits for bytes before answering `WouldBlock`. It paces the client's
/// polling loop, so the loop does not spin.
pub(crate) const READ_SLICE: Duration = Duration::from_millis(1);

/// A [`Link`] with non-blocking byte reads and buffered writes (sent on `flush`).
#[derive(Debug)]
pub(crate) struct NbSerial {
    link: Link,
    rx: VecDeque<u8>,
    tx: Vec<u8>,
    buf: Vec<u8>,
    ended: bool,
    error: Option<Error>,
    /// How many bytes have been received.
    pub(crate) received: u64,
}

impl NbSerial {
    /// Wraps an open link.
    pub(crate) fn new(link: Link) -> Self {
        NbSerial {
            link,
            rx: VecDeque::new(),
            tx: Vec::new(),
            buf: vec![0u8; 4096],
            ended: false,
            error: None,
            received: 0,
        }
    }

    /// Whether the other end closed the stream.
    pub(crate) fn ended(&self) -> bool {
        self.ended
    }

    /// The first I/O error met, taken out.
    pub(crate) fn take_error(&mut self) -> Option<Error> {
        self.error.take()
    }

    /// The endpoint's name.
    pub(crate) fn name(&self) -> &str {
        self.link.name()
    }
}

impl ErrorType for NbSerial {
    type Error = ErrorKind;
}

impl Read<u8> for NbSerial {
    fn read(&mut self) -> nb::Result<u8, ErrorKind> {
        if self.rx.is_empty() && !self.ended {
            match self.link.read(&mut self.buf, READ_SLICE) {
                Ok(Input::Data(n)) => {
                    self.received += n as u64;
                    self.rx.extend(&self.buf[..n]);
                }
                Ok(Input::Idle) => {}
                Ok(Input::End) => self.ended = true,
                Err(e) => {
                    self.error.get_or_insert(e);
                    return Err(nb::Error::Other(ErrorKind::Other));
                }
            }
        }
        self.rx.pop_front().ok_or(nb::Error::WouldBlock)
    }
}

impl Write<u8> for NbSerial {
    fn write(&mut self, word: u8) -> nb::Result<(), ErrorKind> {
        self.tx.push(word);
        Ok(())
    }

    fn flush(&mut self) -> nb::Result<(), ErrorKind> {
        if self.tx.is_empty() {
            return Ok(());
        }
        let result = self.link.write_all(&self.tx);
        self.tx.clear();
        result.map_err(|e| {
            self.error.get_or_insert(e);
            nb::Error::Other(ErrorKind::Other)
        })
    }
}
