//! The HTTP side of `protolink web`: a small read-only server on `std::net`, one thread per
//! connection, every resource bounded. What it streams comes from the [`Hub`].
//!
//! * The decoder publishes one snapshot per display frame into a [`Hub`], which holds only the
//!   latest (a sequence number and its JSON): never a queue. Each live-update stream
//!   (server-sent events, `GET /events`) sends the newest snapshot whenever it is ready for
//!   one; the snapshots it skipped are counted as dropped. So a slow client costs the decoder
//!   and the other clients nothing.
//! * At most [`MAX_STREAMS`] live-update streams and [`MAX_CONNECTIONS`] connections in all;
//!   more are answered `503` and counted.
//! * A request head is at most [`MAX_HEAD`] bytes with at most [`MAX_HEADERS`] headers
//!   (`431` otherwise), parsed by `httparse`; it must arrive within [`READ_TIMEOUT`]. A write
//!   that cannot go out within [`WRITE_TIMEOUT`] ends the connection.
//! * Only `GET` and `HEAD` (`405` otherwise); every response closes its connection.
//! * Bound to a loopback address, it answers only requests whose `Host` is an address or
//!   `localhost` (`421` otherwise), so a web page that points its own name at 127.0.0.1 (DNS
//!   rebinding) cannot read the state.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread;
use std::time::Duration;

use super::assets;
use super::hub::Hub;
use super::state::ServerState;
use crate::error::{Error, Result};

/// The most live-update streams served at once.
pub const MAX_STREAMS: u64 = 8;
/// The most connections served at once (streams included).
pub const MAX_CONNECTIONS: u64 = 24;
/// The longest request head (request line and headers) accepted, bytes.
pub const MAX_HEAD: usize = 8 * 1024;
/// The most headers accepted in one request.
pub const MAX_HEADERS: usize = 32;
/// How long a client has to send its request head.
pub const READ_TIMEOUT: Duration = Duration::from_secs(5);
/// How long one write to a client may take before the connection is given up.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// A stream with nothing new sends a comment this often (so a gone client is noticed).
pub const KEEPALIVE: Duration = Duration::from_secs(1);

/// The server's counters (shown on the page and in `/api/state`).
#[derive(Debug, Default)]
pub struct Counters {
    connections: AtomicU64,
    streams: AtomicU64,
    refused: AtomicU64,
    bad_requests: AtomicU64,
    frames_sent: AtomicU64,
    frames_dropped: AtomicU64,
}

impl Counters {
    /// A copy for the state.
    pub fn state(&self) -> ServerState {
        ServerState {
            clients: self.streams.load(Ordering::Relaxed),
            refused: self.refused.load(Ordering::Relaxed),
            bad_requests: self.bad_requests.load(Ordering::Relaxed),
            frames_sent: self.frames_sent.load(Ordering::Relaxed),
            frames_dropped: self.frames_dropped.load(Ordering::Relaxed),
        }
    }
}

/// Takes one of `limit` slots of `counter`, or `None` when all are taken; the slot is given
/// back when the guard drops.
struct Slot<'a>(&'a AtomicU64);

impl<'a> Slot<'a> {
    fn take(counter: &'a AtomicU64, limit: u64) -> Option<Self> {
        counter
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
                (n < limit).then_some(n + 1)
            })
            .ok()
            .map(|_| Slot(counter))
    }
}

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A running server: the listening socket's address, the hub and the counters.
#[derive(Debug)]
pub struct Server {
    addr: SocketAddr,
    hub: Arc<Hub>,
    counters: Arc<Counters>,
    stop: Arc<AtomicBool>,
}

impl Server {
    /// Binds `addr` and starts accepting connections on a thread of its own.
    ///
    /// # Errors
    /// [`Error::Open`] when the address cannot be bound (in use, not this machine's).
    pub fn start(addr: SocketAddr) -> Result<Server> {
        let open_err = |source| Error::Open {
            endpoint: format!("http://{addr}/"),
            source,
        };
        let listener = TcpListener::bind(addr).map_err(open_err)?;
        let addr = listener.local_addr().map_err(open_err)?;
        listener.set_nonblocking(true).map_err(open_err)?;
        let loopback = addr.ip().is_loopback();
        let server = Server {
            addr,
            hub: Arc::new(Hub::default()),
            counters: Arc::new(Counters::default()),
            stop: Arc::new(AtomicBool::new(false)),
        };
        let (hub, counters, stop) = (
            server.hub.clone(),
            server.counters.clone(),
            server.stop.clone(),
        );
        thread::Builder::new()
            .name("web-accept".into())
            .spawn(move || accept_loop(&listener, loopback, &hub, &counters, &stop))
            .map_err(|source| Error::Io {
                what: "starting the web server".into(),
                source,
            })?;
        Ok(server)
    }

