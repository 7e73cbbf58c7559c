//! What the blocking and async readers and writers share: the reader's buffer, its decode step
//! and end-of-stream state, and the writers' chunking. The two feature modules only add the
//! `read`/`write` calls (blocking or `.await`) around these, in loops of a few lines.

use crate::{Decode, Event, IoError};

/// What the reader found, without borrowing it.
pub(crate) enum Token<F, P> {
    /// An event, found in the read buffer's bytes from `from` on.
    Event { from: usize, event: Event<F, P> },
    /// The end of the stream, nothing held.
    Eof,
}

/// The reader's state: the decoder, the read buffer and the unread part of it.
#[derive(Debug, Clone)]
pub(crate) struct ReaderCore<D, const R: usize> {
    pub(crate) decoder: D,
    buf: [u8; R],
    start: usize,
    end: usize,
    /// A read returned 0 bytes: hand out what [`Decode::end`] gives, then [`Token::Eof`].
    ending: bool,
}

type TokenOf<D> = Token<<D as Decode>::Found, <D as Decode>::Error>;

impl<D: Decode, const R: usize> ReaderCore<D, R> {
    pub(crate) const fn new(decoder: D) -> Self {
        const { assert!(R > 0, "the read buffer needs at least one byte") };
        Self {
            decoder,
            buf: [0; R],
            start: 0,
            end: 0,
            ending: false,
        }
    }

    /// Decodes the unread bytes (and events a rescan left queued) up to the first event; at
    /// the end of the stream, the next event of [`Decode::end`].
    #[inline]
    pub(crate) fn decode(&mut self) -> Option<TokenOf<D>> {
        if self.ending {
            return Some(self.end_step());
        }
        let from = self.start;
        let unread = self.buf.get(from..self.end).unwrap_or(&[]);
        let (used, event) = self.decoder.decode(unread);
        self.start = from.saturating_add(used);
        Some(Token::Event {
            from,
            event: event?,
        })
    }

    fn end_step(&mut self) -> TokenOf<D> {
        match self.decoder.end() {
            Some(event) => Token::Event {
                from: self.end,
                event,
            },
            None => {
                self.ending = false;
                Token::Eof
            }
        }
    }

    /// The buffer to read into; only called once every byte was decoded.
    #[inline]
    pub(crate) fn space(&mut self) -> &mut [u8] {
        self.start = 0;
        self.end = 0;
        &mut self.buf
    }

    /// `n` bytes were read into [`Self::space`]; 0 is the end of the stream.
    #[inline]
    pub(crate) fn filled(&mut self, n: usize) -> Option<TokenOf<D>> {
        if n != 0 {
            self.end = n.min(R);
            return None;
        }
        self.ending = true;
        Some(self.end_step())
    }

    /// Turns a token into what the reader returns.
    #[inline]
    pub(crate) fn take<E>(&self, token: TokenOf<D>) -> Result<D::Item<'_>, IoError<E, D::Error>> {
        match token {
            Token::Event { from, event } => match event {
                Event::Found(found) => {
                    let input = self.buf.get(from..self.end).unwrap_or(&[]);
                    Ok(self.decoder.item(input, found))
                }
                Event::Error(e) => Err(IoError::Protocol(e)),
                Event::Truncated(pending) => Err(IoError::UnexpectedEof { pending }),
            },
            Token::Eof => Err(IoError::Eof),
        }
    }

    /// The bytes read from the transport but not decoded yet.
    pub(crate) fn unread(&self) -> usize {
        self.end.saturating_sub(self.start)
    }
}

/// The writers hand the transport at most this many bytes of an iterator at a time.
pub(crate) const CHUNK: usize = 32;

/// The bytes of an iterator on their way out, a chunk at a time.
pub(crate) struct Chunks<I> {
    bytes: I,
    chunk: [u8; CHUNK],
    at: usize,
    end: usize,
    total: usize,
}

