//! `protolink web` end to end: `protolink sim --bank 30` sends telemetry over loopback UDP,
//! `protolink web` serves the page, and Debian's Chromium (headless, over the DevTools
//! protocol) shows it. The page must load without a console error, its horizon's pixels must
//! show the simulated bank within 1 degree, its heading must turn at the rate the bank and the
//! airspeed give, its ground track must grow, and pausing the box ("a pause") must turn every
//! rate stale. The server's limits and `/api/state` are tested without a browser.
//!
//! Without chromium the browser test is skipped with a message, except under CI (`CI=true`),
//! where a missing chromium fails it. A screenshot is kept in `target/web-sim.png`.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::process::Child;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::common::*;
use protolink_tests::browser::{
    Page, STATE_FIELDS, check_a_pause_turns_the_rates_stale, check_the_turn, chromium, http_get,
};
use serde_json::Value;

/// Kills a started process when the test ends, passed or not.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts `protolink sim --bank 30` sending to `out`, taking commands on `cmd`.
fn sim(out: u16, cmd: u16) -> Running {
    Running(spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{out}"),
        "--udp-in",
        &cmd.to_string(),
        "--bank",
        "30",
        "--seconds",
        "120",
    ]))
}

/// Starts `protolink web --from FROM --listen 127.0.0.1:0` and returns it with the address it
/// printed.
fn web(from: &str) -> (Running, SocketAddr) {
    web_with(from, &[])
}

/// [`web`] with more arguments.
fn web_with(from: &str, more: &[&str]) -> (Running, SocketAddr) {
    let mut args = vec![
        "web",
        "--from",
        from,
        "--listen",
        "127.0.0.1:0",
        "--seconds",
        "120",
    ];
    args.extend_from_slice(more);
    let mut child = spawn(&args);
    let stderr = child.stderr.take().expect("stderr");
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let running = Running(child);
    let line = rx
        .recv_timeout(Duration::from_secs(30))
        .expect("protolink web prints its address");
    let addr = line
        .strip_prefix("web: http://")
        .and_then(|l| l.split('/').next())
        .and_then(|a| a.parse().ok())
        .unwrap_or_else(|| panic!("no address in {line:?}"));
    (running, addr)
}

/// `/api/state` as JSON, once `ready` holds (checked every 100 ms, for at most 20 s).
fn state_when(addr: SocketAddr, what: &str, ready: impl Fn(&Value) -> bool) -> Value {
    let started = Instant::now();
    loop {
        let (status, body) = http_get(addr, "/api/state");
        if status == 200
            && let Ok(v) = serde_json::from_str::<Value>(&body)
            && ready(&v)
        {
            return v;
        }
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "{what}: not within 20 s; last answer {status}: {body}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"))
}

#[test]
fn the_page_flies_the_simulated_turn_in_chromium() {
    let Some(chromium) = chromium() else { return };
    let (out, cmd) = (17_491, 17_492);
    let (_web, addr) = web(&format!("udp:{out}"));
    let _sim = sim(out, cmd);
    let page = Page::open(&chromium, &format!("http://{addr}/"));

    // 30 degrees of bank at the sim's default airspeed (the firmware's, 50 m/s): 6.5 °/s.
    let tas = f64::from(flight_sim::FlightParams::DEFAULT.airspeed_mps);
    check_the_turn(&page, 30.0, tas);

    // Everything else is on the page: identity, error counters, message rows.
    let text = page.eval("document.body.innerText");
    let text = text.as_str().unwrap_or_default();
    for want in [
        "AEOLUS-SENSE",
        "ATTITUDE",
        "PRESSURE",
        "GPS",
        "CRC errors",
        "AEOLUS on",
    ] {
        assert!(text.contains(want), "{want:?} not on the page:\n{text}");
    }
    page.screenshot(&target_dir().join("web-sim.png"));

    // "a pause": the box stops sending; every telemetry rate turns stale.
    check_a_pause_turns_the_rates_stale(&page, cmd);
    page.screenshot(&target_dir().join("web-sim-paused.png"));

    let errors = page.errors();
    assert!(errors.is_empty(), "the page logged errors: {errors:#?}");
}