    /// The address it listens on (the real port when `:0` was asked for).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Where the decoder publishes snapshots.
    pub fn hub(&self) -> &Hub {
        &self.hub
    }

    /// The counters as the state shows them.
    pub fn counters(&self) -> ServerState {
        self.counters.state()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        self.hub.close();
    }
}

fn accept_loop(
    listener: &TcpListener,
    loopback: bool,
    hub: &Arc<Hub>,
    counters: &Arc<Counters>,
    stop: &AtomicBool,
) {
    while !stop.load(Ordering::SeqCst) {
        match listener.accept() {
            Ok((mut stream, _)) => {
                let _ = stream.set_nonblocking(false);
                let Some(conn) = Connection::take(counters) else {
                    counters.refused.fetch_add(1, Ordering::Relaxed);
                    // A few bytes into a fresh socket's buffer: never blocks for long.
                    let _ = stream.set_write_timeout(Some(Duration::from_millis(100)));
                    let _ = respond(
                        &mut stream,
                        false,
                        "503 Service Unavailable",
                        "text/plain; charset=utf-8",
                        b"too many connections",
                    );
                    continue;
                };
                let hub = hub.clone();
                // If the thread cannot start, the closure (and with it the slot) is dropped.
                let _ = thread::Builder::new()
                    .name("web-conn".into())
                    .spawn(move || serve(stream, loopback, &hub, &conn.0));
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                thread::sleep(Duration::from_millis(20));
            }
            // A connection that failed before it was accepted (reset, out of descriptors):
            // wait a little and go on.
            Err(_) => thread::sleep(Duration::from_millis(20)),
        }
    }
}

/// One of [`MAX_CONNECTIONS`] connection slots, given back when dropped.
struct Connection(Arc<Counters>);

impl Connection {
    fn take(counters: &Arc<Counters>) -> Option<Self> {
        Slot::take(&counters.connections, MAX_CONNECTIONS).map(|slot| {
            std::mem::forget(slot);
            Connection(counters.clone())
        })
    }
}

impl Drop for Connection {
    fn drop(&mut self) {
        self.0.connections.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A response without a body beyond `body`.
fn respond(
    stream: &mut impl Write,
    head_only: bool,
    status: &str,
    content_type: &str,
    body: &[u8],
) -> std::io::Result<()> {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes())?;
    if !head_only {
        stream.write_all(body)?;
    }
    stream.flush()
}

/// Reads the request head: up to and including the blank line, at most [`MAX_HEAD`] bytes,
/// all within [`READ_TIMEOUT`]. `Ok(None)` when it is too long.
fn read_head(stream: &mut TcpStream) -> std::io::Result<Option<Vec<u8>>> {
    let started = std::time::Instant::now();
    let mut head = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        // The whole head within READ_TIMEOUT, not each read: a client that trickles bytes
        // cannot hold a connection slot for long.
        let left = READ_TIMEOUT.saturating_sub(started.elapsed());
        if left.is_zero() {
            return Err(std::io::ErrorKind::TimedOut.into());
        }
        stream.set_read_timeout(Some(left))?;
        let n = stream.read(&mut chunk)?;
        if n == 0 {
            return Err(std::io::ErrorKind::UnexpectedEof.into());
        }
        head.extend_from_slice(&chunk[..n]);
        if head.windows(4).any(|w| w == b"\r\n\r\n") || head.windows(2).any(|w| w == b"\n\n") {
            return Ok(Some(head));
        }
        if head.len() > MAX_HEAD {
            return Ok(None);
        }
    }
}

