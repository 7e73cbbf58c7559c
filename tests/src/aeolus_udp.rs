//! The app's side of an AEOLUS box on UDP, for end-to-end tests of `protolink sim` and
//! `protolink bridge`: a socket that receives the box's datagrams (every frame decoded
//! strictly: a frame without a CRC or with a wrong one fails the test), and one that sends it
//! COMMAND and SETTIME datagrams.

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use aeolus_proto::message::{Message, Text};
use aeolus_proto::{CrcMode, decode_datagram};

/// One frame received from the box.
#[derive(Debug, Clone)]
pub struct Received {
    /// Message ID.
    pub id: u8,
    /// Message data (unescaped, without ID and CRC).
    pub data: Vec<u8>,
    /// Index of the datagram it came in.
    pub datagram: usize,
}

impl Received {
    /// The typed message, if it parses.
    pub fn message(&self) -> Option<Message<'_>> {
        Message::parse(self.id, &self.data).ok()
    }

    /// The text of a TOAST.
    pub fn toast(&self) -> Option<String> {
        match self.message()? {
            Message::Toast(t) => Some(String::from_utf8_lossy(t.as_bytes()).into_owned()),
            _ => None,
        }
    }
}

/// The app's two sockets and what it has received so far.
pub struct App {
    rx: UdpSocket,
    tx: UdpSocket,
    /// The box's in-port, where commands go (on 127.0.0.1).
    pub box_port: u16,
    /// Every frame received, in order.
    pub frames: Vec<Received>,
    /// Datagrams received.
    pub datagrams: usize,
}

impl App {
    /// Binds the receiving socket on an ephemeral port of 127.0.0.1 ([`App::port`] tells which);
    /// commands go to `box_port` on 127.0.0.1.
    pub fn new(box_port: u16) -> Self {
        let rx = UdpSocket::bind("127.0.0.1:0").expect("bind the app's socket");
        rx.set_read_timeout(Some(Duration::from_millis(20)))
            .expect("set a read timeout");
        App {
            rx,
            tx: UdpSocket::bind("127.0.0.1:0").expect("bind the sending socket"),
            box_port,
            frames: Vec::new(),
            datagrams: 0,
        }
    }

    /// The port the box must send to.
    pub fn port(&self) -> u16 {
        self.rx.local_addr().expect("bound").port()
    }

    /// Waits up to 20 ms for one datagram and decodes it.
    pub fn read_some(&mut self) {
        let mut buf = [0u8; 2048];
        if let Ok(n) = self.rx.recv(&mut buf) {
            for f in decode_datagram(&mut buf[..n], true) {
                let f = f.unwrap_or_else(|e| panic!("a bad frame from the box: {e:?}"));
                self.frames.push(Received {
                    id: f.id(),
                    data: f.data().to_vec(),
                    datagram: self.datagrams,
                });
            }
            self.datagrams += 1;
        }
    }

    /// Receives for `d`.
    pub fn read_for(&mut self, d: Duration) {
        let end = Instant::now() + d;
        while Instant::now() < end {
            self.read_some();
        }
    }

    /// Receives until a TOAST arrives (failing after `timeout`); its index in
    /// [`App::frames`].
    pub fn read_until_toast(&mut self, timeout: Duration) -> usize {
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

    /// Sends one message as a datagram to the box.
    pub fn send(&self, msg: &Message<'_>) {
        let mut buf = [0u8; 256];
        let n = msg.encode(&mut buf, CrcMode::Compute).expect("encode");
        self.tx
            .send_to(&buf[..n], ("127.0.0.1", self.box_port))
            .expect("send to the box");
    }

    /// Sends a COMMAND.
    pub fn command(&self, text: &str) {
        self.send(&Message::Command(Text::new(text).expect("a short command")));
    }
}
