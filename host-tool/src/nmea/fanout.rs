//! Lines to many readers without letting one hold up the rest: a TCP server whose every
//! client has its own bounded queue, or a UDP sender (one datagram per line).
//!
//! Everything is bounded: at most [`MAX_CLIENTS`] clients, at most [`MAX_PER_PEER`] of them
//! from one address, at most [`QUEUE_BYTES`] queued for each. A client from an address at its
//! limit is accepted and closed at once, counted as refused. When every place is taken, a
//! client from an address that holds fewer takes the place of the oldest client of the address
//! that holds the most (counted as replaced), if that address would still hold more; otherwise
//! it is refused. So no other address can hold the user's place, whether its clients read or
//! not. A client that reads
//! too slowly loses whole lines, never parts of one: a line that does not fit its queue is
//! dropped for that client alone and counted. Sockets are non-blocking, so no client can stall
//! the loop or the others.
//!
//! A client that stays behind is let go, so clients that connect and never read cannot hold
//! every place. It is behind once it holds [`UNREAD_LIMIT`] bytes it has not read, as far as
//! its system tells (on Linux, from the window it advertises: [`super::window`]), once its
//! socket takes no more bytes, or once a line is dropped for it; it then has [`STALL_LIMIT`] to
//! catch up (less unread and its queue drained empty) before it is closed, counted as evicted
//! and noted. A client whose receive buffer is set is behind about 16 s after it stops reading
//! at the `xcsoar` rate (its window shows a little over half of what it holds), and let go
//! [`STALL_LIMIT`] later; one whose system widens its buffer with what it holds (Linux's automatic
//! sizing) shows nothing to a sender for hours, and the shares per address keep the user's
//! place from it. Each client's kernel send buffer is kept small ([`SEND_BUFFER`]), so a
//! refused write comes soon after its window shuts rather than after the megabytes an
//! automatically sized send buffer would hold. On Linux a peer that stops acknowledging
//! altogether (a tablet asleep, a cable pulled) is dropped by the system after [`STALL_LIMIT`]
//! of unacknowledged data (`TCP_USER_TIMEOUT`).

use std::collections::VecDeque;
use std::io::{self, Read as _, Write as _};
use std::net::{SocketAddr, TcpListener, TcpStream, UdpSocket};
use std::time::{Duration, Instant};

use super::window::Unread;
use crate::endpoint::udp_out::{Sends, bind_for};
use crate::error::{Error, Result};

/// Most clients served at once.
pub(crate) const MAX_CLIENTS: usize = 8;
/// Most clients from one address at once (a tablet running a glide computer, a moving map and
/// a logger).
pub(crate) const MAX_PER_PEER: usize = 3;
/// Bytes queued for one client at most (about 200 sentences: several seconds of output).
pub(crate) const QUEUE_BYTES: usize = 16 * 1024;
/// Bytes read (and discarded) from one client per turn: what a client sends is not used.
const READ_PER_TURN: usize = 4096;
/// How long a client may stay behind (its socket full, or lines dropped for it) before it is
/// let go.
pub(crate) const STALL_LIMIT: Duration = Duration::from_secs(15);
/// Bytes a client may hold unread, as its window shows it, before it is behind: about 7 KB of
/// sentences (16 s of the `xcsoar` set) for a client that reads nothing, while a client that
/// reads holds at most what arrived since its last read.
pub(crate) const UNREAD_LIMIT: u32 = 4 * 1024;
/// The kernel send buffer asked for each client's socket, bytes (Linux doubles it).
pub(crate) const SEND_BUFFER: usize = 4096;

/// What a [`Fanout`] has done.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub(crate) struct Counters {
    /// Lines handed to [`Fanout::send`].
    pub(crate) lines: u64,
    /// Clients accepted (TCP).
    pub(crate) clients: u64,
    /// Clients turned away: their address held [`MAX_PER_PEER`], or every place was held by
    /// addresses with no more than their share (TCP).
    pub(crate) refused: u64,
    /// Clients closed to give their place to a client from an address holding fewer (also
    /// counted as disconnected).
    pub(crate) replaced: u64,
    /// Clients gone (closed by them, a write failed, or evicted).
    pub(crate) disconnected: u64,
    /// Clients let go after [`STALL_LIMIT`] behind (also counted as disconnected).
    pub(crate) evicted: u64,
    /// Lines dropped for a client whose queue was full, summed over the clients.
    pub(crate) dropped: u64,
    /// Datagrams whose send failed (UDP).
    pub(crate) send_errors: u64,
}

