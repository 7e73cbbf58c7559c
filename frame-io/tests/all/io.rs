//! The blocking and async readers deliver exactly what the decoder delivers over the whole
//! stream, whatever the read sizes and the read buffer's size, with pending reads, transport
//! errors anywhere and the end of the stream in or between frames; the write loops write
//! exactly their bytes, whatever the transport accepts per call.

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};

use embedded_io::ErrorKind;
use frame_io::{Decode, Event, IoError, Span, embedded_io as bio, embedded_io_async as aio};

/// Where a line is: in the decoder's buffer, or in place in the input of `decode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    Held(usize),
    InPlace { at: usize, len: usize },
}

/// Lines ended by `\n`, of up to 8 bytes; a longer line is an error at its ninth byte. A line
/// whole in the input while nothing is held is found in place. At the end of the stream the
/// held bytes are first reported as `Truncated`, then (rescanned, say) handed out as a line.
#[derive(Debug, Clone, Default)]
struct Lines {
    buf: [u8; 8],
    len: usize,
    ends: usize,
    /// The held bytes were reported as `Truncated`; the next `end` hands them out.
    truncated: bool,
}

impl Decode for Lines {
    type Error = &'static str;
    type Found = Found;
    type Item<'a> = &'a [u8];
    const TRUNCATED: &'static str = "line cut short";

    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<Found, &'static str>>) {
        if self.len == 0 {
            if let Some(at) = bytes.iter().take(9).position(|&b| b == b'\n') {
                return (
                    at + 1,
                    Some(Event::Found(Found::InPlace { at: 0, len: at })),
                );
            }
        }
        for (i, &b) in bytes.iter().enumerate() {
            if b == b'\n' {
                let len = std::mem::take(&mut self.len);
                return (i + 1, Some(Event::Found(Found::Held(len))));
            }
            let Some(slot) = self.buf.get_mut(self.len) else {
                self.len = 0;
                return (i + 1, Some(Event::Error("line too long")));
            };
            *slot = b;
            self.len += 1;
        }
        (bytes.len(), None)
    }

    fn end(&mut self) -> Option<Event<Found, &'static str>> {
        self.ends += 1;
        if self.len == 0 {
            return None;
        }
        if !std::mem::replace(&mut self.truncated, true) {
            return Some(Event::Truncated(self.len));
        }
        self.truncated = false;
        Some(Event::Found(Found::Held(std::mem::take(&mut self.len))))
    }

    fn item<'a>(&'a self, input: &'a [u8], found: Found) -> &'a [u8] {
        match found {
            Found::Held(len) => &self.buf[..len],
            Found::InPlace { at, len } => &input[at..at + len],
        }
    }

    fn span(&self) -> Span {
        // The readers never ask where an event is.
        Span::default()
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Ev {
    Line(Vec<u8>),
    Protocol(&'static str),
    UnexpectedEof(usize),
    Eof,
}

/// The reference: the whole stream through `decode` at once, then `end` until `None`.
fn reference(stream: &[u8]) -> Vec<Ev> {
    let mut d = Lines::default();
    let mut out = Vec::new();
    let mut rest = stream;
    loop {
        let (used, event) = d.decode(rest);
        match event {
            Some(Event::Found(f)) => out.push(Ev::Line(d.item(rest, f).to_vec())),
            Some(Event::Error(e)) => out.push(Ev::Protocol(e)),
            Some(Event::Truncated(n)) => out.push(Ev::UnexpectedEof(n)),
            None => break,
        }
        rest = &rest[used..];
    }
    while let Some(event) = d.end() {
        match event {
            Event::Found(f) => out.push(Ev::Line(d.item(&[], f).to_vec())),
            Event::Error(e) => out.push(Ev::Protocol(e)),
            Event::Truncated(n) => out.push(Ev::UnexpectedEof(n)),
        }
    }
    out.push(Ev::Eof);
    out
}

fn ev(r: Result<&[u8], IoError<ErrorKind, &'static str>>) -> Result<Ev, ErrorKind> {
    Ok(match r {
        Ok(line) => Ev::Line(line.to_vec()),
        Err(IoError::Protocol(e)) => Ev::Protocol(e),
        Err(IoError::UnexpectedEof { pending }) => Ev::UnexpectedEof(pending),
        Err(IoError::Eof) => Ev::Eof,
        Err(IoError::Transport(k)) => return Err(k),
        Err(IoError::WriteZero) => panic!("a reader never reports WriteZero"),
    })
}

/// An in-memory transport: reads of the sizes in `sizes` (cycled), `Pending` before every
/// other async read, an error (once) before the read that would start at each offset in
/// `errors`, and `extra` more bytes reported than given (a transport that lies).
struct Wire {
    data: Vec<u8>,
    pos: usize,
    sizes: Vec<usize>,
    call: usize,
    errors: Vec<usize>,
    pending: bool,
    extra: usize,
}

impl Wire {
    fn new(data: &[u8], sizes: &[usize], errors: &[usize]) -> Self {
        Wire {
            data: data.to_vec(),
            pos: 0,
            sizes: sizes.to_vec(),
            call: 0,
            errors: errors.to_vec(),
            pending: false,
            extra: 0,
        }
    }

    fn read_now(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        if let Some(i) = self.errors.iter().position(|&at| at <= self.pos) {
            self.errors.remove(i);
            return Err(ErrorKind::Other);
        }
        let size = self.sizes[self.call % self.sizes.len()].max(1);
        self.call += 1;
        let n = size.min(buf.len()).min(self.data.len() - self.pos);
        buf[..n].copy_from_slice(&self.data[self.pos..self.pos + n]);
        self.pos += n;
        Ok(if n == 0 { 0 } else { n + self.extra })
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
        self.pending = !self.pending;
        if self.pending {
            YieldOnce(false).await;
        }
        self.read_now(buf)
    }
}

/// A future that is pending once.
struct YieldOnce(bool);
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

fn block_on<F: Future>(f: F) -> F::Output {
    let mut f = pin!(f);
    let mut cx = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(v) = f.as_mut().poll(&mut cx) {
            return v;
        }
    }
}

/// Runs a reader to `Eof`; returns its events and the number of transport errors.
fn run(mut next: impl FnMut() -> Result<Ev, ErrorKind>) -> (Vec<Ev>, usize) {
    let (mut out, mut errors) = (Vec::new(), 0);
    loop {
        match next() {
            Ok(e) => {
                let end = e == Ev::Eof;
                out.push(e);
                if end {
                    return (out, errors);
                }
            }
            Err(_) => errors += 1,
        }
    }
}

fn check<const R: usize>(stream: &[u8], sizes: &[usize], errors: &[usize]) {
    let want = reference(stream);
    let injected = errors.iter().filter(|&&e| e <= stream.len()).count();
    let mut r = bio::Reader::<_, _, R>::new(Wire::new(stream, sizes, errors), Lines::default());
    let got = run(|| ev(r.read()));
    assert_eq!(
        got,
        (want.clone(), injected),
        "blocking, R {R}, sizes {sizes:?}"
    );
    assert_eq!(r.unread(), 0);
    let mut r = aio::Reader::<_, _, R>::new(Wire::new(stream, sizes, errors), Lines::default());
    let got = run(|| ev(block_on(r.read())));
    assert_eq!(got, (want, injected), "async, R {R}, sizes {sizes:?}");
    assert_eq!(r.unread(), 0);
}

const STREAMS: [&[u8]; 6] = [
    b"",
    b"ab\n\ncdefgh\n",
    b"ab\n123456789xy\nq",
    b"12345678\n123456789012345678\nz\n",
    b"\n\n\nlonger than eight\nhal",
    b"abc",
];

#[test]
fn readers_deliver_what_the_decoder_delivers() {
    for s in STREAMS {
        for size in 1..=s.len() + 1 {
            check::<1>(s, &[size], &[]);
            check::<3>(s, &[size], &[]);
            check::<64>(s, &[size, 1], &[]);
        }
    }
}

#[test]
fn transport_errors_lose_nothing() {
    for s in STREAMS {
        for at in 0..=s.len() {
            check::<4>(s, &[3], &[at]);
            check::<4>(s, &[1, 5], &[at, at + 2]);
        }
    }
}

#[test]
fn the_end_of_the_stream_inside_a_line() {
    let (events, _) = run({
        let mut r = bio::Reader::<_, _, 4>::new(Wire::new(b"ok\nhal", &[4], &[]), Lines::default());
        move || ev(r.read())
    });
    assert_eq!(
        events,
        [
            Ev::Line(b"ok".to_vec()),
            Ev::UnexpectedEof(3),
            Ev::Line(b"hal".to_vec()),
            Ev::Eof
        ]
    );
}

#[test]
fn end_is_called_first_once_then_until_none_and_reading_goes_on_after_eof() {
    let mut r = bio::Reader::<_, _, 8>::new(&b"ab"[..], Lines::default());
    assert_eq!(r.read(), Err(IoError::UnexpectedEof { pending: 2 }));
    assert_eq!(r.decoder().ends, 1);
    assert_eq!(r.read(), Ok(&b"ab"[..]));
    assert_eq!(r.read(), Err(IoError::Eof));
    assert_eq!(r.decoder().ends, 3);
    // After `Eof` the reader reads again: a transport that has more now is read on.
    *r.get_mut() = &b"cd\n"[..];
    assert_eq!(r.read(), Ok(&b"cd"[..]));
    assert_eq!(r.read(), Err(IoError::Eof));
    assert_eq!(r.decoder().ends, 4);

    let mut r = aio::Reader::<_, _, 8>::new(&b"ab"[..], Lines::default());
    assert_eq!(
        block_on(r.read()),
        Err(IoError::UnexpectedEof { pending: 2 })
    );
    assert_eq!(block_on(r.read()), Ok(&b"ab"[..]));
    assert_eq!(block_on(r.read()), Err(IoError::Eof));
    *r.get_mut() = &b"cd\n"[..];
    assert_eq!(block_on(r.read()), Ok(&b"cd"[..]));
    assert_eq!(r.decoder().ends, 3);
}

#[test]
fn unread_and_the_accessors() {
    let mut r = bio::Reader::<_, _, 16>::new(&b"a\nbc\nd"[..], Lines::default());
    assert_eq!(r.read(), Ok(&b"a"[..]));
    assert_eq!(r.unread(), 4);
    assert_eq!(r.get_ref().len(), 0);
    r.decoder_mut().ends = 7;
    assert_eq!(r.decoder().ends, 7);
    assert_eq!(r.into_inner(), &[] as &[u8]);

    let mut r = aio::Reader::<_, _, 16>::new(&b"a\nbc\nd"[..], Lines::default());
    assert_eq!(block_on(r.read()), Ok(&b"a"[..]));
    assert_eq!(r.unread(), 4);
    assert_eq!(block_on(r.read()), Ok(&b"bc"[..]));
    assert_eq!(r.unread(), 1);
    assert_eq!(r.get_ref().len(), 0);
    r.decoder_mut().ends = 7;
    assert_eq!(r.decoder().ends, 7);
    *r.get_mut() = &b"x"[..];
    assert_eq!(r.into_inner(), b"x");
}

#[test]
fn a_transport_that_reports_more_than_it_was_given_is_held_to_the_buffer() {
    for r_len in [1usize, 4] {
        let mut w = Wire::new(b"ab\ncd\n", &[2], &[]);
        w.extra = 5;
        let mut r = bio::Reader::<_, _, 4>::new(w, Lines::default());
        let _ = r.read();
        assert!(r.unread() <= 4, "{r_len}");
        let mut w = Wire::new(b"ab\ncd\n", &[2], &[]);
        w.extra = 5;
        let mut r = aio::Reader::<_, _, 4>::new(w, Lines::default());
        let _ = block_on(r.read());
        assert!(r.unread() <= 4);
    }
}

/// A transport that takes at most `max` bytes per write (and claims `extra` more), fails once
/// at `fail_at`, or accepts nothing.
#[derive(Default)]
struct Sink {
    out: Vec<u8>,
    max: usize,
    extra: usize,
    fail_at: Option<usize>,
    zero: bool,
    writes: usize,
}

fn sink(max: usize) -> Sink {
    Sink {
        max,
        ..Sink::default()
    }
}

impl Sink {
    fn write_now(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        self.writes += 1;
        if self.fail_at.is_some_and(|at| self.out.len() >= at) {
            self.fail_at = None;
            return Err(ErrorKind::BrokenPipe);
        }
        if self.zero {
            return Ok(0);
        }
        let n = buf.len().min(self.max);
        self.out.extend_from_slice(&buf[..n]);
        Ok(n + self.extra)
    }
}

impl embedded_io::ErrorType for Sink {
    type Error = ErrorKind;
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

type WriteResult<T> = Result<T, IoError<ErrorKind, ()>>;

#[test]
fn write_iter_writes_every_byte_a_chunk_at_a_time() {
    for len in [0usize, 1, 31, 32, 33, 64, 100] {
        let want: Vec<u8> = (0..len).map(|i| i as u8).collect();
        for max in [1usize, 5, 32, 40] {
            let mut s = sink(max);
            let n: WriteResult<usize> = bio::write_iter(&mut s, want.iter().copied());
            assert_eq!(n, Ok(len));
            assert_eq!(s.out, want);
            // A chunk is at most 32 bytes: this many writes, no more.
            let chunks = (0..len).step_by(32).map(|at| (len - at).min(32));
            assert_eq!(s.writes, chunks.map(|c| c.div_ceil(max)).sum::<usize>());
            let mut s = sink(max);
            let n: WriteResult<usize> = block_on(aio::write_iter(&mut s, want.iter().copied()));
            assert_eq!(n, Ok(len));
            assert_eq!(s.out, want);
        }
    }
}

#[test]
fn write_all_writes_every_byte() {
    let want: Vec<u8> = (0..50).collect();
    for max in [1usize, 7, 50, 64] {
        let mut s = sink(max);
        let r: WriteResult<()> = bio::write_all(&mut s, &want);
        assert_eq!(r, Ok(()));
        assert_eq!(s.out, want);
        assert_eq!(s.writes, 50usize.div_ceil(max));
        let mut s = sink(max);
        let r: WriteResult<()> = block_on(aio::write_all(&mut s, &want));
        assert_eq!(r, Ok(()));
        assert_eq!(s.out, want);
        let r: WriteResult<()> = bio::write_all(&mut s, &[]);
        assert_eq!(r, Ok(()));
    }
}

#[test]
fn a_transport_that_claims_more_than_it_took_counts_what_it_was_given() {
    let want: Vec<u8> = (0..70).collect();
    let mut s = Sink {
        extra: 3,
        ..sink(10)
    };
    let n: WriteResult<usize> = bio::write_iter(&mut s, want.iter().copied());
    // Each write is believed up to what it was given: 10 + 10 + 10 (a 32-byte chunk: the
    // fourth write of 2 bytes claims 5), and so on; the count never passes what was given.
    assert!(n.unwrap() <= 70);
    let mut s = Sink {
        extra: 3,
        ..sink(10)
    };
    let n: WriteResult<usize> = block_on(aio::write_iter(&mut s, want.iter().copied()));
    assert!(n.unwrap() <= 70);
}

#[test]
fn write_errors_are_the_transports() {
    let bytes = [0x55u8; 100];
    for fail_at in [0usize, 8, 40] {
        let mut s = Sink {
            fail_at: Some(fail_at),
            ..sink(8)
        };
        let r: WriteResult<usize> = bio::write_iter(&mut s, bytes.iter().copied());
        assert_eq!(r, Err(IoError::Transport(ErrorKind::BrokenPipe)));
        let mut s = Sink {
            fail_at: Some(fail_at),
            ..sink(8)
        };
        let r: WriteResult<usize> = block_on(aio::write_iter(&mut s, bytes.iter().copied()));
        assert_eq!(r, Err(IoError::Transport(ErrorKind::BrokenPipe)));
        let mut s = Sink {
            fail_at: Some(fail_at),
            ..sink(8)
        };
        let r: WriteResult<()> = bio::write_all(&mut s, &bytes);
        assert_eq!(r, Err(IoError::Transport(ErrorKind::BrokenPipe)));
        let mut s = Sink {
            fail_at: Some(fail_at),
            ..sink(8)
        };
        let r: WriteResult<()> = block_on(aio::write_all(&mut s, &bytes));
        assert_eq!(r, Err(IoError::Transport(ErrorKind::BrokenPipe)));
    }
    let zero = || Sink {
        zero: true,
        ..sink(8)
    };
    let r: WriteResult<usize> = bio::write_iter(&mut zero(), bytes.iter().copied());
    assert_eq!(r, Err(IoError::WriteZero));
    let r: WriteResult<usize> = block_on(aio::write_iter(&mut zero(), bytes.iter().copied()));
    assert_eq!(r, Err(IoError::WriteZero));
    let r: WriteResult<()> = bio::write_all(&mut zero(), &bytes);
    assert_eq!(r, Err(IoError::WriteZero));
    let r: WriteResult<()> = block_on(aio::write_all(&mut zero(), &bytes));
    assert_eq!(r, Err(IoError::WriteZero));
}

#[test]
fn error_texts() {
    let cases: [(IoError<&str, &str>, &str); 5] = [
        (IoError::Transport("reset"), "transport error: \"reset\""),
        (
            IoError::Protocol("bad checksum"),
            "protocol error: bad checksum",
        ),
        (
            IoError::UnexpectedEof { pending: 5 },
            "end of stream inside a frame (5 bytes pending)",
        ),
        (IoError::Eof, "end of stream"),
        (IoError::WriteZero, "the transport accepted no bytes"),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
        assert_eq!(e.is_protocol(), matches!(e, IoError::Protocol(_)), "{e:?}");
        let dynamic: &dyn std::error::Error = &e;
        assert!(dynamic.source().is_none());
    }
}
