//! Debian's Chromium, headless, driven over the DevTools protocol (`headless_chrome`, no
//! browser download), for the tests of `protolink web`: `host-tool/tests/all/web.rs` (against
//! `protolink sim`) and `tests/tests/all/web_qemu.rs` (against the firmware in QEMU).
//!
//! [`Page`] records every console error, uncaught exception and failed load the page causes,
//! evaluates expressions, takes screenshots, and measures the horizon's roll from the
//! attitude canvas's pixels ([`Page::horizon`]).

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use headless_chrome::protocol::cdp::Log::LogEntryLevel;
use headless_chrome::protocol::cdp::Page::CaptureScreenshotFormatOption;
use headless_chrome::protocol::cdp::Runtime::ConsoleAPICalledEventTypeOption;
use headless_chrome::protocol::cdp::types::Event;
use headless_chrome::{Browser, LaunchOptions, Tab};
use serde_json::Value;

/// Where Debian's `chromium` package puts the browser.
pub const CHROMIUM: &str = "/usr/bin/chromium";

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

/// One page in a fresh headless Chromium (its own profile directory, removed at the end).
pub struct Page {
    tab: Arc<Tab>,
    errors: Arc<Mutex<Vec<String>>>,
    profile: PathBuf,
    // Dropped last: closing the browser ends the process.
    _browser: Browser,
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
    /// --no-first-run`, a fresh `--user-data-dir`) and opens `url`.
    pub fn open(chromium: &Path, url: &str) -> Page {
        static N: AtomicU32 = AtomicU32::new(0);
        let profile = std::env::temp_dir().join(format!(
            "protolink-chromium-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::SeqCst)
        ));
        let _ = std::fs::remove_dir_all(&profile);
        std::fs::create_dir_all(&profile).expect("a profile directory");
        let args: Vec<&std::ffi::OsStr> = [
            "--disable-gpu",
            "--disable-background-networking",
            "--no-first-run",
            "--disable-dev-shm-usage",
        ]
        .iter()
        .map(std::ffi::OsStr::new)
        .collect();
        let options = LaunchOptions::default_builder()
            .path(Some(chromium.to_path_buf()))
            .headless(true)
            .sandbox(false)
            .window_size(Some((1400, 900)))
            .user_data_dir(Some(profile.clone()))
            .idle_browser_timeout(Duration::from_secs(300))
            .args(args)
            .build()
            .expect("launch options");
        let browser = Browser::new(options).expect("chromium starts");
        let tab = browser.new_tab().expect("a tab");
        tab.set_default_timeout(Duration::from_secs(20));
        let errors = Arc::new(Mutex::new(Vec::new()));
        tab.enable_log().expect("Log domain");
        tab.enable_runtime().expect("Runtime domain");
        let sink = errors.clone();
        tab.add_event_listener(Arc::new(move |event: &Event| {
            let error = match event {
                Event::LogEntryAdded(e) if e.params.entry.level == LogEntryLevel::Error => {
                    Some(format!(
                        "log: {} ({})",
                        e.params.entry.text,
                        e.params.entry.url.clone().unwrap_or_default()
                    ))
                }
                Event::RuntimeExceptionThrown(e) => {
                    let d = &e.params.exception_details;
                    Some(format!(
                        "exception: {} {} at {}:{}",
                        d.text,
                        d.exception
                            .as_ref()
                            .and_then(|x| x.description.clone())
                            .unwrap_or_default(),
                        d.line_number,
                        d.column_number
                    ))
                }
                Event::RuntimeConsoleAPICalled(e)
                    if e.params.Type == ConsoleAPICalledEventTypeOption::Error =>
                {
                    Some(format!(
                        "console.error: {:?}",
                        e.params
                            .args
                            .iter()
                            .map(|a| a.value.clone().or(a.description.clone().map(Value::from)))
                            .collect::<Vec<_>>()
                    ))
                }
                _ => None,
            };
            if let Some(error) = error
                && let Ok(mut errors) = sink.lock()
            {
                errors.push(error);
            }
        }))
        .expect("an event listener");
        tab.navigate_to(url)
            .expect("navigate")
            .wait_until_navigated()
            .expect("the page loads");
        Page {
            tab,
            errors,
            profile,
            _browser: browser,
        }
    }

    /// The value of a JavaScript expression (passed through `JSON.stringify`).
    pub fn eval(&self, expression: &str) -> Value {
        let wrapped = format!("JSON.stringify({expression})");
        let result = self
            .tab
            .evaluate(&wrapped, false)
            .unwrap_or_else(|e| panic!("evaluating {expression}: {e}"));
        match result.value {
            Some(Value::String(json)) => serde_json::from_str(&json).unwrap_or(Value::Null),
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

    /// The console errors, uncaught exceptions and failed loads so far.
    pub fn errors(&self) -> Vec<String> {
        self.errors.lock().map(|e| e.clone()).unwrap_or_default()
    }

    /// A PNG screenshot of the whole window into `path`.
    pub fn screenshot(&self, path: &Path) {
        let png = self
            .tab
            .capture_screenshot(CaptureScreenshotFormatOption::Png, None, None, true)
            .expect("a screenshot");
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

impl Drop for Page {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.profile);
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

/// `GET path` on `addr`: the status code and the body (the server closes every connection).
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
    let _ = s.read_to_end(&mut raw);
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