/// `protolink web --units aviation` on `protolink sim --climb 2.5 --bank 20`: the tapes show
/// knots and feet, the vertical speed indicator about 490 ft/min (2.5 m/s is 492.1 ft/min),
/// the pitch ladder the climb's flight path angle, and the altitude tape climbs.
#[test]
fn aviation_units_on_a_climbing_turn_in_chromium() {
    let Some(chromium) = chromium() else { return };
    let (out, cmd) = (17_731, 17_732);
    let (_web, addr) = web_with(&format!("udp:{out}"), &["--units", "aviation"]);
    let _sim = Running(spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{out}"),
        "--udp-in",
        &cmd.to_string(),
        "--climb",
        "2.5",
        "--bank",
        "20",
        "--seconds",
        "120",
    ]));
    let page = Page::open(&chromium, &format!("http://{addr}/"));
    let number = |e: &Value, k: &str| e[k].as_f64();
    let first = page.wait_for(
        "a vertical speed on the page",
        Duration::from_secs(20),
        |e| number(e, "vertical_speed_shown").is_some() && number(e, "altitude_shown").is_some(),
    );
    for (key, unit) in [
        ("units", "aviation"),
        ("speed_unit", "kt"),
        ("altitude_unit", "ft"),
        ("vertical_speed_unit", "ft/min"),
    ] {
        assert_eq!(first[key], unit, "{key}: {first}");
    }
    // The sim's true airspeed, 50 m/s, is 97.19 kt; the tape shows the indicated airspeed,
    // lower by the square root of the density ratio at the pressure altitude (the ISA,
    // written here).
    let tas = number(&first, "tas_shown").expect("true airspeed shown");
    assert!((tas - 97.19).abs() < 0.05, "true airspeed {tas} kt");
    let h = number(&first, "pressure_altitude_m").expect("pressure altitude");
    let kelvin = 288.15 - 0.0065 * h;
    let density = 101_325.0 * (kelvin / 288.15).powf(5.255_88) / (287.05 * kelvin);
    let want = 97.19 * (density / 1.225).sqrt();
    let kt = number(&first, "airspeed_shown").expect("airspeed drawn");
    assert!(
        (kt - want).abs() < 0.05,
        "indicated airspeed {kt} kt, not {want:.2} kt"
    );
    // Feet on the tape: the GPS altitude (m) over 0.3048.
    let m = number(&first, "gps_altitude_m").expect("GPS altitude");
    let ft = number(&first, "altitude_shown").expect("altitude drawn");
    assert!((ft - m / 0.3048).abs() < 0.01, "{ft} ft for {m} m");
    let caption = page.eval("document.querySelector('.pfd').innerText");
    let caption = caption.as_str().unwrap_or_default();
    for want in [
        "indicated airspeed kt",
        "altitude ft",
        "vertical speed ft/min",
    ] {
        assert!(caption.contains(want), "{want:?} not in {caption:?}");
    }
    // About 490 ft/min, over several frames.
    for _ in 0..5 {
        let vs = number(&page.efis(), "vertical_speed_shown").expect("vertical speed drawn");
        assert!((vs - 492.1).abs() < 10.0, "vertical speed {vs} ft/min");
        std::thread::sleep(Duration::from_millis(200));
    }
    // The nose is up by the flight path angle, asin(2.5 / 50) = 2.87°.
    let pitch = number(&page.efis(), "pitch_deg").expect("pitch drawn");
    assert!((pitch - 2.866).abs() < 0.05, "pitch {pitch}°");
    // The tape climbs: 2.5 m/s for 2 s of the box's clock is 16.4 ft.
    let climbed = page.wait_for("the altitude tape climbs", Duration::from_secs(10), |e| {
        number(e, "altitude_shown").is_some_and(|a| a > ft + 16.0)
    });
    assert!(number(&climbed, "altitude_shown").unwrap_or(0.0) < ft + 400.0);
    page.screenshot(&target_dir().join("web-sim-aviation.png"));
    let errors = page.errors();
    assert!(errors.is_empty(), "the page logged errors: {errors:#?}");
}

