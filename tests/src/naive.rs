//! Naive decoders, the baseline of the corruption figures: they trust the length a frame
//! claims and never rescan bytes they have consumed.

use aeolus_proto::message::Message;

/// A naive AEOLUS receiver: after a flag it reads the ID, then trusts the data length the ID
/// implies (section 6's table), consuming exactly that many bytes plus the CRC even if a flag
/// turns up among them; then it hunts for a new flag. Variable-length IDs run to the next flag.
pub fn aeolus(stream: &[u8]) -> Vec<Vec<u8>> {
    #[derive(PartialEq)]
    enum S {
        Hunt,
        Id,
        Body,
    }
    let fixed = |id: u8| -> Option<usize> {
        let dummy = [0u8; 256];
        match Message::parse(id, &dummy[..0]) {
            Err(aeolus_proto::Error::WrongLength { expected, .. }) => Some(expected as usize),
            _ => None,
        }
    };
    let mut out = Vec::new();
    let mut s = S::Hunt;
    let mut raw = Vec::new();
    let mut want: Option<usize> = None;
    let mut esc = false;
    let finish = |raw: &Vec<u8>, out: &mut Vec<Vec<u8>>| {
        if raw.len() >= 3 {
            let n = raw.len();
            let rx = u16::from_le_bytes([raw[n - 2], raw[n - 1]]);
            if rx == 0 || rx == aeolus_proto::crc::checksum(&raw[..n - 2]) {
                out.push(raw.clone());
            }
        }
    };
    for &b in stream {
        match s {
            S::Hunt => {
                if b == 0x7E {
                    s = S::Id;
                }
            }
            S::Id | S::Body if want.is_none() && b == 0x7E => {
                // Variable length (or no ID yet): a flag ends it.
                if s == S::Body {
                    finish(&raw, &mut out);
                }
                raw.clear();
                esc = false;
                s = S::Id;
            }
            S::Id | S::Body => {
                if b == 0x7D && !esc {
                    esc = true;
                    continue;
                }
                let v = if esc { b ^ 0x20 } else { b };
                esc = false;
                raw.push(v);
                if s == S::Id {
                    want = fixed(v).map(|l| l + 3);
                    s = S::Body;
                }
                if Some(raw.len()) == want {
                    finish(&raw, &mut out);
                    raw.clear();
                    want = None;
                    s = S::Hunt;
                }
            }
        }
    }
    out
}
