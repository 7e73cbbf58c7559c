//! Debian's Chromium, headless, driven over the DevTools protocol (a small client of our own
//! in `cdp.rs`, on `tungstenite`), for the tests of `protolink web`:
//! `host-tool/tests/all/web.rs` (against `protolink sim`) and `tests/tests/all/web_qemu.rs`
//! (against the firmware in QEMU).
//!
//! [`Page`] records every console error, uncaught exception and failed load the page causes,
//! evaluates expressions, takes screenshots, and measures the horizon's roll from the
//! attitude canvas's pixels ([`Page::horizon`]).

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

use crate::cdp::{Chromium, Connection, TIMEOUT};

/// Where Debian's `chromium` package puts the browser.
pub const CHROMIUM: &str = "/usr/bin/chromium";

/// The most errors [`Page::errors`] keeps; past it they are counted, and the count is the
/// list's last entry.
pub const MAX_ERRORS: usize = 1000;

/// The browser, or `None` when it is missing: the caller's test is then skipped through
/// [`crate::skip::skip`] (which fails it under CI, so the browser tests never skip there).
pub fn chromium() -> Option<PathBuf> {
    let found = Command::new(CHROMIUM)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some(PathBuf::from(CHROMIUM));
    }
    crate::skip::skip("chromium is not installed (scripts/setup.sh chromium installs it)");
    None
}

/// One page in a fresh headless Chromium (its own profile directory; the browser is killed
/// and the directory removed when the page is dropped).
pub struct Page {
    session: Mutex<Session>,
    // Dropped after the connection: kills the browser, removes its directory.
    _chromium: Chromium,
}

/// The connection and what its events told so far.
struct Session {
    connection: Connection,
    events: Events,
}

/// What [`Page`] keeps from the DevTools events.
#[derive(Default)]
struct Events {
    errors: Vec<String>,
    /// Errors past [`MAX_ERRORS`], counted only.
    dropped: u64,
    /// `Page.loadEventFired` seen since the last navigation began.
    loaded: bool,
}

impl Events {
    fn on(&mut self, method: &str, params: &Value) {
        let error = match method {
            "Page.loadEventFired" => {
                self.loaded = true;
                None
            }
            "Log.entryAdded" if params["entry"]["level"] == "error" => {
                let entry = &params["entry"];
                Some(format!(
                    "log: {} ({})",
                    entry["text"].as_str().unwrap_or_default(),
                    entry["url"].as_str().unwrap_or_default()
                ))
            }
            "Runtime.exceptionThrown" => Some(format!(
                "exception: {}",
                exception_text(&params["exceptionDetails"])
            )),
            "Runtime.consoleAPICalled" if params["type"] == "error" => {
                // Each argument's value (a primitive) or else its description (an object).
                let args: Vec<Option<Value>> = params["args"]
                    .as_array()
                    .map(Vec::as_slice)
                    .unwrap_or_default()
                    .iter()
                    .map(|a| {
                        a.get("value")
                            .filter(|v| !v.is_null())
                            .cloned()
                            .or_else(|| a["description"].as_str().map(Value::from))
                    })
                    .collect();
                Some(format!("console.error: {args:?}"))
            }
            _ => None,
        };
        if let Some(error) = error {
            self.record(error);
        }
    }

    fn record(&mut self, error: String) {
        if self.errors.len() < MAX_ERRORS {
            self.errors.push(error);
        } else {
            self.dropped += 1;
        }
    }
}

impl Session {
    fn call(&mut self, method: &str, params: Value) -> Result<Value, String> {
        let events = &mut self.events;
        self.connection
            .call(method, params, &mut |m, p| events.on(m, p))
    }
}

/// An exception's text as `Runtime.exceptionThrown` and `Runtime.evaluate` give it: the
/// message, the exception's description, and where.
fn exception_text(details: &Value) -> String {
    format!(
        "{} {} at {}:{}",
        details["text"].as_str().unwrap_or_default(),
        details["exception"]["description"]
            .as_str()
            .unwrap_or_default(),
        details["lineNumber"],
        details["columnNumber"]
    )
}

/// What [`Page::horizon`] measured on the attitude canvas.
#[derive(Debug, Clone, Copy)]
pub struct Horizon {
    /// The roll the pixels show: the angle of the sky/ground edge, degrees, positive when the
    /// edge's right end is higher (a right bank).
    pub measured_deg: f64,
    /// The roll the drawing code says it drew (`window.efis.roll_deg`), same frame.
    pub drawn_deg: f64,
}

