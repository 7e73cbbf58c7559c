//! What a decoder's step reports, the same for both decoders.

/// What the rules of a decoder made of the bytes at the front of a window: the decoder's own
/// buffer (`push`, `poll`, `idle`) or, on the slice path, the input itself (`feed`). An event
/// the bytes gave has already been handed to the step's `on_event`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step {
    /// Undecided until the window holds this many bytes.
    Need(usize),
    /// The front's bytes up to this count are decided on: drop them.
    Used(usize),
}
