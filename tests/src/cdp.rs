//! The few pieces of the Chrome DevTools Protocol that [`crate::browser`] needs: start
//! Chromium with a DevTools port, find its page, and exchange JSON with that page over a
//! WebSocket (`tungstenite` for the framing, plain `ws://` on 127.0.0.1, a std `TcpStream`
//! with read timeouts: no async runtime, no thread).
//!
//! A command is `{"id", "method", "params"}`; its answer carries the same `id` and a
//! `result` or an `error`. Events, `{"method", "params"}`, arrive in between, and
//! [`Connection::call`] hands each one it reads to the caller's handler, so none is lost while
//! a command waits. Every wait has a deadline ([`TIMEOUT`]), and every read a bound.

use std::ffi::OsString;
use std::fs::File;
use std::io::{ErrorKind, Read};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use tungstenite::{Message, WebSocket};

/// How long Chromium may take to start, to answer one command, or to load a page.
pub(crate) const TIMEOUT: Duration = Duration::from_secs(20);

/// The most messages one [`Connection::drain`] reads: a page that logs without a pause
/// cannot hold the caller there (the rest wait for the next read).
const MAX_DRAINED: usize = 10_000;

/// The most of Chromium's stderr read while looking for its DevTools line.
const MAX_STDERR: u64 = 1 << 20;

/// What Chromium prints on stderr once its DevTools server listens.
const LISTENING: &str = "DevTools listening on ws://";

/// A running Chromium and its directory (the profile and its stderr): dropping it kills the
/// browser, waits for it, and removes the directory.
pub(crate) struct Chromium {
    child: Child,
    dir: PathBuf,
}

