//! The HTTP side of `protolink web`: a small read-only server on `std::net`, one thread per
//! connection, every resource bounded. What it streams comes from the [`Hub`].
//!
//! * The decoder publishes one snapshot per display frame into a [`Hub`], which holds only the
//!   latest (a sequence number and its JSON): never a queue. Each live-update stream
//!   (server-sent events, `GET /events`) sends the newest snapshot whenever it is ready for
//!   one; the snapshots it skipped are counted as dropped. So a slow client costs the decoder
//!   and the other clients nothing.
//! * At most [`MAX_CONNECTIONS`] connections in all, at most [`MAX_PER_PEER`] from one
//!   address; more are answered `503` and counted.
//! * At most [`MAX_STREAMS`] live-update streams, at most [`MAX_STREAMS_PER_PEER`] from one
//!   address: a newer stream from an address at its limit takes the place of that address's
//!   oldest (a page reloaded, one tab too many), and when every place is taken a stream from an
//!   address with fewer takes the oldest place of the address that holds the most; each is
//!   counted as replaced. So no other address can hold the user's place, whether its clients
//!   read or not. Only when every place is held by an address with no more than its share is a
//!   new stream answered `503` (counted as refused); the page tries again, backing off.
//! * A request head is at most [`MAX_HEAD`] bytes with at most [`MAX_HEADERS`] headers
//!   (`431` otherwise), parsed by `httparse`; it must arrive within [`HEAD_TIMEOUT`]. At most
//!   [`MAX_PENDING`] connections may be sending their head at once: a new one closes the
//!   oldest of them that has had [`PENDING_GRACE`] (of its own address when that address is
//!   at its limit; counted as evicted), so clients that send their heads slowly can neither
//!   take the slots that connections with a request use nor keep a new client out. A write that cannot go out within [`WRITE_TIMEOUT`] ends the
//!   connection.
//! * A request a browser marks as sent by another site (`Sec-Fetch-Site: cross-site` or
//!   `same-site`, other than the user opening the page itself), or whose `Origin` is not this
//!   server, is refused with `403` and counted: a web page the user has open elsewhere can
//!   neither read the state nor hold the live-update streams.
//! * Only `GET` and `HEAD` (`405` otherwise); every response closes its connection.
//! * Bound to a loopback address, it answers only requests whose `Host` is an address or
//!   `localhost` (`421` otherwise), so a web page that points its own name at 127.0.0.1 (DNS
//!   rebinding) cannot read the state.