#[test]
fn api_state_has_every_field() {
    let (out, cmd) = (17_493, 17_494);
    let (_web, addr) = web(&format!("udp:{out}"));
    let _sim = sim(out, cmd);
    let v = state_when(addr, "a GPS track and the box's identity", |v| {
        v["track"].as_array().is_some_and(|t| !t.is_empty()) && v["info"].is_object()
    });
    for field in STATE_FIELDS {
        assert!(v.get(field).is_some(), "no {field} in {v}");
    }
    assert!(
        (v["attitude"]["roll_deg"].as_f64().unwrap() - 30.0).abs() < 0.01,
        "{v}"
    );
    assert_eq!(v["info"]["model"], "AEOLUS-SENSE");
    assert_eq!(v["toast"], "AEOLUS on");
    assert!(v["air"]["pressure_altitude_m"].is_number());
    assert!(v["gps"]["altitude_m"].is_number());
    assert!(v["wind"]["direction_deg"].is_number());
    let attitude = v["types"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["name"] == "ATTITUDE")
        .expect("an ATTITUDE row");
    for field in [
        "id",
        "count",
        "rate_hz",
        "interval_box_ms",
        "intervals_ms",
        "stale",
        "periodic",
        "age_s",
    ] {
        assert!(attitude.get(field).is_some(), "no {field} in {attitude}");
    }
    assert_eq!(attitude["stale"], false);
    assert!(attitude["rate_hz"].as_f64().unwrap() > 50.0, "{attitude}");
    for field in [
        "checksum_errors",
        "bytes_discarded",
        "malformed",
        "truncated",
    ] {
        assert_eq!(v["errors"][field], 0, "{field}: {v}");
    }
}

#[test]
fn nothing_on_the_endpoint_says_no_data() {
    let (_web, addr) = web("udp:17995");
    let v = state_when(addr, "NO DATA", |v| v["no_data"].is_string());
    assert!(
        v["no_data"]
            .as_str()
            .unwrap()
            .contains("udp:127.0.0.1:17995"),
        "{v}"
    );
    assert_eq!(v["bytes"], 0);
}

/// Sends `raw` and returns the status line of the answer.
fn status_of(addr: SocketAddr, raw: &[u8]) -> String {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let _ = s.write_all(raw);
    let mut answer = Vec::new();
    let _ = s.read_to_end(&mut answer);
    String::from_utf8_lossy(&answer)
        .lines()
        .next()
        .unwrap_or_default()
        .to_owned()
}