impl Chromium {
    /// Starts `chromium` headless on about:blank, with a fresh profile and a DevTools port
    /// of its choosing, and connects to its page. Panics, with the end of the browser's
    /// stderr, when it exits or does not listen within [`TIMEOUT`].
    pub(crate) fn launch(chromium: &Path) -> (Chromium, Connection) {
        static N: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "protolink-chromium-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::SeqCst)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        let profile = dir.join("profile");
        std::fs::create_dir_all(&profile).expect("a profile directory");
        // Chromium's stderr goes to a file: nothing has to keep reading a pipe for it.
        let stderr_path = dir.join("stderr.txt");
        let stderr = File::create(&stderr_path).expect("a file for chromium's stderr");
        let mut user_data_dir = OsString::from("--user-data-dir=");
        user_data_dir.push(&profile);
        let child = Command::new(chromium)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-background-networking",
                "--no-first-run",
                "--disable-dev-shm-usage",
                // As headless_chrome passed them: the page's timers and frames run at full
                // rate whatever the browser thinks of its (absent) window.
                "--disable-background-timer-throttling",
                "--disable-backgrounding-occluded-windows",
                "--disable-renderer-backgrounding",
                "--window-size=1400,900",
            ])
            .arg(user_data_dir)
            .args(["--remote-debugging-port=0", "about:blank"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(stderr)
            .spawn()
            .unwrap_or_else(|e| panic!("starting {}: {e}", chromium.display()));
        // From here on a panic drops `browser`, which kills the process.
        let mut browser = Chromium { child, dir };
        let deadline = Instant::now() + TIMEOUT;
        let port = browser.devtools_port(&stderr_path, deadline);
        let url = page_url(port, deadline);
        let connection = Connection::open(&url);
        (browser, connection)
    }

    /// The port in Chromium's `DevTools listening on ws://127.0.0.1:PORT/...` line.
    fn devtools_port(&mut self, stderr_path: &Path, deadline: Instant) -> u16 {
        loop {
            let stderr = read_start(stderr_path);
            if let Some(port) = stderr.lines().find_map(|line| {
                let rest = line.trim().strip_prefix(LISTENING)?;
                let host_port = rest.split('/').next()?;
                host_port.rsplit(':').next()?.parse().ok()
            }) {
                return port;
            }
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!(
                    "chromium exited ({status}) before its DevTools server listened; its stderr \
                     ends:\n{}",
                    last_lines(&stderr, 20)
                );
            }
            assert!(
                Instant::now() < deadline,
                "chromium printed no {LISTENING:?} line within {TIMEOUT:?}; its stderr ends:\n{}",
                last_lines(&stderr, 20)
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Chromium {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        // The browser's own processes (network, storage, renderers) outlive it by a few
        // milliseconds and may still write to the profile: removed again until it stays gone
        // (one second at most).
        for _ in 0..20 {
            let _ = std::fs::remove_dir_all(&self.dir);
            std::thread::sleep(Duration::from_millis(50));
            if !self.dir.exists() {
                break;
            }
        }
    }
}

/// The first [`MAX_STDERR`] bytes of a file, as text (empty when it cannot be read).
fn read_start(path: &Path) -> String {
    let mut raw = Vec::new();
    if let Ok(file) = File::open(path) {
        let _ = file.take(MAX_STDERR).read_to_end(&mut raw);
    }
    String::from_utf8_lossy(&raw).into_owned()
}

/// The last `n` lines of `text`.
fn last_lines(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

/// The WebSocket address of the browser's page, from its target list (`GET /json/list`),
/// asked again every 100 ms until `deadline` while there is no page in it.
fn page_url(port: u16, deadline: Instant) -> String {
    let addr = SocketAddr::from(([127, 0, 0, 1], port));
    loop {
        let (status, body) = crate::browser::http_get(addr, "/json/list");
        let targets: Value = serde_json::from_str(&body).unwrap_or(Value::Null);
        let page = targets.as_array().and_then(|targets| {
            targets
                .iter()
                .filter(|t| t["type"] == "page")
                .find_map(|t| t["webSocketDebuggerUrl"].as_str())
        });
        if let Some(url) = page {
            return url.to_owned();
        }
        assert!(
            Instant::now() < deadline,
            "no page in chromium's target list within {TIMEOUT:?}: {status} {body}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// A WebSocket to one page's DevTools endpoint.
pub(crate) struct Connection {
    ws: WebSocket<TcpStream>,
    last_id: u64,
}

impl Connection {
    /// Connects to `url` (`ws://127.0.0.1:PORT/devtools/page/ID`).
    fn open(url: &str) -> Connection {
        let addr: SocketAddr = url
            .strip_prefix("ws://")
            .and_then(|rest| rest.split('/').next())
            .and_then(|host_port| host_port.parse().ok())
            .unwrap_or_else(|| panic!("not a ws://IP:PORT/ address: {url}"));
        let stream = TcpStream::connect_timeout(&addr, Duration::from_secs(5))
            .unwrap_or_else(|e| panic!("connecting to {url}: {e}"));
        stream
            .set_read_timeout(Some(TIMEOUT))
            .and_then(|()| stream.set_write_timeout(Some(TIMEOUT)))
            .and_then(|()| stream.set_nodelay(true))
            .expect("socket options");
        let (ws, _) = tungstenite::client::client(url, stream)
            .unwrap_or_else(|e| panic!("the WebSocket handshake with {url}: {e}"));
        Connection { ws, last_id: 0 }
    }

    /// Sends the command `method` with `params` and returns its `result`, or its `error` (or
    /// a failed connection, or no answer within [`TIMEOUT`]) as text. Events already waiting
    /// and those that arrive before the answer go to `on_event`, in order.
    pub(crate) fn call(
        &mut self,
        method: &str,
        params: Value,
        on_event: &mut dyn FnMut(&str, &Value),
    ) -> Result<Value, String> {
        self.drain(on_event)?;
        self.last_id += 1;
        let id = self.last_id;
        let command = json!({ "id": id, "method": method, "params": params });
        self.ws
            .send(Message::text(command.to_string()))
            .map_err(|e| format!("sending {method}: {e}"))?;
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let Some(mut message) = self.read(deadline)? else {
                return Err(format!("no answer to {method} within {TIMEOUT:?}"));
            };
            if message["id"].as_u64() == Some(id) {
                if let Some(error) = message.get("error") {
                    return Err(format!("{method}: {error}"));
                }
                return Ok(message["result"].take());
            }
            // An event, or the late answer to a command that timed out (dropped).
            dispatch(&message, on_event);
        }
    }

    /// Hands the events that have already arrived (at most [`MAX_DRAINED`]) to `on_event`,
    /// without waiting for more.
    pub(crate) fn drain(&mut self, on_event: &mut dyn FnMut(&str, &Value)) -> Result<(), String> {
        for _ in 0..MAX_DRAINED {
            match self.read(Instant::now())? {
                Some(message) => dispatch(&message, on_event),
                None => break,
            }
        }
        Ok(())
    }

    /// Waits for one message until `deadline` and hands it to `on_event` if it is an event:
    /// `false` when none came.
    pub(crate) fn next_event(
        &mut self,
        deadline: Instant,
        on_event: &mut dyn FnMut(&str, &Value),
    ) -> Result<bool, String> {
        let Some(message) = self.read(deadline)? else {
            return Ok(false);
        };
        dispatch(&message, on_event);
        Ok(true)
    }

    /// The next message as JSON, or `None` when none is complete by `deadline` (a message
    /// partly received stays in tungstenite's buffer for the next read).
    fn read(&mut self, deadline: Instant) -> Result<Option<Value>, String> {
        loop {
            // A zero timeout means "block" to the socket: wait at least a millisecond.
            let left = deadline
                .saturating_duration_since(Instant::now())
                .max(Duration::from_millis(1));
            self.ws
                .get_mut()
                .set_read_timeout(Some(left))
                .map_err(|e| format!("a read timeout: {e}"))?;
            let parsed = match self.ws.read() {
                Ok(Message::Text(text)) => serde_json::from_str(text.as_str()),
                Ok(Message::Binary(bytes)) => serde_json::from_slice(&bytes),
                Ok(Message::Close(frame)) => {
                    return Err(format!(
                        "chromium closed the DevTools connection: {frame:?}"
                    ));
                }
                // Pings (tungstenite queues the pong), pongs, raw frames.
                Ok(_) => {
                    if Instant::now() >= deadline {
                        return Ok(None);
                    }
                    continue;
                }
                Err(tungstenite::Error::Io(e)) if e.kind() == ErrorKind::Interrupted => continue,
                Err(tungstenite::Error::Io(e))
                    if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) =>
                {
                    return Ok(None);
                }
                Err(e) => return Err(format!("the DevTools connection: {e}")),
            };
            return parsed
                .map(Some)
                .map_err(|e| format!("a DevTools message that is not JSON: {e}"));
        }
    }
}

/// Hands `message` to `on_event` if it is an event (it has a `method`).
fn dispatch(message: &Value, on_event: &mut dyn FnMut(&str, &Value)) {
    if let Some(method) = message["method"].as_str() {
        on_event(method, &message["params"]);
    }
}