impl Page {
    /// Starts `chromium` headless (`--no-sandbox --disable-gpu --disable-background-networking
    /// --no-first-run --disable-dev-shm-usage`, no throttling of background timers and
    /// renderers, a 1400×900 window, a fresh `--user-data-dir`, a DevTools port of its
    /// choosing), opens `url` in its page and waits for the load event (20 s at most). Panics
    /// when the browser does not start or the page does not load.
    pub fn open(chromium: &Path, url: &str) -> Page {
        let (chromium, connection) = Chromium::launch(chromium);
        let page = Page {
            session: Mutex::new(Session {
                connection,
                events: Events::default(),
            }),
            _chromium: chromium,
        };
        for domain in ["Log", "Runtime", "Page"] {
            page.call(&format!("{domain}.enable"), json!({}))
                .unwrap_or_else(|e| panic!("{e}"));
        }
        let mut session = page.session();
        // A load event already on its way is about:blank's: handled before the flag is reset.
        let Session { connection, events } = &mut *session;
        connection
            .drain(&mut |m, p| events.on(m, p))
            .unwrap_or_else(|e| panic!("{e}"));
        events.loaded = false;
        let navigated = session
            .call("Page.navigate", json!({ "url": url }))
            .unwrap_or_else(|e| panic!("navigating to {url}: {e}"));
        if let Some(error) = navigated["errorText"].as_str() {
            panic!("navigating to {url}: {error}");
        }
        let deadline = Instant::now() + TIMEOUT;
        while !session.events.loaded {
            let Session { connection, events } = &mut *session;
            let read = connection
                .next_event(deadline, &mut |m, p| events.on(m, p))
                .unwrap_or_else(|e| panic!("loading {url}: {e}"));
            assert!(read, "{url}: no load event within {TIMEOUT:?}");
        }
        drop(session);
        page
    }

    /// The session, even when a panic in another thread left its lock poisoned.
    fn session(&self) -> MutexGuard<'_, Session> {
        self.session.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn call(&self, method: &str, params: Value) -> Result<Value, String> {
        self.session().call(method, params)
    }

    /// The value of a JavaScript expression (passed through `JSON.stringify`). Panics with
    /// the expression when it throws or the browser does not answer.
    pub fn eval(&self, expression: &str) -> Value {
        let wrapped = format!("JSON.stringify({expression})");
        let answer = self
            .call(
                "Runtime.evaluate",
                json!({ "expression": wrapped, "returnByValue": true }),
            )
            .unwrap_or_else(|e| panic!("evaluating {expression}: {e}"));
        if let Some(details) = answer.get("exceptionDetails") {
            panic!("evaluating {expression}: {}", exception_text(details));
        }
        match &answer["result"]["value"] {
            Value::String(json) => serde_json::from_str(json).unwrap_or(Value::Null),
            _ => Value::Null,
        }
    }

    /// `window.efis`: what the drawing code drew last.
    pub fn efis(&self) -> Value {
        self.eval("window.efis")
    }

