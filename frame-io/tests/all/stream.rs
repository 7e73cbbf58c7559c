//! `Stream`: every event with its place, the same whatever slices the stream comes in, through
//! each of its forms (`feed` and `finish`, `next_event` and `end_event`), and the count of
//! bytes used across streams. (`Span::after`, the bytes held after an event, is exercised by
//! the rescanning protocols' own place tests.)

use frame_io::{Decode, Event, Place, Span, Stream};

/// Words of up to 6 bytes, each ended by a space; a longer word is an error at its seventh
/// byte; at the end of the stream the bytes held are a word cut short.
#[derive(Debug, Default)]
struct Words {
    len: usize,
    span: Span,
}

impl Decode for Words {
    type Error = &'static str;
    type Found = usize;
    type Item<'a> = usize;
    const TRUNCATED: &'static str = "cut short";

    fn decode(&mut self, bytes: &[u8]) -> (usize, Option<Event<usize, &'static str>>) {
        for (i, &b) in bytes.iter().enumerate() {
            if b == b' ' {
                let len = core::mem::take(&mut self.len);
                // The word and its space.
                self.span = Span {
                    len: len + 1,
                    after: 0,
                };
                return (i + 1, Some(Event::Found(len)));
            }
            self.len += 1;
            if self.len > 6 {
                self.len = 0;
                // The seven bytes condemned, none held after them.
                self.span = Span { len: 7, after: 0 };
                return (i + 1, Some(Event::Error("word too long")));
            }
        }
        (bytes.len(), None)
    }

    fn end(&mut self) -> Option<Event<usize, &'static str>> {
        let pending = core::mem::take(&mut self.len);
        self.span = Span {
            len: pending,
            after: 0,
        };
        (pending > 0).then_some(Event::Truncated(pending))
    }

    fn item<'a>(&'a self, _input: &'a [u8], found: usize) -> usize {
        found
    }

    fn span(&self) -> Span {
        self.span
    }
}

/// An event as owned data.
type Placed = (Place, Result<usize, &'static str>);

const STREAM: &[u8] = b"ab cde toolongword x yz";

/// The stream's events and their places, written out.
const WANT: [Placed; 5] = [
    (Place { offset: 0, len: 3 }, Ok(2)),
    (Place { offset: 3, len: 4 }, Ok(3)),
    (Place { offset: 7, len: 7 }, Err("word too long")),
    (Place { offset: 14, len: 5 }, Ok(4)),
    (Place { offset: 19, len: 2 }, Ok(1)),
];
/// The word cut short by the end: "yz".
const CUT: Placed = (Place { offset: 21, len: 2 }, Err("cut short"));

fn fed(cuts: &[usize]) -> (Vec<Placed>, u64) {
    let mut stream = Stream::new(Words::default());
    let mut out = Vec::new();
    for pair in cuts.windows(2) {
        stream.feed(&STREAM[pair[0]..pair[1]], |place, ev| out.push((place, ev)));
    }
    stream.finish(|place, ev| out.push((place, ev)));
    (out, stream.used())
}

#[test]
fn feed_and_finish_place_every_event_however_the_stream_is_cut() {
    let mut want = WANT.to_vec();
    want.push(CUT);
    assert_eq!(fed(&[0, STREAM.len()]), (want.clone(), STREAM.len() as u64));
    let every: Vec<usize> = (0..=STREAM.len()).collect();
    assert_eq!(fed(&every), (want.clone(), STREAM.len() as u64));
    for cut in 0..=STREAM.len() {
        assert_eq!(fed(&[0, cut, STREAM.len()]).0, want, "cut at {cut}");
    }
}

#[test]
fn the_pull_forms_place_every_event() {
    let mut stream = Stream::new(Words::default());
    let mut out = Vec::new();
    let mut rest = STREAM;
    loop {
        let (used, ev) = stream.next_event(rest);
        rest = &rest[used..];
        match ev {
            Some(ev) => out.push(ev),
            None => break,
        }
    }
    assert!(rest.is_empty());
    assert_eq!(out, WANT);
    assert_eq!(stream.used(), STREAM.len() as u64);
    assert_eq!(stream.end_event(), Some(CUT));
    assert_eq!(stream.end_event(), None);
    // One byte at a time too: the bytes used are counted by the call that used them.
    let mut stream = Stream::new(Words::default());
    let mut out = Vec::new();
    for byte in STREAM {
        let (used, ev) = stream.next_event(core::slice::from_ref(byte));
        assert_eq!(used, 1);
        out.extend(ev);
    }
    out.extend(stream.end_event());
    let mut want = WANT.to_vec();
    want.push(CUT);
    assert_eq!(out, want);
}

#[test]
fn offsets_go_on_across_streams_and_a_decoder_can_be_reached() {
    let mut stream = Stream::new(Words::default());
    stream.feed(b"ab", |_, _| {});
    stream.finish(|_, _| {});
    let mut places = Vec::new();
    stream.feed(b"cd ", |place, _| places.push(place));
    assert_eq!(places, [Place { offset: 2, len: 3 }]);
    assert_eq!(places[0].end(), 5);
    assert_eq!(stream.used(), 5);
    stream.decoder_mut().len = 4;
    assert_eq!(stream.decoder().len, 4);
    assert_eq!(stream.into_inner().len, 4);
}

#[test]
fn a_place_counts_back_from_the_bytes_used() {
    assert_eq!(
        Span { len: 3, after: 2 }.place(10),
        Place { offset: 5, len: 3 }
    );
    assert_eq!(Place { offset: 5, len: 3 }.end(), 8);
    // The count wraps, as a 64-bit count of bytes would after 2^64 of them.
    assert_eq!(
        Span { len: 2, after: 0 }.place(1),
        Place {
            offset: u64::MAX,
            len: 2
        }
    );
}
