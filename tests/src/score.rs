//! Scoring what a decoder delivered against what was sent.

/// The figures of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Figures {
    /// Frames sent.
    pub sent: usize,
    /// Frames whose bytes the channel left untouched.
    pub intact_sent: usize,
    /// Untouched frames the decoder delivered, in order.
    pub intact_delivered: usize,
    /// Touched frames whose content the decoder still recovered exactly (e.g. only a flag hit).
    pub recovered: usize,
    /// Frames delivered that match nothing sent: corrupted frames wrongly accepted.
    pub wrongly_accepted: usize,
}

impl Figures {
    /// Intact frames delivered / intact frames sent, in percent.
    pub fn delivered_percent(&self) -> f64 {
        if self.intact_sent == 0 {
            100.0
        } else {
            100.0 * self.intact_delivered as f64 / self.intact_sent as f64
        }
    }
}

/// Matches delivered frame keys to the sent ones, in order. A delivered key equal to one of
/// the next `window` sent keys counts for that frame; anything else was wrongly accepted.
pub fn score(sent: &[(Vec<u8>, bool)], delivered: &[Vec<u8>], window: usize) -> Figures {
    let mut f = Figures {
        sent: sent.len(),
        intact_sent: sent.iter().filter(|s| s.1).count(),
        ..Figures::default()
    };
    let mut cursor = 0;
    for d in delivered {
        let end = (cursor + window).min(sent.len());
        match sent[cursor..end].iter().position(|(k, _)| k == d) {
            Some(j) => {
                if sent[cursor + j].1 {
                    f.intact_delivered += 1;
                } else {
                    f.recovered += 1;
                }
                cursor += j + 1;
            }
            None => f.wrongly_accepted += 1,
        }
    }
    f
}
