//! [`Input`]: a protocol decoder over `decode`'s input through the one adapter of the
//! contract (`frame_io::Stream`), each event at its input offset.

use aeolus_proto::{Decode, Stream};

use super::{Fault, Item, Placed};

/// A decoder and where its stream sits in the input: each event comes with the input offset
/// of its first byte and its length on the wire, from the event's place in the stream. The
/// caller says at which input offset each slice starts; a gap between slices (datagrams in a
/// capture) moves the offsets of what follows, and a frame never spans one (each datagram is
/// finished).
#[derive(Debug)]
pub(crate) struct Input<D> {
    stream: Box<Stream<D>>,
    /// Input offset minus stream offset, for the slice fed last (wrapping).
    delta: u64,
}

impl<D: Decode> Input<D> {
    /// `decoder` at the start of the input.
    pub(crate) fn new(decoder: D) -> Self {
        Input {
            stream: Box::new(Stream::new(decoder)),
            delta: 0,
        }
    }

    /// The decoder (its counters).
    pub(crate) fn decoder(&self) -> &D {
        self.stream.decoder()
    }

    /// The decoder, to drop what it holds at a datagram's end.
    pub(crate) fn decoder_mut(&mut self) -> &mut D {
        self.stream.decoder_mut()
    }

    /// Feeds `bytes`, which start at input offset `offset`: each event with its input offset
    /// and wire length.
    pub(crate) fn feed(
        &mut self,
        bytes: &[u8],
        offset: u64,
        mut on_event: impl FnMut(u64, u64, Result<D::Item<'_>, D::Error>),
    ) {
        self.delta = offset.wrapping_sub(self.stream.used());
        let delta = self.delta;
        self.stream.feed(bytes, |place, event| {
            on_event(place.offset.wrapping_add(delta), place.len as u64, event);
        });
    }

    /// The stream ended (the input, or a datagram): its events, as [`Input::feed`]'s.
    pub(crate) fn finish(
        &mut self,
        mut on_event: impl FnMut(u64, u64, Result<D::Item<'_>, D::Error>),
    ) {
        let delta = self.delta;
        self.stream.finish(|place, event| {
            on_event(place.offset.wrapping_add(delta), place.len as u64, event);
        });
    }
}

impl<D: Decode> Input<D> {
    /// The stream ended (`why`: the sentence that says which end): a frame in progress is
    /// given up as [`Fault::Cut`], counted in `truncated`.
    pub(crate) fn cut_short(
        &mut self,
        why: &'static str,
        truncated: &mut u32,
        mut on_item: impl FnMut(Placed<'_>),
    ) {
        self.finish(|at, len, event| {
            if event.is_err() {
                *truncated = truncated.wrapping_add(1);
                on_item(Placed {
                    offset: at,
                    len,
                    item: Item::Error(Fault::Cut(why)),
                });
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Offsets follow the input's, across a gap between two slices.
    #[test]
    fn events_are_placed_at_input_offsets() {
        let frame = [0x7E, 0x52, b'h', b'i', 0x00, 0x73, 0xEC, 0x7E];
        let mut input = Input::new(aeolus_proto::Decoder::<64>::new());
        let mut seen = Vec::new();
        input.feed(&frame[..3], 100, |at, len, ev| {
            seen.push((at, len, ev.is_ok()))
        });
        input.feed(&frame[3..], 103, |at, len, ev| {
            seen.push((at, len, ev.is_ok()))
        });
        input.decoder_mut().reset();
        input.feed(&[0x00, 0x7E, 0x52], 500, |at, len, ev| {
            seen.push((at, len, ev.is_ok()))
        });
        input.finish(|at, len, ev| seen.push((at, len, ev.is_ok())));
        assert_eq!(seen, [(100, 8, true), (501, 2, false)]);
    }
}