/// One TCP client and the bytes waiting for it.
#[derive(Debug)]
struct Client {
    stream: TcpStream,
    peer: SocketAddr,
    queue: VecDeque<u8>,
    dropped: u64,
    /// What it holds unread, from its window.
    unread: Unread,
    /// The bytes it held unread at the last turn (0 where not known).
    unread_now: u32,
    /// Since when it is behind: it held [`UNREAD_LIMIT`] unread, its socket took no more, or a
    /// line was dropped for it; until it holds less and its queue drains empty.
    behind_since: Option<Instant>,
}

/// Why a client is let go.
enum Gone {
    /// It closed, or a read or write failed.
    Left,
    /// It stayed behind for the stall limit.
    Evicted,
}

/// Where the lines go.
#[derive(Debug)]
enum Sink {
    Tcp {
        listener: TcpListener,
        clients: Vec<Client>,
    },
    Udp {
        socket: UdpSocket,
        to: SocketAddr,
    },
}

/// A TCP server or a UDP sender for lines.
#[derive(Debug)]
pub(crate) struct Fanout {
    sink: Sink,
    counters: Counters,
    /// The datagrams' outcome (UDP).
    sends: Sends,
    stall_limit: Duration,
}

impl Fanout {
    /// A TCP server on `addr`, non-blocking.
    ///
    /// # Errors
    /// The address cannot be bound.
    pub(crate) fn listen(addr: SocketAddr) -> Result<Self> {
        let open_err = |source| Error::Open {
            endpoint: format!("a TCP server on {addr}"),
            source,
        };
        let listener = TcpListener::bind(addr).map_err(open_err)?;
        listener.set_nonblocking(true).map_err(open_err)?;
        Ok(Self::with(Sink::Tcp {
            listener,
            clients: Vec::new(),
        }))
    }

    /// A UDP sender to `to`, from an ephemeral port of its family, on the loopback address
    /// for a loopback destination (every interface otherwise): [`bind_for`].
    ///
    /// # Errors
    /// No socket can be bound.
    pub(crate) fn udp(to: SocketAddr) -> Result<Self> {
        let socket = bind_for(to, false)?;
        Ok(Self::with(Sink::Udp { socket, to }))
    }

    fn with(sink: Sink) -> Self {
        Fanout {
            sink,
            counters: Counters::default(),
            sends: Sends::default(),
            stall_limit: STALL_LIMIT,
        }
    }

    /// The same with another stall limit than [`STALL_LIMIT`] (a test's short one).
    #[cfg(test)]
    pub(crate) fn with_stall_limit(mut self, limit: Duration) -> Self {
        self.stall_limit = limit;
        self
    }

    /// The server's address (TCP), or where the datagrams go (UDP).
    ///
    /// # Errors
    /// The operating system cannot tell the bound address.
    pub(crate) fn local_addr(&self) -> io::Result<SocketAddr> {
        match &self.sink {
            Sink::Tcp { listener, .. } => listener.local_addr(),
            Sink::Udp { to, .. } => Ok(*to),
        }
    }

    /// What has been done so far.
    pub(crate) fn counters(&self) -> Counters {
        self.counters
    }

    /// Queues `line` for every client (TCP) or sends it as one datagram (UDP).
    pub(crate) fn send(&mut self, line: &[u8]) {
        self.counters.lines += 1;
        match &mut self.sink {
            Sink::Tcp { clients, .. } => {
                for c in clients {
                    if c.queue.len() + line.len() <= QUEUE_BYTES {
                        c.queue.extend(line);
                    } else {
                        c.dropped += 1;
                        self.counters.dropped += 1;
                        c.behind_since.get_or_insert_with(Instant::now);
                    }
                }
            }
            Sink::Udp { socket, to } => {
                if !self.sends.count(socket.send_to(line, *to)) {
                    self.counters.send_errors += 1;
                }
            }
        }
    }

