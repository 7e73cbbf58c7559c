//! The links read and write their ports by slice (`embedded_io`). A port may hand over what it
//! has received in pieces of any size and take any part of a write: these tests run the same
//! received stream through ports that give 1, 2, 3, ... bytes per read and take 1, 2, ...
//! bytes per write, and require exactly the bytes sent and the counters of the one-byte port
//! (the byte-at-a-time behaviour). They also hold the links to their RX bounds: at most
//! `RX_BUDGET` bytes read per poll, and nothing read (so nothing lost) while the TX queue has
//! no room for one more answer.

use std::collections::VecDeque;
use std::convert::Infallible;

use aeolus_proto::message::{Message, SetTime, Text};
use aeolus_proto::{CrcMode, Decode, Decoder};
use embedded_io::{ErrorType, Write, WriteReady};
use sensor_box::aeolus_link::{self, AeolusLink};
use sensor_box::aok_link::{self, AokLink};
use sensor_box::aydp_link::{self, AydpLink};
use sensor_box::port::{Receive, Transmit};
use sensor_box::{Persisted, Shared};

/// An in-memory port: hands over at most `rx_piece` received bytes per read and takes at most
/// `tx_piece` bytes per write, and at most `tx_room` bytes until the test gives it more (a
/// UART that drains at a fixed rate).
struct SlicePort {
    rx: VecDeque<u8>,
    rx_piece: usize,
    /// Bytes the link has read, in total.
    read: usize,
    tx_piece: usize,
    tx_room: usize,
    sent: Vec<u8>,
    /// Bytes the link encoded straight into the port (`Transmit`), in total.
    lent: usize,
}

impl SlicePort {
    /// Polls once a millisecond for `ms` milliseconds, handing the port each piece of `input`
    /// at its millisecond and, with `rate`, letting the UART take that many bytes each
    /// millisecond; the most bytes one poll read.
    fn drive(
        &mut self,
        ms: u64,
        input: &[(u64, Vec<u8>)],
        rate: Option<usize>,
        mut poll: impl FnMut(u64, &mut Self),
    ) -> usize {
        let mut most = 0;
        for now in 0..ms {
            for (_, bytes) in input.iter().filter(|(at, _)| *at == now) {
                self.rx.extend(bytes);
            }
            if let Some(rate) = rate {
                self.tx_room = rate;
            }
            let before = self.read;
            poll(now, self);
            most = most.max(self.read - before);
        }
        most
    }

    fn new(rx_piece: usize, tx_piece: usize) -> Self {
        SlicePort {
            rx: VecDeque::new(),
            rx_piece,
            read: 0,
            tx_piece,
            tx_room: usize::MAX,
            sent: Vec::new(),
            lent: 0,
        }
    }
}

impl ErrorType for SlicePort {
    type Error = Infallible;
}

impl Receive for SlicePort {
    fn receive(&mut self, take: impl FnOnce(&[u8]) -> usize) -> Result<usize, Infallible> {
        if self.rx.is_empty() {
            return Ok(0);
        }
        let piece = self.rx_piece.min(self.rx.len());
        let bytes = &self.rx.make_contiguous()[..piece];
        let n = take(bytes);
        assert!(n <= piece, "took more than it was lent");
        self.rx.drain(..n);
        self.read += n;
        Ok(n)
    }
}

impl Transmit for SlicePort {
    /// Lends as many free bytes as one write would take (so a frame longer than `tx_piece`
    /// or than the room left goes through the link's queue instead).
    fn transmit(&mut self, fill: impl FnOnce(&mut [u8]) -> usize) -> Result<usize, Infallible> {
        let mut free = vec![0xAA; self.tx_piece.min(self.tx_room).min(4096)];
        let n = fill(&mut free);
        assert!(n <= free.len(), "wrote more than it was lent");
        self.sent.extend_from_slice(&free[..n]);
        self.tx_room -= n;
        self.lent += n;
        Ok(n)
    }
}

impl WriteReady for SlicePort {
    fn write_ready(&mut self) -> Result<bool, Infallible> {
        Ok(self.tx_room > 0)
    }
}