use std::collections::{HashMap, VecDeque};
use std::io::{Read, Write};
use std::net::{IpAddr, Shutdown, SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread;
use std::time::{Duration, Instant};

use super::assets;
use super::hub::Hub;
use super::state::ServerState;
use crate::error::{Error, Result};

/// The most live-update streams served at once.
pub(crate) const MAX_STREAMS: usize = 8;
/// The most live-update streams from one address at once: a page and one more (a second tab,
/// or the page reloaded before its old stream is noticed gone).
pub(crate) const MAX_STREAMS_PER_PEER: usize = 2;
/// The most connections served at once (streams included).
pub(crate) const MAX_CONNECTIONS: u64 = 24;
/// The most connections from one address at once (a browser opens six per host).
pub(crate) const MAX_PER_PEER: u64 = 12;
/// The most connections still sending their request head at once: more than one address may
/// hold, so another address always finds room.
pub(crate) const MAX_PENDING: usize = 16;
/// How long a connection may send its head before a new one may close it to take its place.
pub(crate) const PENDING_GRACE: Duration = Duration::from_millis(250);
/// The longest request head (request line and headers) accepted, bytes.
pub(crate) const MAX_HEAD: usize = 8 * 1024;
/// The most headers accepted in one request.
pub(crate) const MAX_HEADERS: usize = 32;
/// How long a client has to send its whole request head (a browser sends it at once).
pub(crate) const HEAD_TIMEOUT: Duration = Duration::from_secs(2);
/// How long one write to a client may take before the connection is given up.
pub(crate) const WRITE_TIMEOUT: Duration = Duration::from_secs(2);
/// A stream with nothing new sends a comment this often (so a gone client is noticed).
pub(crate) const KEEPALIVE: Duration = Duration::from_secs(1);

/// The server's counters (shown on the page and in `/api/state`).
#[derive(Debug, Default)]
pub(crate) struct Counters {
    connections: AtomicU64,
    /// The live-update streams open now, oldest first.
    streams: Mutex<Vec<Live>>,
    replaced: AtomicU64,
    refused: AtomicU64,
    bad_requests: AtomicU64,
    cross_site: AtomicU64,
    evicted: AtomicU64,
    frames_sent: AtomicU64,
    frames_dropped: AtomicU64,
    /// Connections per peer address (only addresses with one open).
    peers: Mutex<HashMap<IpAddr, u64>>,
    /// The connections still sending their head, oldest first.
    pending: Mutex<VecDeque<Pending>>,
    next_id: AtomicU64,
}

/// Locks `m`, taking the data of a poisoned lock as it is (every update is one step).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Counters {
    /// A copy for the state.
    pub(crate) fn state(&self) -> ServerState {
        ServerState {
            clients: lock(&self.streams).len() as u64,
            replaced: self.replaced.load(Ordering::Relaxed),
            refused: self.refused.load(Ordering::Relaxed),
            bad_requests: self.bad_requests.load(Ordering::Relaxed),
            cross_site: self.cross_site.load(Ordering::Relaxed),
            evicted: self.evicted.load(Ordering::Relaxed),
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
pub(crate) struct Server {
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
    pub(crate) fn start(addr: SocketAddr) -> Result<Server> {
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
    pub(crate) fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Where the decoder publishes snapshots.
    pub(crate) fn hub(&self) -> &Hub {
        &self.hub
    }

    /// The counters as the state shows them.
    pub(crate) fn counters(&self) -> ServerState {
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
            Ok((mut stream, peer)) => {
                let _ = stream.set_nonblocking(false);
                let conn = match Connection::take(counters, peer.ip()) {
                    Ok(conn) => conn,
                    Err(why) => {
                        counters.refused.fetch_add(1, Ordering::Relaxed);
                        // A few bytes into a fresh socket's buffer: never blocks for long.
                        let _ = stream.set_write_timeout(Some(Duration::from_millis(100)));
                        let _ = respond(
                            &mut stream,
                            false,
                            "503 Service Unavailable",
                            "text/plain; charset=utf-8",
                            why.as_bytes(),
                        );
                        continue;
                    }
                };
                let hub = hub.clone();
                // If the thread cannot start, the closure (and with it the slot) is dropped.
                let _ = thread::Builder::new()
                    .name("web-conn".into())
                    .spawn(move || serve(stream, loopback, &hub, &conn));
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

/// One of [`MAX_CONNECTIONS`] connection slots and one of its peer's [`MAX_PER_PEER`], given
/// back when dropped; while the request head is awaited, also one of [`MAX_PENDING`].
struct Connection {
    counters: Arc<Counters>,
    peer: IpAddr,
    id: u64,
}

impl Connection {
    /// The slots for a new connection from `peer`, or the sentence that refuses it. When its
    /// peer is at [`MAX_PER_PEER`], [`MAX_PENDING`] heads are awaited or every connection
    /// slot is taken, the oldest connection (of that peer, or of any) still sending its head
    /// after [`PENDING_GRACE`] is closed to make room.
    fn take(counters: &Arc<Counters>, peer: IpAddr) -> std::result::Result<Self, &'static str> {
        let peer_full = || lock(&counters.peers).get(&peer).copied().unwrap_or(0) >= MAX_PER_PEER;
        if peer_full() && !evict_oldest(counters, Some(peer), || !peer_full()) {
            return Err("too many connections from your address");
        }
        let pending_full = || lock(&counters.pending).len() >= MAX_PENDING;
        if pending_full() && !evict_oldest(counters, None, || !pending_full()) {
            return Err("too many connections are still sending their request");
        }
        let all_taken = || counters.connections.load(Ordering::SeqCst) >= MAX_CONNECTIONS;
        if all_taken() && !evict_oldest(counters, None, || !all_taken()) {
            return Err("too many connections");
        }
        {
            let mut peers = lock(&counters.peers);
            let n = peers.entry(peer).or_insert(0);
            if *n >= MAX_PER_PEER {
                return Err("too many connections from your address");
            }
            *n += 1;
        }
        if let Some(slot) = Slot::take(&counters.connections, MAX_CONNECTIONS) {
            // Given back by the connection's drop.
            std::mem::forget(slot);
            return Ok(Connection {
                counters: counters.clone(),
                peer,
                id: counters.next_id.fetch_add(1, Ordering::Relaxed),
            });
        }
        release_peer(counters, peer);
        Err("too many connections")
    }

    /// Marks the connection as sending its head (closable by a newer one) until [`Self::arrived`].
    fn awaiting_head(&self, stream: &TcpStream) {
        if let Ok(handle) = stream.try_clone() {
            lock(&self.counters.pending).push_back(Pending {
                id: self.id,
                since: Instant::now(),
                peer: self.peer,
                stream: handle,
            });
        }
    }

    /// The head arrived (or the connection ended): it no longer counts as pending.
    fn arrived(&self) {
        lock(&self.counters.pending).retain(|p| p.id != self.id);
    }
}

/// A connection still sending its request head.
#[derive(Debug)]
struct Pending {
    id: u64,
    since: Instant,
    peer: IpAddr,
    /// A handle to close it by.
    stream: TcpStream,
}

/// Closes the oldest connection still sending its head after [`PENDING_GRACE`] (of `peer`
/// when given), counted as evicted, and waits up to 50 ms for its thread to give its slots
/// back (`freed`); false when there is none to close.
fn evict_oldest(counters: &Counters, peer: Option<IpAddr>, freed: impl Fn() -> bool) -> bool {
    let victim = {
        let mut pending = lock(&counters.pending);
        let at = pending.iter().position(|p| {
            peer.is_none_or(|peer| p.peer == peer) && p.since.elapsed() >= PENDING_GRACE
        });
        at.and_then(|i| pending.remove(i))
    };
    let Some(victim) = victim else {
        return false;
    };
    counters.evicted.fetch_add(1, Ordering::Relaxed);
    let _ = victim.stream.shutdown(Shutdown::Both);
    let until = Instant::now() + Duration::from_millis(50);
    while !freed() && Instant::now() < until {
        thread::sleep(Duration::from_millis(1));
    }
    freed()
}

impl Drop for Connection {
    fn drop(&mut self) {
        self.arrived();
        release_peer(&self.counters, self.peer);
        // Only a connection whose slot was taken exists: `take` returns one only then.
        self.counters.connections.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Gives back one of `peer`'s connections; an address with none left is forgotten.
fn release_peer(counters: &Counters, peer: IpAddr) {
    let mut peers = lock(&counters.peers);
    if let Some(n) = peers.get_mut(&peer) {
        *n = n.saturating_sub(1);
        if *n == 0 {
            peers.remove(&peer);
        }
    }
}

/// One open live-update stream.
#[derive(Debug)]
struct Live {
    id: u64,
    peer: IpAddr,
    /// A handle to close it by (none for a test's writer).
    closer: Option<TcpStream>,
}

/// A place among the [`MAX_STREAMS`] live-update streams, given back when dropped (or taken
/// by a newer stream: see [`StreamPlace::take`]).
struct StreamPlace<'a> {
    counters: &'a Counters,
    id: u64,
}

impl<'a> StreamPlace<'a> {
    /// A place for a stream from `peer`, or `None` when every place is held by an address
    /// with no more than its share. When `peer` holds [`MAX_STREAMS_PER_PEER`] already, its
    /// oldest stream is closed and gives its place; when every place is taken, the oldest
    /// stream of the address that holds the most does, if that address would still hold more
    /// than `peer`. A stream closed so is counted as replaced.
    fn take(counters: &'a Counters, peer: IpAddr, closer: Option<TcpStream>) -> Option<Self> {
        let id = counters.next_id.fetch_add(1, Ordering::Relaxed);
        let victim = {
            let mut live = lock(&counters.streams);
            let held = |p: IpAddr| live.iter().filter(|l| l.peer == p).count();
            let mine = held(peer);
            let victim = if mine >= MAX_STREAMS_PER_PEER {
                live.iter().position(|l| l.peer == peer)
            } else if live.len() >= MAX_STREAMS {
                let crowded = live.iter().map(|l| l.peer).max_by_key(|&p| held(p))?;
                if held(crowded) <= mine + 1 {
                    return None;
                }
                live.iter().position(|l| l.peer == crowded)
            } else {
                None
            };
            let victim = victim.map(|at| live.remove(at));
            live.push(Live { id, peer, closer });
            victim
        };
        if let Some(victim) = victim {
            counters.replaced.fetch_add(1, Ordering::Relaxed);
            // Its thread finds its next write failing (within a keep-alive) and ends.
            if let Some(stream) = victim.closer {
                let _ = stream.shutdown(Shutdown::Both);
            }
        }
        Some(StreamPlace { counters, id })
    }
}

impl Drop for StreamPlace<'_> {
    fn drop(&mut self) {
        lock(&self.counters.streams).retain(|l| l.id != self.id);
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
/// all within [`HEAD_TIMEOUT`]. `Ok(None)` when it is too long.
fn read_head(stream: &mut TcpStream) -> std::io::Result<Option<Vec<u8>>> {
    let started = std::time::Instant::now();
    let mut head = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        // The whole head within HEAD_TIMEOUT, not each read: a client that trickles bytes
        // cannot hold a connection slot for long.
        let left = HEAD_TIMEOUT.saturating_sub(started.elapsed());
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

/// Whether a browser marks the request as made by another site's page: `Sec-Fetch-Site`
/// `cross-site` or `same-site` (other than the user opening the page itself: a navigation to
/// a document), or an `Origin` other than the `Host` the request was sent to.
fn from_another_site(headers: &[httparse::Header<'_>]) -> bool {
    let get = |name: &str| {
        headers
            .iter()
            .find(|h| h.name.eq_ignore_ascii_case(name))
            .map(|h| String::from_utf8_lossy(h.value).trim().to_ascii_lowercase())
    };
    let site = get("sec-fetch-site");
    let user_opened = get("sec-fetch-mode").as_deref() == Some("navigate")
        && get("sec-fetch-dest")
            .as_deref()
            .is_none_or(|d| d == "document");
    if matches!(site.as_deref(), Some("cross-site" | "same-site")) && !user_opened {
        return true;
    }
    match (get("origin"), get("host")) {
        (Some(origin), Some(host)) => origin != format!("http://{host}"),
        (Some(_), None) => true,
        (None, _) => false,
    }
}

/// One connection: read one request, answer it, close.
fn serve(mut stream: TcpStream, loopback: bool, hub: &Hub, conn: &Connection) {
    let counters = &*conn.counters;
    let _ = stream.set_read_timeout(Some(HEAD_TIMEOUT));
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
    conn.awaiting_head(&stream);
    let head = read_head(&mut stream);
    conn.arrived();
    let head = match head {
        Ok(Some(head)) => head,
        Ok(None) => return bad(&mut stream, "431 Request Header Fields Too Large"),
        Err(_) => return,
    };
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut req = httparse::Request::new(&mut headers);
    let (method, path, host_ok, cross_site) = match req.parse(&head) {
        Ok(httparse::Status::Complete(_)) => (
            req.method.unwrap_or_default().to_owned(),
            req.path.unwrap_or_default().to_owned(),
            req.headers
                .iter()
                .find(|h| h.name.eq_ignore_ascii_case("host"))
                .is_none_or(|h| local_host(h.value)),
            from_another_site(req.headers),
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
    // Another site's page must neither read the state nor hold a stream slot.
    if cross_site {
        counters.cross_site.fetch_add(1, Ordering::Relaxed);
        let _ = respond(
            &mut stream,
            false,
            "403 Forbidden",
            "text/plain; charset=utf-8",
            b"refused: a request from another site (open the page itself)",
        );
        return;
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
        "/events" => {
            let place = StreamPlace::take(counters, conn.peer, stream.try_clone().ok());
            return stream_events(stream, place, head_only, hub, counters);
        }
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

/// `GET /events`: the latest snapshot as a server-sent event whenever there is a newer one, for
/// as long as the stream holds its `place` (`None`: no place, answered `503`).
fn stream_events(
    mut stream: impl Write,
    place: Option<StreamPlace<'_>>,
    head_only: bool,
    hub: &Hub,
    counters: &Counters,
) {
    let Some(_place) = place else {
        counters.refused.fetch_add(1, Ordering::Relaxed);
        let _ = respond(
            &mut stream,
            false,
            "503 Service Unavailable",
            "text/plain; charset=utf-8",
            b"every live-update place is taken: the page tries again",
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
    fn requests_of_another_site_are_told_apart() {
        let h = |pairs: &[(&'static str, &'static str)]| -> bool {
            let headers: Vec<httparse::Header<'_>> = pairs
                .iter()
                .map(|(name, value)| httparse::Header {
                    name,
                    value: value.as_bytes(),
                })
                .collect();
            from_another_site(&headers)
        };
        let host = ("Host", "127.0.0.1:8080");
        // No fetch metadata (curl, an older browser), the user typing the address, the page's
        // own requests: served.
        assert!(!h(&[host]));
        assert!(!h(&[host, ("Sec-Fetch-Site", "none")]));
        assert!(!h(&[host, ("Sec-Fetch-Site", "same-origin")]));
        assert!(!h(&[host, ("Origin", "http://127.0.0.1:8080")]));
        // A link on another site opening the page itself: served (its requests are then
        // same-origin).
        assert!(!h(&[
            host,
            ("Sec-Fetch-Site", "cross-site"),
            ("Sec-Fetch-Mode", "navigate"),
            ("Sec-Fetch-Dest", "document"),
        ]));
        // Another site's script, frame or stream: refused.
        assert!(h(&[
            host,
            ("Sec-Fetch-Site", "cross-site"),
            ("Sec-Fetch-Mode", "cors")
        ]));
        assert!(h(&[
            host,
            ("Sec-Fetch-Site", "Same-Site"),
            ("Sec-Fetch-Mode", "no-cors")
        ]));
        assert!(h(&[
            host,
            ("Sec-Fetch-Site", "cross-site"),
            ("Sec-Fetch-Mode", "navigate"),
            ("Sec-Fetch-Dest", "iframe"),
        ]));
        assert!(h(&[host, ("Origin", "http://evil.example")]));
        assert!(h(&[host, ("Origin", "http://127.0.0.1:9999")]));
        assert!(h(&[host, ("Origin", "null")]));
        assert!(h(&[("Origin", "http://127.0.0.1:8080")]));
    }

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
            thread::spawn(move || {
                let place = StreamPlace::take(&counters, IpAddr::from([127, 0, 0, 1]), None);
                stream_events(out, place, false, &hub, &counters);
            })
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
    fn a_crowded_address_gives_its_oldest_stream_and_no_address_takes_anothers_share() {
        let counters = Counters::default();
        let at = |n: u8| IpAddr::from([127, 0, 0, n]);
        let peers = |c: &Counters| lock(&c.streams).iter().map(|l| l.peer).collect::<Vec<_>>();
        // One address: its third stream replaces its first.
        let first = StreamPlace::take(&counters, at(2), None).unwrap();
        let (first_id, _second) = (first.id, StreamPlace::take(&counters, at(2), None).unwrap());
        std::mem::forget(first); // its thread has not noticed yet
        let _third = StreamPlace::take(&counters, at(2), None).unwrap();
        assert!(lock(&counters.streams).iter().all(|l| l.id != first_id));
        assert_eq!((peers(&counters).len(), counters.state().replaced), (2, 1));
        // Every place taken by four addresses, two each: a fifth (the user's) takes the oldest
        // place of one of them; its second stream would only swap shares, and is refused.
        let mut held: Vec<_> = (3..=5)
            .flat_map(|n| [n, n])
            .map(|n| StreamPlace::take(&counters, at(n), None).unwrap())
            .collect();
        assert_eq!(peers(&counters).len(), MAX_STREAMS);
        held.push(StreamPlace::take(&counters, at(1), None).expect("the user's page"));
        assert_eq!(counters.state().replaced, 2);
        assert_eq!(peers(&counters).iter().filter(|&&p| p == at(1)).count(), 1);
        assert!(StreamPlace::take(&counters, at(1), None).is_none());
        assert_eq!(
            (peers(&counters).len(), counters.state().replaced),
            (MAX_STREAMS, 2)
        );
        // Eight addresses, one each: a ninth is refused, and nothing is closed for it.
        drop(held);
        drop(_third);
        drop(_second);
        let eight: Vec<_> = (10..18)
            .map(|n| StreamPlace::take(&counters, at(n), None).unwrap())
            .collect();
        let replaced = counters.state().replaced;
        assert!(StreamPlace::take(&counters, at(1), None).is_none());
        assert_eq!(
            (counters.state().replaced, peers(&counters).len()),
            (replaced, 8)
        );
        drop(eight);
        assert_eq!(counters.state().clients, 0);
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
