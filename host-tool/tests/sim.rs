//! `protolink sim` end to end: the real binary sends to a plain UDP socket in the test, and the
//! test drives it with COMMAND and SETTIME datagrams on its in-port.

mod common;

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use aeolus_proto::message::{Message, SetTime, Text};
use aeolus_proto::{CrcMode, decode_datagram};
use common::*;

/// One received frame.
#[derive(Debug, Clone)]
struct Got {
    id: u8,
    data: Vec<u8>,
    /// Index of the datagram it came in.
    datagram: usize,
}

impl Got {
    fn toast(&self) -> Option<String> {
        match Message::parse(self.id, &self.data) {
            Ok(Message::Toast(t)) => Some(String::from_utf8_lossy(t.as_bytes()).into_owned()),
            _ => None,
        }
    }

    fn timestamp(&self) -> Option<f64> {
        Some(match Message::parse(self.id, &self.data).ok()? {
            Message::Gyro(m) => m.timestamp_ms,
            Message::Accel(m) => m.timestamp_ms,
            Message::Magnet(m) => m.timestamp_ms,
            Message::Attitude(m) => m.timestamp_ms,
            Message::Compass(m) => m.timestamp_ms,
            Message::Pressure(m) => m.timestamp_ms,
            Message::Gps(m) => m.timestamp_ms,
            Message::Temp(m) => m.timestamp_ms,
            Message::Wind(m) => m.timestamp_ms,
            _ => return None,
        })
    }
}

/// The test's side of the UDP link: a receiving socket, the frames so far (every one with a
/// good CRC, or the test fails), and a socket to send commands from.
struct Link {
    rx: UdpSocket,
    tx: UdpSocket,
    in_port: u16,
    frames: Vec<Got>,
    datagrams: usize,
}

impl Link {
    fn new() -> Self {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_millis(20)))
            .unwrap();
        Link {
            rx,
            tx: UdpSocket::bind("127.0.0.1:0").unwrap(),
            in_port: free_udp_port(),
            frames: Vec::new(),
            datagrams: 0,
        }
    }

    fn out_port(&self) -> String {
        self.rx.local_addr().unwrap().port().to_string()
    }

    fn read_some(&mut self) {
        let mut buf = [0u8; 2048];
        if let Ok(n) = self.rx.recv(&mut buf) {
            for f in decode_datagram(&mut buf[..n], true) {
                let f = f.unwrap_or_else(|e| panic!("a bad frame from the sim: {e:?}"));
                self.frames.push(Got {
                    id: f.id(),
                    data: f.data().to_vec(),
                    datagram: self.datagrams,
                });
            }
            self.datagrams += 1;
        }
    }

    fn read_for(&mut self, d: Duration) -> usize {
        let first = self.frames.len();
        let end = Instant::now() + d;
        while Instant::now() < end {
            self.read_some();
        }
        first
    }

    fn read_until_toast(&mut self, timeout: Duration) -> usize {
        let mut checked = self.frames.len();
        let end = Instant::now() + timeout;
        loop {
            if let Some(i) = self.frames[checked..]
                .iter()
                .position(|f| f.toast().is_some())
            {
                return checked + i;
            }
            checked = self.frames.len();
            assert!(Instant::now() < end, "no TOAST within {timeout:?}");
            self.read_some();
        }
    }

    fn send(&self, msg: &Message<'_>) {
        let mut buf = [0u8; 128];
        let n = msg.encode(&mut buf, CrcMode::Compute).unwrap();
        self.tx
            .send_to(&buf[..n], ("127.0.0.1", self.in_port))
            .unwrap();
    }

    fn command(&self, text: &str) {
        self.send(&Message::Command(Text::new(text).unwrap()));
    }
}

/// The spec's periodic messages (figure 1c): ID, name, interval in ms.
const PERIODIC: [(u8, &str, f64); 9] = [
    (62, "GYRO", 7.0),
    (63, "ACCEL", 7.0),
    (64, "MAGNET", 7.0),
    (71, "ATTITUDE", 7.0),
    (72, "COMPASS", 7.0),
    (61, "PRESSURE", 5.0),
    (66, "GPS", 92.0),
    (65, "TEMP", 829.0),
    (73, "WIND", 1000.0),
];