#[test]
fn the_server_is_read_only_and_bounded() {
    let (_web, addr) = web("udp:17996");
    assert_eq!(http_get(addr, "/").0, 200);
    assert_eq!(http_get(addr, "/app.js").0, 200);
    assert_eq!(http_get(addr, "/style.css").0, 200);
    assert_eq!(http_get(addr, "/nope").0, 404);
    assert_eq!(http_get(addr, "/../../etc/passwd").0, 404);
    assert!(
        status_of(
            addr,
            b"POST /api/state HTTP/1.1\r\nContent-Length: 2\r\n\r\nhi"
        )
        .contains(" 405 ")
    );
    assert!(status_of(addr, b"garbage\r\n\r\n").contains(" 400 "));
    // DNS rebinding: another name for 127.0.0.1 is refused; an address or localhost is not.
    assert!(
        status_of(
            addr,
            b"GET /api/state HTTP/1.1\r\nHost: evil.example:8080\r\n\r\n"
        )
        .contains(" 421 ")
    );
    assert!(status_of(addr, b"GET / HTTP/1.1\r\nHost: localhost:8080\r\n\r\n").contains(" 200 "));
    // A request head past the limit: refused, never read on without bound.
    let mut long = b"GET / HTTP/1.1\r\nX-Long: ".to_vec();
    long.extend(std::iter::repeat_n(b'a', 64 * 1024));
    long.extend(b"\r\n\r\n");
    assert!(status_of(addr, &long).contains(" 431 "));
    let mut many = b"GET / HTTP/1.1\r\n".to_vec();
    for i in 0..100 {
        many.extend(format!("X-{i}: 1\r\n").as_bytes());
    }
    many.extend(b"\r\n");
    assert!(status_of(addr, &many).contains(" 431 "));

    // A client that connects and says nothing holds nobody up.
    let _silent = TcpStream::connect(addr).unwrap();
    assert_eq!(http_get(addr, "/api/state").0, 200);

    // Eight live clients from eight addresses are served (each read to its end by a thread of
    // its own); a ninth, from an address of its own, is refused and counted: no address holds
    // more than its share.
    let mut streams = Vec::new();
    for n in 0..8 {
        let mut s = connect_from([127, 0, 1, n], addr).unwrap();
        s.write_all(b"GET /events HTTP/1.1\r\n\r\n").unwrap();
        s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
        let mut head = [0u8; 15];
        s.read_exact(&mut head).unwrap();
        assert_eq!(&head, b"HTTP/1.1 200 OK");
        let mut reader = s.try_clone().unwrap();
        std::thread::spawn(move || std::io::copy(&mut reader, &mut std::io::sink()));
        streams.push(s);
    }
    let ninth = status_of(addr, b"GET /events HTTP/1.1\r\n\r\n");
    assert!(ninth.contains(" 503 "), "{ninth}");
    let v = state_when(addr, "the counters", |v| v["server"]["refused"] == 1);
    assert_eq!(v["server"]["clients"], 8, "{v}");
    // The others are still served; a closed stream frees its place.
    let closed = streams.pop().unwrap();
    closed.shutdown(std::net::Shutdown::Both).unwrap();
    state_when(addr, "a freed place", |v| v["server"]["clients"] == 7);
    let mut s = TcpStream::connect(addr).unwrap();
    s.write_all(b"GET /events HTTP/1.1\r\n\r\n").unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut got = vec![0u8; 4096];
    let n = s.read(&mut got).unwrap();
    assert!(got[..n].starts_with(b"HTTP/1.1 200 OK"));
    // A live update: one whole state per event.
    let mut text = String::from_utf8_lossy(&got[..n]).into_owned();
    let started = Instant::now();
    while !text.contains("\n\ndata: {") || !text.trim_end().ends_with('}') {
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "no event in {text}"
        );
        let n = s.read(&mut got).unwrap();
        text.push_str(&String::from_utf8_lossy(&got[..n]));
    }
    let event = text
        .split("data: ")
        .nth(1)
        .unwrap()
        .split("\n\n")
        .next()
        .unwrap();
    let v: Value = serde_json::from_str(event).expect("an event is one JSON state");
    assert!(v.get("server").is_some());
}

#[test]
fn listen_is_checked_and_errors_are_one_sentence() {
    let err = usage_failed(&run(&[
        "web",
        "--from",
        "udp:17997",
        "--listen",
        "localhost:8080",
    ]));
    assert!(err.contains("IP:PORT"), "{err}");
    usage_failed(&run(&[
        "web",
        "--from",
        "udp:17997",
        "--listen",
        "127.0.0.1:99999",
    ]));
    // The address is taken.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port();
    let err = failed(&run(&[
        "web",
        "--from",
        "udp:17997",
        "--listen",
        &format!("127.0.0.1:{port}"),
        "--seconds",
        "5",
    ]));
    assert!(err.contains(&format!("127.0.0.1:{port}")), "{err}");
}

#[test]
fn seconds_ends_it_with_the_counters() {
    let out = ok(&run(&[
        "web",
        "--from",
        "udp:17998",
        "--listen",
        "127.0.0.1:0",
        "--seconds",
        "1",
    ]));
    assert!(out.starts_with("web: "), "{out}");
    assert!(out.contains("refused=0"), "{out}");
}

/// A TCP connection to `to` from the local address `from` (another loopback address stands
/// for another machine).
fn connect_from(from: [u8; 4], to: SocketAddr) -> std::io::Result<TcpStream> {
    use socket2::{Domain, Socket, Type};
    let s = Socket::new(Domain::IPV4, Type::STREAM, None)?;
    s.bind(&SocketAddr::from((from, 0)).into())?;
    s.connect_timeout(&to.into(), Duration::from_secs(2))?;
    Ok(s.into())
}