impl Write for SlicePort {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        assert!(
            buf.is_empty() || self.tx_room > 0,
            "write without write_ready: it would block"
        );
        let n = buf.len().min(self.tx_piece).min(self.tx_room);
        self.sent.extend_from_slice(&buf[..n]);
        self.tx_room -= n;
        Ok(n)
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// The read sizes every test tries: every size up to past the links' read buffer, and more.
fn rx_pieces() -> impl Iterator<Item = usize> {
    (1..=70).chain([97, 128, 255, 256, 257, 1000])
}

fn aeolus(msg: Message<'_>) -> Vec<u8> {
    let mut buf = [0u8; 600];
    let n = msg.encode(&mut buf, CrcMode::Compute).unwrap();
    buf[..n].to_vec()
}

fn command(text: &str) -> Vec<u8> {
    aeolus(Message::Command(Text::new(text).unwrap()))
}

/// What the AEOLUS peer sends, by millisecond: commands answered by TOASTs (known, unknown,
/// the longest), a SETTIME, garbage, a bad escape, a bad CRC, a frame too long for the
/// decoder, a burst of 40 commands in one millisecond (more than one poll reads) and 600
/// bytes of noise.
fn aeolus_input() -> Vec<(u64, Vec<u8>)> {
    let settime = aeolus(Message::SetTime(SetTime {
        year_since_1900: 124,
        month0: 2,
        day: 1,
        hour: 12,
        minute: 0,
        second: 0,
    }));
    let mut bad_crc = command("a pause");
    let at = bad_crc.len() - 2;
    bad_crc[at] ^= 0x55;
    let mut burst = Vec::new();
    for i in 0..40 {
        burst.extend(command(&format!("burst {i}")));
    }
    let noise: Vec<u8> = (0..600u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let mut too_long = vec![0x7E, 0x52];
    too_long.extend(std::iter::repeat_n(b'x', 400));
    too_long.push(0x7E);
    vec![
        (2, command("a pause")),
        (3, [b"garbage".as_slice(), &command("a resume")].concat()),
        (5, settime),
        (
            7,
            [&[0x7E, 0x52, 0x7D, 0x11][..], &command("what")].concat(),
        ),
        (9, bad_crc),
        (11, too_long),
        (13, command(&"y".repeat(120))),
        (20, burst),
        (24, noise),
        (40, [command("a pause"), command("a resume")].concat()),
    ]
}

/// Runs the AEOLUS link for 200 ms over a port that reads `rx_piece` and writes (or lends)
/// `tx_piece` bytes at a time and drains `rate` bytes per millisecond; what it sent, its
/// counters, the most bytes one poll read and the bytes encoded straight into the port.
fn run_aeolus(rx_piece: usize, tx_piece: usize, rate: usize) -> (Vec<u8>, String, usize, usize) {
    let mut port = SlicePort::new(rx_piece, tx_piece);
    let mut shared = Shared::new(Persisted::default(), 0);
    let mut link = AeolusLink::new(0);
    let most = port.drive(200, &aeolus_input(), Some(rate), |now, p| {
        link.poll(now, p, &mut shared)
    });
    let state = format!(
        "{:?} {:?} paused {} clock {:?}",
        link.counters(),
        link.rx_stats(),
        shared.paused,
        shared.wall_clock
    );
    (port.sent, state, most, port.lent)
}

#[test]
fn aeolus_sends_the_same_bytes_under_every_split() {
    // 921 600 Bd is 92 bytes a millisecond; 40 a millisecond makes the TX queue back up.
    for rate in [92, 40] {
        let (reference, state, most, lent) = run_aeolus(1, usize::MAX, rate);
        assert_eq!(
            most,
            aeolus_link::RX_BUDGET,
            "the burst takes more than one poll"
        );
        // Both TX paths ran: telemetry encoded straight into the port while the queue was
        // empty, answers and what did not fit through the queue.
        assert!(lent > 0, "nothing lent");
        assert!(lent < reference.len(), "{lent} of {} lent", reference.len());
        for rx_piece in rx_pieces() {
            for tx_piece in [1, 2, 7, 64, usize::MAX] {
                let (sent, s, m, _) = run_aeolus(rx_piece, tx_piece, rate);
                assert!(m <= aeolus_link::RX_BUDGET);
                assert_eq!(
                    s, state,
                    "reads of {rx_piece}, writes of {tx_piece}, {rate} B/ms"
                );
                assert!(
                    sent == reference,
                    "reads of {rx_piece}, writes of {tx_piece}, {rate} B/ms: other bytes sent"
                );
            }
        }
    }
}

/// The TOASTs in an AEOLUS stream.
fn toasts(wire: &[u8]) -> Vec<String> {
    let mut decoder = Decoder::<512>::new();
    let mut out = Vec::new();
    decoder.feed(wire, |f| {
        if let Ok(Message::Toast(t)) = f.unwrap().message() {
            out.push(t.as_str().unwrap().to_owned());
        }
    });
    out
}

#[test]
fn aeolus_reads_nothing_while_an_answer_would_not_fit_and_loses_nothing() {
    for rx_piece in [1, 5, 64, 1000] {
        let mut port = SlicePort::new(rx_piece, usize::MAX);
        let mut shared = Shared::new(Persisted::default(), 0);
        let mut link = AeolusLink::new(0);
        // Telemetry paused, so only answers are sent; the UART takes nothing for a while.
        port.rx.extend(command("a pause"));
        link.poll(0, &mut port, &mut shared);
        let mut burst = Vec::new();
        for i in 0..30 {
            burst.extend(command(&format!("unknown {i:02} {}", "z".repeat(100))));
        }
        port.rx.extend(&burst);
        port.tx_room = 0;
        for now in 1..20 {
            link.poll(now, &mut port, &mut shared);
            // What is left in the link's queue is always room for one longest answer short.
            assert!(link.tx_pending() <= aeolus_link::TX_QUEUE);
        }
        // The port keeps what the link could not answer yet.
        assert!(port.rx.len() > burst.len() / 2, "reads of {rx_piece}");
        // The UART drains again: every command is answered, none dropped.
        for now in 20..400 {
            port.tx_room = 92;
            link.poll(now, &mut port, &mut shared);
        }
        assert!(port.rx.is_empty());
        assert_eq!(link.counters().tx_dropped, 0, "reads of {rx_piece}");
        let answers = toasts(&port.sent);
        assert_eq!(answers.len(), 2 + 30, "boot, paused, then the 30 answers");
        // Each answer is a TOAST of the longest text (the command is cut to fit).
        let answer = |i: u32| {
            format!("unknown command: unknown {i:02} {}", "z".repeat(100))[..120].to_owned()
        };
        assert_eq!(answers[2], answer(0));
        assert_eq!(answers[31], answer(29));
    }
}

/// Runs the AOK link for 300 ms; what it sent and its counters.
fn run_aok(
    rx_piece: usize,
    tx_piece: usize,
    rate: usize,
    input: &[(u64, Vec<u8>)],
) -> (Vec<u8>, String, usize) {
    let mut port = SlicePort::new(rx_piece, tx_piece);
    let mut shared = Shared::new(Persisted::default(), 0);
    let mut link = AokLink::new(&shared);
    let most = port.drive(300, input, Some(rate), |now, p| {
        link.poll(now, p, &mut shared)
    });
    let state = format!(
        "{:?} {:?} {:?} debug {}",
        link.counters(),
        link.decoder_stats(),
        link.parameters(),
        link.debug_enabled()
    );
    (port.sent, state, most)
}

#[test]
fn aok_sends_the_same_bytes_under_every_split() {
    let mut bulk = Vec::new();
    for _ in 0..6 {
        bulk.extend([0x47, 0x00]); // bulk read: 112 bytes of reply each
    }
    let input: Vec<(u64, Vec<u8>)> = vec![
        (1, vec![0x67, 0x03]),       // read parameter 3
        (2, vec![0x00, 0x31, 0x67]), // noise, a motor-test start whose checksum fails
        (3, vec![0x0c]),
        (4, bulk),
        (30, vec![0x67]), // half a command, then silence: the idle rule drops it
        (150, vec![0x63, 0x01, 0x67, 0x04]),
    ];
    // 38 400 Bd is about 4 bytes a millisecond.
    for rate in [4, 1000] {
        let (reference, state, most) = run_aok(1, usize::MAX, rate, &input);
        assert!(most <= aok_link::RX_BUDGET);
        for rx_piece in rx_pieces() {
            for tx_piece in [1, 3, 64, usize::MAX] {
                let (sent, s, m) = run_aok(rx_piece, tx_piece, rate, &input);
                assert!(m <= aok_link::RX_BUDGET);
                assert_eq!(
                    s, state,
                    "reads of {rx_piece}, writes of {tx_piece}, {rate} B/ms"
                );
                assert!(
                    sent == reference,
                    "reads of {rx_piece}, writes of {tx_piece}: other bytes sent"
                );
            }
        }
        // The six bulk reads are all answered, none dropped, even at the line rate.
        assert!(state.contains("replies_dropped: 0"), "{state}");
    }
}

/// Runs the AYDP link for 100 ms; what it sent and its counters.
fn run_aydp(
    rx_piece: usize,
    tx_piece: usize,
    input: &[(u64, Vec<u8>)],
) -> (Vec<u8>, String, usize) {
    let mut port = SlicePort::new(rx_piece, tx_piece);
    let mut shared = Shared::new(Persisted::default(), 0);
    let mut link = AydpLink::new(0);
    let most = port.drive(100, input, None, |now, p| link.poll(now, p, &mut shared));
    let state = format!("{:?} {:?}", link.counters(), link.decoder_stats());
    (port.sent, state, most)
}

#[test]
fn aydp_sends_the_same_bytes_under_every_split() {
    // Expedited "request data" for the airspeed and for the link counters (which report the
    // decoder's counters as of before the request's last byte), with noise around them.
    let airspeed = [0xFF, 0x89, 0x0A, 0x00, 0x00, 0x00, 0x01, 0x10, 0x01, 0x6C];
    let mut counters = airspeed;
    counters[7] = 0x00; // address 0x0300, little-endian
    counters[8] = 0x03;
    counters[9] = counters[..9].iter().fold(0, |a, b| a ^ b);
    let mut stream = Vec::new();
    for i in 0..20u8 {
        stream.extend([i, 0xFF]);
        stream.extend(airspeed);
        stream.extend(counters);
    }
    let input: Vec<(u64, Vec<u8>)> = vec![(3, stream.clone()), (50, stream)];
    let (reference, state, most) = run_aydp(1, usize::MAX, &input);
    assert!(most <= aydp_link::RX_BUDGET);
    assert!(state.contains("requests_answered: 80"), "{state}");
    for rx_piece in rx_pieces() {
        for tx_piece in [1, 5, usize::MAX] {
            let (sent, s, m) = run_aydp(rx_piece, tx_piece, &input);
            assert!(m <= aydp_link::RX_BUDGET);
            assert_eq!(s, state, "reads of {rx_piece}, writes of {tx_piece}");
            assert!(
                sent == reference,
                "reads of {rx_piece}, writes of {tx_piece}: other bytes sent"
            );
        }
    }
}