#[test]
fn sim_sends_every_type_at_the_spec_rates_and_obeys_commands() {
    let mut link = Link::new();
    let in_port = link.in_port.to_string();
    let out_port = link.out_port();
    let child = spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{out_port}"),
        "--udp-in",
        &in_port,
        "--seconds",
        "6",
    ]);

    // The boot TOAST first, then 2 s of telemetry, every frame with a good CRC.
    let first = link.read_until_toast(Duration::from_secs(5));
    assert_eq!(first, 0, "the boot TOAST comes first");
    assert_eq!(link.frames[0].toast().as_deref(), Some("AEOLUS on"));
    link.read_for(Duration::from_secs(2));
    for (id, name, interval) in PERIODIC {
        let ts: Vec<f64> = link
            .frames
            .iter()
            .filter(|f| f.id == id)
            .filter_map(Got::timestamp)
            .collect();
        assert!(!ts.is_empty(), "no {name} in 2 s");
        if ts.len() >= 3 {
            // The firmware's drift-free schedule: the mean interval is the spec's, within 2 %.
            let mean = (ts[ts.len() - 1] - ts[0]) / (ts.len() - 1) as f64;
            assert!(
                (mean - interval).abs() <= 0.02 * interval,
                "{name}: mean interval {mean} ms, spec {interval} ms"
            );
        }
    }
    assert!(link.frames.iter().any(|f| f.id == 51), "no AEOLUSINFO");
    // One frame per datagram by default.
    assert_eq!(link.datagrams, link.frames.len());

    // SETTIME, then "a pause": the answer, then silence.
    link.send(&Message::SetTime(SetTime {
        year_since_1900: 126,
        month0: 10,
        day: 21,
        hour: 12,
        minute: 0,
        second: 0,
    }));
    link.command("a pause");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS paused"));
    link.read_for(Duration::from_millis(400));
    assert_eq!(link.frames.len(), ack + 1, "telemetry while paused");

    // "a resume": the answer, then telemetry again.
    link.command("a resume");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS resumed"));
    link.read_for(Duration::from_millis(300));
    let after = link.frames.len() - ack - 1;
    assert!(
        after >= 40,
        "only {after} frames in 300 ms after the resume"
    );

    // An unknown command is answered; "a reboot" restarts the box with its boot TOAST.
    link.command("a hello");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(
        link.frames[ack].toast().as_deref(),
        Some("unknown command: a hello")
    );
    link.command("a reboot");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(
        link.frames[ack].toast().as_deref(),
        Some("AEOLUS rebooting")
    );
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS on"));

    // The counters on exit: every datagram it received was acted on.
    let out = ok(&finish(child));
    let summary = out.lines().find(|l| l.starts_with("sim: ")).unwrap();
    for want in [
        "settime=1 ",
        "commands=3 ",
        "unknown_commands=1 ",
        "reboots=1 ",
        "rx_errors=0 ",
        "send_errors=0 ",
        "datagrams_received=5",
    ] {
        assert!(summary.contains(want), "{want} not in {summary}");
    }
}

#[test]
fn sim_packs_frames_into_datagrams() {
    let mut link = Link::new();
    let in_port = link.in_port.to_string();
    let out_port = link.out_port();
    let child = spawn(&[
        "sim",
        "--udp-out",
        &out_port,
        "--udp-in",
        &in_port,
        "--pack",
        "4",
        "--seconds",
        "1.5",
    ]);
    link.read_for(Duration::from_millis(1200));
    let out = ok(&finish(child));
    let mut per_datagram = vec![0usize; link.datagrams];
    for f in &link.frames {
        per_datagram[f.datagram] += 1;
    }
    assert!(link.frames.len() > 300, "{} frames", link.frames.len());
    assert!(per_datagram.iter().all(|&n| (1..=4).contains(&n)));
    assert!(
        per_datagram.iter().filter(|&&n| n == 4).count() > per_datagram.len() / 2,
        "most datagrams are full packs: {per_datagram:?}"
    );
    assert!(out.contains("send_errors=0"));
}

#[test]
fn sim_refuses_an_impossible_flight_in_one_sentence() {
    let err = failed(&run(&["sim", "--airspeed", "500", "--seconds", "1"]));
    assert!(
        err.contains("error: cannot simulate that flight: airspeed out of range"),
        "{err}"
    );
    let err = failed(&run(&["sim", "--bank", "-75", "--seconds", "1"]));
    assert!(err.contains("bank angle out of range"), "{err}");
}