    /// One turn of the server: accepts waiting clients, writes what each can take, reads and
    /// discards what they sent, and lets go of the ones that left. `note` gets one sentence
    /// for each client that comes or goes.
    pub(crate) fn poll(&mut self, mut note: impl FnMut(&str)) {
        let Sink::Tcp { listener, clients } = &mut self.sink else {
            return;
        };
        while let Ok((stream, peer)) = listener.accept() {
            let place = match place_for(clients, peer) {
                Ok(place) => place,
                Err(why) => {
                    self.counters.refused += 1;
                    note(&format!("refused {peer}: {why}"));
                    continue;
                }
            };
            if stream.set_nonblocking(true).is_err() {
                self.counters.refused += 1;
                note(&format!(
                    "refused {peer}: its socket cannot be made non-blocking"
                ));
                continue;
            }
            if let Some(at) = place {
                let old = clients.remove(at);
                self.counters.replaced += 1;
                self.counters.disconnected += 1;
                note(&format!(
                    "closed {} to make room for {peer}: its address held the most clients ({} lines dropped for it)",
                    old.peer, old.dropped
                ));
            }
            // A small kernel buffer: a client that reads nothing is seen behind sooner. Where
            // the option cannot be set, the client is served with the system's buffer.
            let sock = socket2::SockRef::from(&stream);
            let _ = sock.set_send_buffer_size(SEND_BUFFER);
            // A peer that stops acknowledging (a tablet asleep, a cable pulled) is dropped by
            // the system once data has waited unacknowledged this long.
            #[cfg(target_os = "linux")]
            let _ = sock.set_tcp_user_timeout(Some(STALL_LIMIT));
            self.counters.clients += 1;
            note(&format!("client {peer} connected"));
            clients.push(Client {
                stream,
                peer,
                queue: VecDeque::with_capacity(QUEUE_BYTES),
                dropped: 0,
                unread: Unread::default(),
                unread_now: 0,
                behind_since: None,
            });
        }
        let before = clients.len();
        let (limit, counters) = (self.stall_limit, &mut self.counters);
        clients.retain_mut(|c| match c.serve(limit) {
            Ok(()) => true,
            Err(Gone::Left) => {
                note(&format!(
                    "client {} left ({} lines dropped for it)",
                    c.peer, c.dropped
                ));
                false
            }
            Err(Gone::Evicted) => {
                counters.evicted += 1;
                note(&format!(
                    "evicted {}: behind for {} s, reading too little or nothing ({} bytes unread, {} lines dropped for it)",
                    c.peer,
                    limit.as_secs_f64(),
                    c.unread_now,
                    c.dropped
                ));
                false
            }
        });
        self.counters.disconnected += (before - clients.len()) as u64;
    }

    /// Fails when lines were to go out as datagrams and not one did ([`Sends::check`], the
    /// rule of every command that sends).
    ///
    /// # Errors
    /// [`Error::Io`] with the last send error.
    pub(crate) fn check(&mut self) -> Result<()> {
        let to = self
            .local_addr()
            .map_or_else(|_| "?".to_owned(), |a| a.to_string());
        self.sends.check(to)
    }
}

/// Where a new client from `peer` goes among `clients`: `Ok(None)` a free place, `Ok(Some(i))`
/// the place of client `i` (the oldest of the address holding the most, when every place is
/// taken and that address would still hold more than `peer`), or the reason it is refused.
fn place_for(clients: &[Client], peer: SocketAddr) -> std::result::Result<Option<usize>, String> {
    let held = |ip| clients.iter().filter(|c| c.peer.ip() == ip).count();
    let mine = held(peer.ip());
    if mine >= MAX_PER_PEER {
        return Err(format!("its address has {MAX_PER_PEER} clients connected"));
    }
    if clients.len() < MAX_CLIENTS {
        return Ok(None);
    }
    let crowded = clients
        .iter()
        .map(|c| c.peer.ip())
        .max_by_key(|&ip| held(ip));
    match crowded {
        Some(ip) if held(ip) > mine + 1 => Ok(clients.iter().position(|c| c.peer.ip() == ip)),
        _ => Err(format!(
            "{MAX_CLIENTS} clients are connected, no address more than its share"
        )),
    }
}

