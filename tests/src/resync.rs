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

/// Runs the contract: `seeds` streams of `frames` random frames, the middle one corrupted at
/// every position by every fault of [`Fault::all`].
pub fn run(p: &dyn Protocol, start: u8, seeds: u64, frames: usize) -> Contract {
    let mut c = Contract::default();
    for seed in 0..seeds {
        let mut rng = Rng::new(0x5EED_0000 + seed);
        let sent: Vec<(Vec<u8>, Vec<u8>)> = (0..frames).map(|_| p.frame(&mut rng)).collect();
        let victim = frames / 2;
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