/// Whether a `Host` header names this machine by address (`127.0.0.1:8080`, `[::1]:8080`) or
/// as `localhost`.
fn local_host(value: &[u8]) -> bool {
    let Ok(host) = std::str::from_utf8(value) else {
        return false;
    };
    let host = host.trim();
    let name = match host.strip_prefix('[') {
        Some(v6) => v6.split(']').next().unwrap_or_default(),
        None => host.split(':').next().unwrap_or_default(),
    };
    name.eq_ignore_ascii_case("localhost") || name.parse::<std::net::IpAddr>().is_ok()
}

/// One connection: read one request, answer it, close.
fn serve(mut stream: TcpStream, loopback: bool, hub: &Hub, counters: &Counters) {
    let _ = stream.set_read_timeout(Some(READ_TIMEOUT));
    let _ = stream.set_write_timeout(Some(WRITE_TIMEOUT));
    let _ = stream.set_nodelay(true);
    let bad = |stream: &mut TcpStream, status: &str| {
        counters.bad_requests.fetch_add(1, Ordering::Relaxed);
        let _ = respond(
            stream,
            false,
            status,
            "text/plain; charset=utf-8",
            status.as_bytes(),
        );
    };
    let head = match read_head(&mut stream) {
        Ok(Some(head)) => head,
        Ok(None) => return bad(&mut stream, "431 Request Header Fields Too Large"),
        Err(_) => return,
    };
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut req = httparse::Request::new(&mut headers);
    let (method, path, host_ok) = match req.parse(&head) {
        Ok(httparse::Status::Complete(_)) => (
            req.method.unwrap_or_default().to_owned(),
            req.path.unwrap_or_default().to_owned(),
            req.headers
                .iter()
                .find(|h| h.name.eq_ignore_ascii_case("host"))
                .is_none_or(|h| local_host(h.value)),
        ),
        Err(httparse::Error::TooManyHeaders) => {
            return bad(&mut stream, "431 Request Header Fields Too Large");
        }
        _ => return bad(&mut stream, "400 Bad Request"),
    };
    // A page elsewhere that points its own name at 127.0.0.1 (DNS rebinding) must not read
    // the state: a loopback server answers only to an address or `localhost`.
    if loopback && !host_ok {
        return bad(&mut stream, "421 Misdirected Request");
    }
    let head_only = match method.as_str() {
        "GET" => false,
        "HEAD" => true,
        _ => {
            counters.bad_requests.fetch_add(1, Ordering::Relaxed);
            let _ = stream.write_all(
                b"HTTP/1.1 405 Method Not Allowed\r\nAllow: GET, HEAD\r\nContent-Length: 0\r\n\
                  Connection: close\r\n\r\n",
            );
            return;
        }
    };
    let path = path.split(['?', '#']).next().unwrap_or_default();
    let _ = match path {
        "/events" => return stream_events(stream, head_only, hub, counters),
        "/api/state" => match hub.latest() {
            // Before the first snapshot (the first moments after the start).
            (0, _) => respond(
                &mut stream,
                head_only,
                "503 Service Unavailable",
                "text/plain; charset=utf-8",
                b"starting: no state yet",
            ),
            (_, json) => respond(
                &mut stream,
                head_only,
                "200 OK",
                "application/json",
                json.as_bytes(),
            ),
        },
        _ => match assets::find(path) {
            Some((content_type, body)) => {
                respond(&mut stream, head_only, "200 OK", content_type, body)
            }
            None => return bad(&mut stream, "404 Not Found"),
        },
    };
}