/// The first line of the answer to `request` sent from `from`, and whether a live update
/// (`data: {`) followed within 5 s.
fn ask_from(from: [u8; 4], to: SocketAddr, request: &str) -> (String, bool) {
    let Ok(mut s) = connect_from(from, to) else {
        return ("no connection".into(), false);
    };
    let _ = s.set_read_timeout(Some(Duration::from_secs(5)));
    if s.write_all(request.as_bytes()).is_err() {
        return ("write failed".into(), false);
    }
    let mut text = String::new();
    let mut buf = [0u8; 4096];
    let started = Instant::now();
    while started.elapsed() < Duration::from_secs(5) && !text.contains("\ndata: {") {
        match s.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => text.push_str(&String::from_utf8_lossy(&buf[..n])),
        }
    }
    let status = text.lines().next().unwrap_or("nothing").to_owned();
    (status, text.contains("\ndata: {"))
}

/// Slow clients on another machine (127.0.0.2) that send their request heads a line at a
/// time and reconnect whenever they are closed, and pages of another site (127.0.0.3) asking
/// for the live stream: a normal page load and its stream (127.0.0.1) are still served, the
/// other site is refused with 403, and both are counted.
#[test]
fn hostile_peers_leave_a_normal_page_and_its_stream_served() {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    let (_web, addr) = web("udp:17994");
    let stop = Arc::new(AtomicBool::new(false));
    let slow_connections = Arc::new(AtomicU64::new(0));
    let mut threads = Vec::new();
    for _ in 0..30 {
        let (stop, count) = (stop.clone(), slow_connections.clone());
        threads.push(std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                let Ok(mut s) = connect_from([127, 0, 0, 2], addr) else {
                    std::thread::sleep(Duration::from_millis(50));
                    continue;
                };
                count.fetch_add(1, Ordering::Relaxed);
                let mut ok = s
                    .write_all(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n")
                    .is_ok();
                while ok && !stop.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(200));
                    ok = s.write_all(b"X-Slow: 1\r\n").is_ok();
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        }));
    }
    let cross = "GET /events HTTP/1.1\r\nHost: 127.0.0.1\r\nOrigin: http://evil.example\r\n\
                 Sec-Fetch-Site: cross-site\r\nSec-Fetch-Mode: cors\r\nSec-Fetch-Dest: empty\r\n\r\n";
    let cross_site: Vec<_> = (0..8)
        .map(|_| std::thread::spawn(move || ask_from([127, 0, 0, 3], addr, cross)))
        .collect();
    std::thread::sleep(Duration::from_secs(3));
    // The page and its stream, ten times over five seconds, while the slow clients keep at it.
    let page = format!("GET / HTTP/1.1\r\nHost: {addr}\r\nSec-Fetch-Site: none\r\n\r\n");
    let script =
        format!("GET /app.js HTTP/1.1\r\nHost: {addr}\r\nSec-Fetch-Site: same-origin\r\n\r\n");
    let events =
        format!("GET /events HTTP/1.1\r\nHost: {addr}\r\nSec-Fetch-Site: same-origin\r\n\r\n");
    let mut failures = Vec::new();
    for _ in 0..10 {
        for request in [&page, &script] {
            let (status, _) = ask_from([127, 0, 0, 1], addr, request);
            if !status.contains(" 200 ") {
                failures.push(status);
            }
        }
        let (status, live) = ask_from([127, 0, 0, 1], addr, &events);
        if !(status.contains(" 200 ") && live) {
            failures.push(format!("{status} (live update: {live})"));
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    stop.store(true, Ordering::Relaxed);
    for t in threads {
        let _ = t.join();
    }
    assert!(
        failures.is_empty(),
        "{} of 30 normal requests failed: {failures:?}",
        failures.len()
    );
    for t in cross_site {
        let (status, live) = t.join().unwrap();
        assert!(
            status.contains(" 403 ") && !live,
            "cross-site stream: {status}"
        );
    }
    let state = state_when(addr, "the counters", |v| v["server"]["cross_site"] == 8);
    let server = &state["server"];
    assert!(
        server["refused"].as_u64().unwrap() > 0,
        "the slow peer's connections beyond its share are refused: {server}"
    );
    assert!(
        slow_connections.load(Ordering::Relaxed) > 12,
        "the slow clients kept at it"
    );
}

/// A live-update stream asked for from `from`, its status line read: the stream stays open,
/// unread from here on (a client that takes nothing), until it is dropped.
fn stream_from(from: [u8; 4], to: SocketAddr) -> (TcpStream, String) {
    let mut s = connect_from(from, to).expect("connect");
    s.write_all(b"GET /events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
        .unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let mut head = [0u8; 15];
    let status = match s.read_exact(&mut head) {
        Ok(()) => String::from_utf8_lossy(&head).into_owned(),
        Err(e) => e.to_string(),
    };
    (s, status)
}

/// Eight streams from another address, read or never read, cannot hold the user's place: the
/// newest of a crowded address takes its oldest's, and the user's page gets its stream at once.
#[test]
fn another_address_cannot_hold_the_users_stream() {
    let (_web, addr) = web("udp:17981");
    for read in [false, true] {
        let crowd: Vec<_> = (0..8)
            .map(|_| {
                let (s, status) = stream_from([127, 0, 0, 2], addr);
                assert_eq!(status, "HTTP/1.1 200 OK");
                if read {
                    let mut reader = s.try_clone().unwrap();
                    std::thread::spawn(move || std::io::copy(&mut reader, &mut std::io::sink()));
                }
                s
            })
            .collect();
        let events = format!("GET /events HTTP/1.1\r\nHost: {addr}\r\n\r\n");
        let (status, live) = ask_from([127, 0, 0, 1], addr, &events);
        assert!(
            status.contains(" 200 ") && live,
            "the user's stream beside 8 {} from another address: {status}",
            if read {
                "readers"
            } else {
                "clients that never read"
            }
        );
        for s in crowd {
            let _ = s.shutdown(std::net::Shutdown::Both);
        }
        state_when(addr, "every stream gone", |v| v["server"]["clients"] == 0);
    }
    // Of each eight, the third to the eighth took the place of an older one.
    let v = state_when(addr, "the counters", |v| v["server"]["replaced"] == 12);
    assert_eq!(v["server"]["refused"], 0, "{v}");
}

/// The page's stream, refused while every place is held by other addresses, comes back by
/// itself once one is free; meanwhile the page polls the state.
#[test]
fn the_page_comes_back_after_its_stream_is_refused_in_chromium() {
    let Some(chromium) = chromium() else { return };
    let (out, cmd) = (17_982, 17_983);
    let (_web, addr) = web(&format!("udp:{out}"));
    let _sim = sim(out, cmd);
    // Every place held: eight other addresses, one stream each, reading.
    let held: Vec<_> = (0..8)
        .map(|n| {
            let (s, status) = stream_from([127, 0, 2, n], addr);
            assert_eq!(status, "HTTP/1.1 200 OK");
            let mut reader = s.try_clone().unwrap();
            std::thread::spawn(move || std::io::copy(&mut reader, &mut std::io::sink()));
            s
        })
        .collect();
    let page = Page::open(&chromium, &format!("http://{addr}/"));
    let efis = page.wait_for(
        "the state polled while refused",
        Duration::from_secs(20),
        |e| e["polled"].as_u64() > Some(2) && e["connected"] == false && e["roll_deg"].is_number(),
    );
    let badge = page.eval("document.getElementById('link').textContent");
    assert!(
        badge
            .as_str()
            .unwrap_or_default()
            .starts_with("refused: retrying"),
        "{badge} ({efis})"
    );
    let v = state_when(addr, "the refusal counted", |v| {
        v["server"]["refused"].as_u64() > Some(0)
    });
    assert_eq!(v["server"]["clients"], 8, "{v}");
    for s in held {
        let _ = s.shutdown(std::net::Shutdown::Both);
    }
    // The retries back off from 1 s to at most 30 s: the next one comes within 30 s.
    let efis = page.wait_for("the stream back", Duration::from_secs(40), |e| {
        e["connected"] == true && e["stream_retries"].as_u64() > Some(0)
    });
    let frames = efis["frames"].as_u64().unwrap_or_default();
    page.wait_for("live updates again", Duration::from_secs(10), |e| {
        e["frames"].as_u64() > Some(frames + 5)
    });
    let badge = page.eval("document.getElementById('link').textContent");
    assert_eq!(badge, "live");
    // The only failures the page saw are its refused streams.
    for error in page.errors() {
        let refused = ["/events", "503", "EventSource"]
            .iter()
            .any(|w| error.contains(w));
        assert!(refused, "{error}");
    }
}