    /// Waits until `condition` holds for `window.efis` (checked every 100 ms), panicking with
    /// `what` and the last value after `timeout`.
    pub fn wait_for(
        &self,
        what: &str,
        timeout: Duration,
        condition: impl Fn(&Value) -> bool,
    ) -> Value {
        let started = Instant::now();
        loop {
            let efis = self.efis();
            if condition(&efis) {
                return efis;
            }
            assert!(
                started.elapsed() < timeout,
                "{what}: not within {timeout:?}; window.efis = {efis}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// The console errors, uncaught exceptions and failed loads so far, including those whose
    /// events arrived since the last command (the first [`MAX_ERRORS`], then a count of the
    /// rest). A broken DevTools connection is one more error.
    pub fn errors(&self) -> Vec<String> {
        let mut session = self.session();
        let Session { connection, events } = &mut *session;
        if let Err(e) = connection.drain(&mut |m, p| events.on(m, p)) {
            events.record(e);
        }
        let mut errors = events.errors.clone();
        if events.dropped > 0 {
            errors.push(format!(
                "... and {} more errors, not kept (only the first {MAX_ERRORS} are)",
                events.dropped
            ));
        }
        errors
    }

    /// A PNG screenshot of the window (the viewport) into `path`.
    pub fn screenshot(&self, path: &Path) {
        let answer = self
            .call(
                "Page.captureScreenshot",
                json!({ "format": "png", "fromSurface": true }),
            )
            .unwrap_or_else(|e| panic!("a screenshot: {e}"));
        let png = data_encoding::BASE64
            .decode(answer["data"].as_str().unwrap_or_default().as_bytes())
            .unwrap_or_else(|e| panic!("a screenshot that is not base64: {e}"));
        assert!(!png.is_empty(), "an empty screenshot: {answer}");
        if let Some(dir) = path.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        std::fs::write(path, png).expect("writing the screenshot");
    }

    /// Measures the horizon on the attitude canvas from its pixels: the sky/ground edge in two
    /// columns 120 px either side of the centre (inside the bank scale, outside the pitch
    /// ladder and the aircraft symbol), to a fraction of a pixel from the blend of the
    /// anti-aliased edge rows; read in the same JavaScript task as `window.efis.roll_deg`, so
    /// both describe the same frame.
    pub fn horizon(&self) -> Option<Horizon> {
        let v = self.eval(HORIZON_JS);
        let y1 = v["y1"].as_f64()?;
        let y2 = v["y2"].as_f64()?;
        let dx = v["dx"].as_f64()?;
        Some(Horizon {
            measured_deg: (y1 - y2).atan2(dx).to_degrees(),
            drawn_deg: v["drawn"].as_f64()?,
        })
    }
}

/// The pixel measurement: for a column x, the edge row is where the sky (blue) ends and the
/// ground (brown) begins, plus the sky's share of the blended rows between them.
const HORIZON_JS: &str = r#"(() => {
  const c = document.getElementById('attitude');
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  const px = (x, y) => { const i = (y * c.width + x) * 4; return [d[i], d[i + 1], d[i + 2]]; };
  const sky = ([r, g, b]) => b > 180 && r < 90;
  const ground = ([r, g, b]) => r > 110 && b < 70;
  const edge = (x) => {
    for (let y = 0; y + 3 < c.height; y++) {
      if (!sky(px(x, y))) continue;
      for (let k = 1; k <= 3; k++) {
        if (ground(px(x, y + k))) {
          // Blue channel: sky 214, ground 43; each blended row adds its sky share.
          let share = 0;
          for (let j = 1; j < k; j++) share += Math.max(0, Math.min(1, (px(x, y + j)[2] - 43) / (214 - 43)));
          return y + 1 + share;
        }
        if (sky(px(x, y + k))) break;
      }
    }
    return null;
  };
  const x1 = Math.round(c.width / 2 - 120);
  const x2 = Math.round(c.width / 2 + 120);
  return { y1: edge(x1), y2: edge(x2), dx: x2 - x1, drawn: window.efis.roll_deg };
})()"#;

/// `GET path` on `addr`: the status code and the body. The body ends where the server closes
/// the connection or, when the answer has a `Content-Length`, after that many bytes (Chromium's
/// DevTools server keeps the connection open whatever the request says).
pub fn http_get(addr: SocketAddr, path: &str) -> (u16, String) {
    let mut s = TcpStream::connect_timeout(&addr, Duration::from_secs(5)).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(10)))
        .expect("timeout");
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .expect("send");
    let mut raw = Vec::new();
    let mut chunk = [0u8; 4096];
    while !complete(&raw) {
        match s.read(&mut chunk) {
            Ok(0) | Err(_) => break,
            Ok(n) => raw.extend_from_slice(&chunk[..n]),
        }
    }
    let text = String::from_utf8_lossy(&raw).into_owned();
    let status = text
        .split(' ')
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let body = text
        .split_once("\r\n\r\n")
        .map(|(_, b)| b.to_owned())
        .unwrap_or_default();
    (status, body)
}

/// Whether `raw` holds a whole HTTP answer by its `Content-Length` (an answer without one
/// ends when the server closes the connection).
fn complete(raw: &[u8]) -> bool {
    let Some(end) = raw.windows(4).position(|w| w == b"\r\n\r\n") else {
        return false;
    };
    let head = String::from_utf8_lossy(&raw[..end]);
    head.lines()
        .filter_map(|line| line.split_once(':'))
        .find(|(name, _)| name.trim().eq_ignore_ascii_case("content-length"))
        .and_then(|(_, value)| value.trim().parse::<usize>().ok())
        .is_some_and(|length| raw.len() >= end + 4 + length)
}

