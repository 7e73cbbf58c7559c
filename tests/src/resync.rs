//! The resynchronisation contract: for a stream of valid frames with one of them corrupted
//! by a single-byte fault at one position, how many of the *other*, intact frames the
//! decoder loses. Exhaustive over every position of the corrupted frame and every fault:
//! each of the 8 bit flips, the byte dropped, a byte inserted before it (0x00, 0xA5, and the
//! protocol's start or flag byte), and the byte replaced by the start or flag byte.

use std::collections::BTreeMap;

use crate::protocols::Protocol;
use crate::rng::Rng;

/// One single-byte fault at a position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fault {
    /// Flip bit `n` (0..8).
    Flip(u8),
    /// Drop the byte.
    Drop,
    /// Insert this byte before it.
    Insert(u8),
    /// Replace the byte by this one (the start or flag byte).
    Replace(u8),
}

impl Fault {
    /// Every fault the contract covers, for a protocol whose start or flag byte is `start`.
    pub fn all(start: u8) -> Vec<Fault> {
        let mut v: Vec<Fault> = (0..8).map(Fault::Flip).collect();
        v.extend([
            Fault::Drop,
            Fault::Insert(0x00),
            Fault::Insert(0xA5),
            Fault::Insert(start),
            Fault::Replace(start),
        ]);
        v
    }

    /// `frame` with the fault at `at`.
    pub fn apply(self, frame: &[u8], at: usize) -> Vec<u8> {
        let mut f = frame.to_vec();
        match self {
            Fault::Flip(bit) => f[at] ^= 1 << bit,
            Fault::Drop => {
                f.remove(at);
            }
            Fault::Insert(b) => f.insert(at, b),
            Fault::Replace(b) => {
                if f[at] == b {
                    // Not a fault at this position.
                    f[at] ^= 0x01;
                }
                f[at] = b;
            }
        }
        f
    }
}

/// The outcome over every case: how many cases lost how many intact frames, the worst case,
/// and the cases in which a frame nobody sent was delivered.
#[derive(Debug, Default, Clone)]
pub struct Contract {
    /// Intact frames lost -> number of cases.
    pub lost: BTreeMap<usize, usize>,
    /// Cases run.
    pub cases: usize,
    /// Cases in which the decoder delivered a frame that was not sent.
    pub phantoms: usize,
    /// The first case with a phantom: fault, position, frame length.
    pub first_phantom: Option<(Fault, usize, usize)>,
    /// The first worst case: fault, position, frame length.
    pub worst: Option<(Fault, usize, usize)>,
}

impl Contract {
    /// The most intact frames lost in any case.
    pub fn worst_lost(&self) -> usize {
        self.lost.keys().next_back().copied().unwrap_or(0)
    }
}

/// The shape of each stream: intact frames before the corrupted one, and after it.
///
/// Frames before the victim are delivered before the fault whatever the decoder does after
/// it, so only the frames after it can show a decoder that fails to resynchronise: a bound
/// of "at most K lost" says something only with more than K of them.
#[derive(Debug, Clone, Copy)]
pub struct Stream {
    /// Intact frames before the corrupted one.
    pub before: usize,
    /// Intact frames after the corrupted one.
    pub after: usize,
}

/// The streams of the pinned contract: two frames before the victim, eight after it (more
/// than any protocol's bound, so a decoder that never resynchronises breaks every bound).
pub const CONTRACT_STREAM: Stream = Stream {
    before: 2,
    after: 8,
};

/// Runs the contract: `seeds` streams of `shape.before` random frames, the corrupted one
/// (at every position, by every fault of [`Fault::all`]) and `shape.after` random frames.
pub fn run(p: &dyn Protocol, start: u8, seeds: u64, shape: Stream) -> Contract {
    let mut c = Contract::default();
    let frames = shape.before + 1 + shape.after;
    for seed in 0..seeds {
        let mut rng = Rng::new(0x5EED_0000 + seed);
        let sent: Vec<(Vec<u8>, Vec<u8>)> = (0..frames).map(|_| p.frame(&mut rng)).collect();
        let victim = shape.before;
        let victim_wire = &sent[victim].0;
        for at in 0..victim_wire.len() {
            for fault in Fault::all(start) {
                let mut stream = Vec::new();
                for (i, (wire, _)) in sent.iter().enumerate() {
                    if i == victim {
                        stream.extend(fault.apply(wire, at));
                    } else {
                        stream.extend(wire);
                    }
                }
                let mut got = p.decode(&stream);
                let mut lost = 0;
                for (i, (_, key)) in sent.iter().enumerate() {
                    if i == victim {
                        continue;
                    }
                    match got.iter().position(|k| k == key) {
                        Some(j) => {
                            got.remove(j);
                        }
                        None => lost += 1,
                    }
                }
                // What is left is the corrupted frame, decoded as sent (a fault that changed
                // nothing the frame carries) or as something never sent.
                got.retain(|k| *k != sent[victim].1);
                if !got.is_empty() {
                    c.phantoms += 1;
                    c.first_phantom
                        .get_or_insert((fault, at, victim_wire.len()));
                }
                if lost > c.worst_lost() || c.worst.is_none() {
                    c.worst = Some((fault, at, victim_wire.len()));
                }
                *c.lost.entry(lost).or_default() += 1;
                c.cases += 1;
            }
        }
    }
    c
}

/// A deliberately broken decoder, to show that the contract's bounds can fail: `inner`'s
/// decoder, except that after its first error it delivers nothing more (as if it dropped
/// every byte after the first bad one and never resynchronised).
pub struct NeverResync<'a>(pub &'a dyn Protocol);

impl Protocol for NeverResync<'_> {
    fn name(&self) -> String {
        format!("{} (never resynchronising)", self.0.name())
    }

    fn frame(&self, rng: &mut Rng) -> (Vec<u8>, Vec<u8>) {
        self.0.frame(rng)
    }

    fn garbage(&self, rng: &mut Rng, n: usize) -> Vec<u8> {
        self.0.garbage(rng, n)
    }

    fn decode_events(&self, stream: &[u8]) -> Vec<Option<Vec<u8>>> {
        self.0
            .decode_events(stream)
            .into_iter()
            .take_while(Option::is_some)
            .collect()
    }

    fn decode_naive(&self, stream: &[u8]) -> Vec<Vec<u8>> {
        self.0.decode_naive(stream)
    }
}