impl<I: Iterator<Item = u8>> Chunks<I> {
    pub(crate) const fn new(bytes: I) -> Self {
        Self {
            bytes,
            chunk: [0; CHUNK],
            at: 0,
            end: 0,
            total: 0,
        }
    }

    /// What is still to be written of the current chunk, the next chunk once it is out, or
    /// `None` once the iterator is exhausted.
    pub(crate) fn pending(&mut self) -> Option<&[u8]> {
        if self.at >= self.end {
            let mut n = 0;
            for slot in self.chunk.iter_mut() {
                let Some(b) = self.bytes.next() else { break };
                *slot = b;
                n += 1;
            }
            (self.at, self.end) = (0, n);
        }
        self.chunk.get(self.at..self.end).filter(|c| !c.is_empty())
    }

    /// A `write` of [`Self::pending`] accepted `n` bytes (0: [`IoError::WriteZero`]).
    pub(crate) fn wrote<E, P>(&mut self, n: usize) -> Result<(), IoError<E, P>> {
        if n == 0 {
            return Err(IoError::WriteZero);
        }
        let n = n.min(self.end.saturating_sub(self.at));
        self.at = self.at.saturating_add(n);
        self.total = self.total.saturating_add(n);
        Ok(())
    }

    /// The bytes written.
    pub(crate) const fn total(&self) -> usize {
        self.total
    }
}

/// What is left of `buf` after a `write` accepted `n` bytes of it (0:
/// [`IoError::WriteZero`]).
pub(crate) fn advance<E, P>(buf: &[u8], n: usize) -> Result<&[u8], IoError<E, P>> {
    if n == 0 {
        return Err(IoError::WriteZero);
    }
    Ok(buf.get(n..).unwrap_or(&[]))
}

/// Liveness: the steps the read and write loops end on. A mutant that breaks one of them makes
/// a loop of `tests/all/io.rs` spin (a hang, not a failure); these fail at once instead (unit
/// tests run before the integration tests).
#[cfg(test)]
mod liveness {
    use super::*;

    /// Holds every byte; the end of the stream reports them once.
    struct Hold(usize);

    impl Decode for Hold {
        type Error = ();
        type Found = ();
        type Item<'a> = ();
        const TRUNCATED: () = ();
        fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<(), ()>>) {
            self.0 += bytes.len();
            (bytes.len(), None)
        }
        fn end(&mut self) -> Option<Event<(), ()>> {
            let held = core::mem::take(&mut self.0);
            (held > 0).then_some(Event::Truncated(held))
        }
        fn item(&self, _input: &[u8], _found: ()) {}
        fn span(&self) -> crate::Span {
            crate::Span::default()
        }
    }

    #[test]
    fn a_read_of_zero_bytes_ends_the_stream_and_others_do_not() {
        let mut core = ReaderCore::<_, 4>::new(Hold(0));
        core.space();
        assert!(core.filled(3).is_none());
        assert_eq!(core.unread(), 3);
        assert!(core.decode().is_none());
        core.space();
        let token = core.filled(0);
        assert!(matches!(
            token,
            Some(Token::Event {
                event: Event::Truncated(3),
                ..
            })
        ));
        assert!(matches!(core.decode(), Some(Token::Eof)));
        // Reading goes on after the end.
        assert!(core.decode().is_none());
    }

    #[test]
    fn a_write_moves_the_chunk_on() {
        let mut chunks = Chunks::new([1u8, 2, 3].into_iter());
        assert_eq!(chunks.pending(), Some(&[1u8, 2, 3][..]));
        assert_eq!(chunks.wrote::<(), ()>(2), Ok(()));
        assert_eq!(chunks.pending(), Some(&[3u8][..]));
        assert_eq!(chunks.wrote::<(), ()>(0), Err(IoError::WriteZero));
        assert_eq!(chunks.wrote::<(), ()>(9), Ok(()));
        assert_eq!(chunks.pending(), None);
        assert_eq!(chunks.total(), 3);
    }
}