impl Client {
    /// Writes what the socket takes and reads what the client sent; an error once it is gone
    /// or has been behind for `limit`.
    fn serve(&mut self, limit: Duration) -> std::result::Result<(), Gone> {
        while !self.queue.is_empty() {
            let (head, _) = self.queue.as_slices();
            match self.stream.write(head) {
                Ok(0) => return Err(Gone::Left),
                Ok(n) => {
                    self.queue.drain(..n);
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    self.behind_since.get_or_insert_with(Instant::now);
                    break;
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(_) => return Err(Gone::Left),
            }
        }
        self.unread_now = self.unread.update(&self.stream).unwrap_or(0);
        let holding = self.unread_now >= UNREAD_LIMIT;
        if holding {
            self.behind_since.get_or_insert_with(Instant::now);
        } else if self.queue.is_empty() {
            self.behind_since = None;
        }
        if self.behind_since.is_some_and(|t| t.elapsed() >= limit) {
            return Err(Gone::Evicted);
        }
        let mut buf = [0u8; 512];
        let mut read = 0;
        while read < READ_PER_TURN {
            match self.stream.read(&mut buf) {
                Ok(0) => return Err(Gone::Left),
                Ok(n) => read += n,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(_) => return Err(Gone::Left),
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A client connected from `from` (an address of 127/8: another machine to the server).
    fn connect_from(from: [u8; 4], to: SocketAddr) -> TcpStream {
        use socket2::{Domain, Socket, Type};
        let s = Socket::new(Domain::IPV4, Type::STREAM, None).unwrap();
        s.bind(&SocketAddr::from((from, 0)).into()).unwrap();
        s.connect(&to.into()).unwrap();
        s.into()
    }

    /// Polls until `done` or 5 s.
    fn poll_until(out: &mut Fanout, notes: &mut Vec<String>, done: impl Fn(Counters) -> bool) {
        let started = Instant::now();
        while !done(out.counters()) && started.elapsed() < Duration::from_secs(5) {
            out.poll(|n| notes.push(n.to_owned()));
        }
    }

    /// A server on 127.0.0.1 with the stall limit `limit`, its address, and a client.
    fn server_with_reader(limit: Duration) -> (Fanout, SocketAddr, TcpStream) {
        let out = Fanout::listen("127.0.0.1:0".parse().unwrap())
            .unwrap()
            .with_stall_limit(limit);
        let addr = out.local_addr().unwrap();
        let reader = TcpStream::connect(addr).unwrap();
        (out, addr, reader)
    }

    /// Reads everything `reader` is sent on a thread of its own, until it is closed or nothing
    /// comes for `quiet`; the thread's result is the count of bytes.
    fn read_all_in_background(
        mut reader: TcpStream,
        quiet: Duration,
    ) -> std::thread::JoinHandle<u64> {
        std::thread::spawn(move || {
            let mut buf = [0u8; 65536];
            let mut total = 0u64;
            reader.set_read_timeout(Some(quiet)).unwrap();
            while let Ok(n) = reader.read(&mut buf) {
                if n == 0 {
                    break;
                }
                total += n as u64;
            }
            total
        })
    }

    fn accept_one(out: &mut Fanout) {
        let started = Instant::now();
        while out.counters().clients == 0 && started.elapsed() < Duration::from_secs(5) {
            out.poll(|_| {});
        }
    }

    #[test]
    fn a_client_that_never_reads_loses_lines_and_holds_no_one_up() {
        let mut out = Fanout::listen("127.0.0.1:0".parse().unwrap()).unwrap();
        let addr = out.local_addr().unwrap();
        let _slow = TcpStream::connect(addr).unwrap();
        accept_one(&mut out);
        let mut fast = TcpStream::connect(addr).unwrap();
        fast.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        while out.counters().clients < 2 {
            out.poll(|_| {});
        }
        let line = [b'x'; 80];
        let mut got = vec![0u8; 80];
        // Until the slow client's socket buffers and queue are full (the loopback buffers
        // may hold megabytes), and a while longer: the fast one gets every line meanwhile.
        let mut sent = 0u64;
        while out.counters().dropped < 100 && sent < 2_000_000 {
            out.send(&line);
            out.poll(|_| {});
            fast.read_exact(&mut got).unwrap();
            assert_eq!(got, line);
            sent += 1;
        }
        let c = out.counters();
        assert_eq!(c.dropped, 100, "{c:?}");
        assert_eq!(c.disconnected, 0);
    }

    /// 80-byte lines, 5 every 10 ms, to a reader and to a client with a 64 KiB receive buffer
    /// (`SO_RCVBUF`) that reads nothing: the silent one is found by what it leaves unread and
    /// let go after the stall limit, long before a write to it would be refused; the reader
    /// gets every line and stays. Beyond Linux the window is not known.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_client_that_reads_nothing_is_found_by_what_it_leaves_unread() {
        let limit = Duration::from_millis(500);
        let (mut out, addr, reader) = server_with_reader(limit);
        let _silent = super::super::window::tests::connect_with_buffer([127, 0, 1, 1], addr);
        let mut notes = Vec::new();
        poll_until(&mut out, &mut notes, |c| c.clients == 2);
        let drain = read_all_in_background(reader, Duration::from_secs(1));
        let line = [b'x'; 80];
        let mut lines = 0u64;
        // At most 100 KB: less than the silent client's buffer and the server's hold (a write
        // to it was refused after 140 KB), so no write to it is ever refused.
        while out.counters().evicted == 0 && lines < 1_250 {
            for _ in 0..5 {
                out.send(&line);
            }
            out.poll(|n| notes.push(n.to_owned()));
            lines += 5;
            std::thread::sleep(Duration::from_millis(10));
        }
        println!(
            "found after {lines} lines ({} bytes): {notes:?}",
            lines * 80
        );
        let c = out.counters();
        assert_eq!(c.evicted, 1, "{c:?} {notes:?}");
        assert_eq!((c.disconnected, c.dropped), (1, 0), "{c:?}");
        let evicted = notes.iter().find(|n| n.starts_with("evicted 127.0.1.1:"));
        assert!(
            evicted.is_some_and(|n| n.contains(" bytes unread")),
            "{notes:?}"
        );
        // Found after 4 KiB unread and the stall limit (20 KB at this rate): about 40 KB.
        assert!(
            lines * 80 < 64 * 1024,
            "{lines} lines sent before it was found"
        );
        drop(out);
        assert_eq!(
            drain.join().unwrap(),
            lines * 80,
            "the reader got every line"
        );
    }

    /// Eight clients that connect and never read hold every place; once they are behind for
    /// the stall limit they are let go, counted and noted, and a ninth client gets a place and
    /// every line, while a client that reads is never let go.
    #[test]
    fn clients_that_read_nothing_are_evicted_and_a_new_one_gets_their_place() {
        let limit = Duration::from_millis(500);
        let (mut out, addr, reader) = server_with_reader(limit);
        let silent: Vec<TcpStream> = (0..MAX_CLIENTS - 1)
            .map(|n| connect_from([127, 0, 1, n as u8], addr))
            .collect();
        let started = Instant::now();
        while out.counters().clients < MAX_CLIENTS as u64
            && started.elapsed() < Duration::from_secs(5)
        {
            out.poll(|_| {});
        }
        assert_eq!(out.counters().clients, MAX_CLIENTS as u64);
        // A ninth, from an address of its own, is refused while the eight are connected.
        let _early = connect_from([127, 0, 2, 1], addr);
        while out.counters().refused == 0 && started.elapsed() < Duration::from_secs(5) {
            out.poll(|_| {});
        }
        assert_eq!(out.counters().refused, 1);
        let drain = read_all_in_background(reader, Duration::from_secs(3));
        // Lines as fast as the loop goes, until the seven silent clients are let go.
        let line = [b'x'; 80];
        let mut notes = Vec::new();
        let started = Instant::now();
        while out.counters().evicted < silent.len() as u64
            && started.elapsed() < Duration::from_secs(20)
        {
            out.send(&line);
            out.poll(|n| notes.push(n.to_owned()));
            std::thread::sleep(Duration::from_micros(200));
        }
        let c = out.counters();
        assert_eq!(c.evicted, silent.len() as u64, "{c:?} {notes:?}");
        assert_eq!(c.disconnected, c.evicted, "the reading client stays: {c:?}");
        assert!(
            notes.iter().any(|n| n.starts_with("evicted 127.0.1.")),
            "{notes:?}"
        );
        // Their places are free: a new client is served.
        let mut ninth = TcpStream::connect(addr).unwrap();
        ninth
            .set_read_timeout(Some(Duration::from_secs(5)))
            .unwrap();
        while out.counters().clients < MAX_CLIENTS as u64 + 1 {
            out.poll(|_| {});
        }
        out.send(b"$PGRMZ,2282,f,2*20\r\n");
        out.poll(|_| {});
        let mut got = [0u8; 20];
        ninth.read_exact(&mut got).unwrap();
        assert_eq!(&got, b"$PGRMZ,2282,f,2*20\r\n");
        drop(out);
        assert!(drain.join().unwrap() > 0);
        drop(silent);
    }

    #[test]
    fn clients_beyond_the_limit_are_refused_and_a_closed_one_is_let_go() {
        let mut out = Fanout::listen("127.0.0.1:0".parse().unwrap()).unwrap();
        let addr = out.local_addr().unwrap();
        let mut streams: Vec<TcpStream> = (0..MAX_CLIENTS + 2)
            .map(|n| connect_from([127, 0, 1, n as u8], addr))
            .collect();
        let started = Instant::now();
        while out.counters().clients + out.counters().refused < (MAX_CLIENTS + 2) as u64
            && started.elapsed() < Duration::from_secs(5)
        {
            out.poll(|_| {});
        }
        assert_eq!(out.counters().clients, MAX_CLIENTS as u64);
        assert_eq!(out.counters().refused, 2);
        streams.truncate(MAX_CLIENTS - 1);
        let started = Instant::now();
        while out.counters().disconnected < 1 && started.elapsed() < Duration::from_secs(5) {
            out.send(b"line\r\n");
            out.poll(|_| {});
        }
        assert_eq!(out.counters().disconnected, 1, "the one closed client");
    }

    /// One address holds at most its share: its fourth client is refused, and when every place
    /// is taken the user's client takes the place of the crowded address's oldest, whether
    /// that one reads or not, and gets every line.
    #[test]
    fn another_address_cannot_hold_the_users_place() {
        let mut out = Fanout::listen("127.0.0.1:0".parse().unwrap()).unwrap();
        let addr = out.local_addr().unwrap();
        let mut notes = Vec::new();
        let crowd: Vec<_> = (0..MAX_PER_PEER + 1)
            .map(|_| connect_from([127, 0, 0, 2], addr))
            .collect();
        poll_until(&mut out, &mut notes, |c| {
            c.clients + c.refused == crowd.len() as u64
        });
        let c = out.counters();
        assert_eq!(
            (c.clients, c.refused),
            (MAX_PER_PEER as u64, 1),
            "{notes:?}"
        );
        assert!(
            notes.iter().any(|n| n.starts_with("refused 127.0.0.2:")),
            "{notes:?}"
        );
        // Every place taken: 3 + 3 + 2 clients from three other addresses.
        let more: Vec<_> = [3, 3, 3, 4, 4]
            .iter()
            .map(|&n| connect_from([127, 0, 0, n], addr))
            .collect();
        poll_until(&mut out, &mut notes, |c| c.clients == MAX_CLIENTS as u64);
        assert_eq!(out.counters().clients, MAX_CLIENTS as u64);
        let mut user = connect_from([127, 0, 0, 1], addr);
        user.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        poll_until(&mut out, &mut notes, |c| c.replaced == 1);
        let c = out.counters();
        assert_eq!(
            (c.replaced, c.refused, c.disconnected),
            (1, 1, 1),
            "{notes:?}"
        );
        assert!(
            notes
                .iter()
                .any(|n| n.starts_with("closed 127.0.0.2:") || n.starts_with("closed 127.0.0.3:")),
            "{notes:?}"
        );
        out.send(b"$PGRMZ,2282,f,2*20\r\n");
        out.poll(|_| {});
        let mut got = [0u8; 20];
        user.read_exact(&mut got).unwrap();
        assert_eq!(&got, b"$PGRMZ,2282,f,2*20\r\n");
        // Another new address takes the place of the most crowded address's oldest client; then
        // a second client of the user's would only swap shares, and is refused.
        let _fifth = connect_from([127, 0, 0, 5], addr);
        poll_until(&mut out, &mut notes, |c| c.replaced == 2);
        assert_eq!(out.counters().replaced, 2, "{notes:?}");
        let _second = connect_from([127, 0, 0, 1], addr);
        poll_until(&mut out, &mut notes, |c| c.refused == 2);
        let c = out.counters();
        assert_eq!((c.replaced, c.refused, c.clients), (2, 2, 10), "{notes:?}");
        drop((crowd, more));
    }
}

/// The examples of this module's items, as tests (the items are crate-private, so rustdoc
/// does not run them).
#[cfg(test)]
#[allow(unused_imports, clippy::unnecessary_wraps)]
mod examples {
    use super::*;

    #[test]
    fn fanout_example() -> Result<(), Box<dyn std::error::Error>> {
        use std::io::Read;
        let mut out = Fanout::listen("127.0.0.1:0".parse()?)?;
        let mut client = std::net::TcpStream::connect(out.local_addr()?)?;
        while out.counters().clients == 0 {
            out.poll(|_| {});
        }
        out.send(b"$PGRMZ,2282,f,2*20\r\n");
        out.poll(|_| {});
        let mut line = [0u8; 20];
        client.read_exact(&mut line)?;
        assert_eq!(&line, b"$PGRMZ,2282,f,2*20\r\n");
        Ok(())
    }
}