/// `GET /events`: the latest snapshot as a server-sent event whenever there is a newer one.
fn stream_events(mut stream: impl Write, head_only: bool, hub: &Hub, counters: &Counters) {
    let Some(_stream_slot) = Slot::take(&counters.streams, MAX_STREAMS) else {
        counters.refused.fetch_add(1, Ordering::Relaxed);
        let _ = respond(
            &mut stream,
            false,
            "503 Service Unavailable",
            "text/plain; charset=utf-8",
            b"too many live clients: close another page first",
        );
        return;
    };
    let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
                X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\nretry: 1000\n\n";
    if stream.write_all(head.as_bytes()).is_err() || head_only {
        return;
    }
    let (mut seen, json) = hub.latest();
    let mut message = Vec::with_capacity(json.len() + 16);
    let send = |stream: &mut dyn Write, message: &mut Vec<u8>, json: &str| {
        message.clear();
        message.extend_from_slice(b"data: ");
        message.extend_from_slice(json.as_bytes());
        message.extend_from_slice(b"\n\n");
        stream.write_all(message).and_then(|()| stream.flush())
    };
    if seen != 0 {
        if send(&mut stream, &mut message, &json).is_err() {
            return;
        }
        counters.frames_sent.fetch_add(1, Ordering::Relaxed);
    }
    loop {
        match hub.newer(seen, KEEPALIVE) {
            Ok(Some((seq, json))) => {
                let skipped = seq.wrapping_sub(seen).saturating_sub(1);
                if seen != 0 && skipped > 0 {
                    counters
                        .frames_dropped
                        .fetch_add(skipped, Ordering::Relaxed);
                }
                seen = seq;
                if send(&mut stream, &mut message, &json).is_err() {
                    return;
                }
                counters.frames_sent.fetch_add(1, Ordering::Relaxed);
            }
            Ok(None) => {
                if stream.write_all(b": idle\n\n").is_err() {
                    return;
                }
            }
            Err(()) => return,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;

    #[test]
    fn only_local_host_names_pass() {
        for ok in [
            "127.0.0.1:8080",
            "localhost",
            "LOCALHOST:1",
            "[::1]:8080",
            "10.0.0.2",
        ] {
            assert!(local_host(ok.as_bytes()), "{ok}");
        }
        for bad in ["evil.example:8080", "127.0.0.1.evil.example", ""] {
            assert!(!local_host(bad.as_bytes()), "{bad}");
        }
        assert!(!local_host(&[0xff, 0xfe]));
    }

    /// A client that takes 20 ms for every write.
    struct Slow(Arc<Mutex<Vec<u8>>>);

    impl Write for Slow {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            thread::sleep(Duration::from_millis(20));
            self.0.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }

        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_slow_client_gets_the_newest_snapshots_and_the_rest_are_counted_as_dropped() {
        let hub = Arc::new(Hub::default());
        let counters = Arc::new(Counters::default());
        let written = Arc::new(Mutex::new(Vec::new()));
        hub.publish("{\"n\":0}".into());
        let stream = {
            let (hub, counters, out) = (hub.clone(), counters.clone(), Slow(written.clone()));
            thread::spawn(move || stream_events(out, false, &hub, &counters))
        };
        // The publisher never waits for the client: 2,000 snapshots, one every 0.1 ms.
        for n in 1..=2000 {
            hub.publish(format!("{{\"n\":{n}}}"));
            thread::sleep(Duration::from_micros(100));
        }
        // Let it take the last one, then end the stream.
        let c = Counters::state;
        for _ in 0..500 {
            if written.lock().unwrap().ends_with(b"{\"n\":2000}\n\n") {
                break;
            }
            thread::sleep(Duration::from_millis(10));
        }
        hub.close();
        stream.join().unwrap();
        let text = String::from_utf8(written.lock().unwrap().clone()).unwrap();
        let events: Vec<u64> = text
            .split("data: ")
            .skip(1)
            .map(|e| {
                e.split("\n\n")
                    .next()
                    .unwrap_or_default()
                    .trim_start_matches("{\"n\":")
                    .trim_end_matches('}')
            })
            .map(|n| n.parse().unwrap())
            .collect();
        let s = c(&counters);
        // Every event is a whole snapshot, newer than the one before; the last is the newest.
        assert!(events.windows(2).all(|w| w[0] < w[1]), "{events:?}");
        assert_eq!(events.last(), Some(&2000));
        assert_eq!(s.frames_sent, events.len() as u64, "{s:?}");
        // The ones it never got were counted: sent + dropped covers every snapshot from the
        // first it was sent to the last.
        assert!(s.frames_dropped > 0, "{s:?}");
        assert_eq!(
            s.frames_sent + s.frames_dropped,
            2000 - events[0] + 1,
            "{s:?}"
        );
        assert_eq!(s.clients, 0, "the stream gave its place back");
    }

    #[test]
    fn slots_never_exceed_their_limit() {
        let counter = AtomicU64::new(0);
        let taken: Vec<_> = (0..10).filter_map(|_| Slot::take(&counter, 3)).collect();
        assert_eq!(taken.len(), 3);
        drop(taken);
        assert_eq!(counter.load(Ordering::SeqCst), 0);
    }
}