/// The fields every `GET /api/state` (and every live update) carries.
pub const STATE_FIELDS: [&str; 17] = [
    "source", "uptime_s", "bytes", "no_data", "attitude", "air", "heading", "gps", "wind",
    "temp_c", "info", "toast", "types", "errors", "track", "server", "units",
];

/// The heading rate of a coordinated turn, g·tan(bank)/TAS, in degrees a second.
///
/// ```
/// let rate = protolink_tests::browser::turn_rate_deg_s(30.0, 50.0);
/// assert!((rate - 6.488).abs() < 0.001);
/// ```
pub fn turn_rate_deg_s(bank_deg: f64, tas_mps: f64) -> f64 {
    (9.806_65 * bank_deg.to_radians().tan() / tas_mps).to_degrees()
}

/// The checks both browser tests make on a box flying a steady turn at `bank_deg` and
/// `tas_mps`: the page draws an attitude, a heading and a track; the horizon's pixels and the
/// drawn roll show the bank within 1 degree (three frames); the drawn heading turns at
/// [`turn_rate_deg_s`] within 2 % over 3 s of the box's clock; the track grows.
pub fn check_the_turn(page: &Page, bank_deg: f64, tas_mps: f64) {
    page.wait_for("the first drawn attitude", Duration::from_secs(20), |e| {
        e["roll_deg"].is_number()
            && e["heading_deg"].is_number()
            && e["track_points"].as_u64() > Some(0)
    });
    for _ in 0..3 {
        let h = page.horizon().expect("a sky/ground edge in both columns");
        println!("horizon: {h:?}, bank {bank_deg}");
        assert!(
            (h.measured_deg - bank_deg).abs() <= 1.0,
            "pixels show {h:?}"
        );
        assert!((h.drawn_deg - bank_deg).abs() <= 1.0, "drawn {h:?}");
        std::thread::sleep(Duration::from_millis(300));
    }
    let num = |v: &Value, k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    let first = page.efis();
    // Three seconds on the box's clock (an emulated box under load runs slower than the host).
    let second = page.wait_for("3 s of box time", Duration::from_secs(30), |e| {
        num(e, "heading_time_ms") >= num(&first, "heading_time_ms") + 3000.0
    });
    let dt_s = (num(&second, "heading_time_ms") - num(&first, "heading_time_ms")) / 1000.0;
    let mut dh = num(&second, "heading_deg") - num(&first, "heading_deg");
    if dh < -180.0 {
        dh += 360.0;
    }
    let rate = dh / dt_s;
    let expected = turn_rate_deg_s(bank_deg, tas_mps);
    println!("heading: {dh:.2} degrees in {dt_s:.3} s = {rate:.3} °/s, expected {expected:.3} °/s");
    assert!(dt_s >= 2.0, "{first} then {second}");
    assert!(
        (rate - expected).abs() <= expected * 0.02,
        "{rate} °/s, expected {expected} °/s"
    );
    assert!(
        num(&second, "track_points") > num(&first, "track_points"),
        "the track did not grow: {first} then {second}"
    );
}

/// Sends the box "a pause" as a datagram to `box_in` on 127.0.0.1, then checks that the page
/// turns every scheduled type stale (at least 8 rows) within 10 s and shows the box's answer.
pub fn check_a_pause_turns_the_rates_stale(page: &Page, box_in: u16) {
    use aeolus_proto::CrcMode;
    use aeolus_proto::message::{Message, Text};
    let mut datagram = [0u8; 64];
    let n = Message::Command(Text::new("a pause").expect("short"))
        .encode(&mut datagram, CrcMode::Compute)
        .expect("fits");
    std::net::UdpSocket::bind("127.0.0.1:0")
        .expect("a socket")
        .send_to(&datagram[..n], ("127.0.0.1", box_in))
        .expect("send");
    let paused = page.wait_for(
        "every rate stale after a pause",
        Duration::from_secs(10),
        |e| {
            e["live_types"].as_array().is_some_and(Vec::is_empty)
                && e["stale_types"].as_array().is_some_and(|s| s.len() >= 8)
        },
    );
    println!("paused: {paused}");
    let stale_rows = page.eval("document.querySelectorAll('#types tr.stale').length");
    assert!(stale_rows.as_u64() >= Some(8), "{stale_rows}");
    assert_eq!(
        page.eval("document.getElementById('toast').textContent"),
        "AEOLUS paused"
    );
}
