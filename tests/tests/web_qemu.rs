//! `protolink web` on the release firmware in QEMU (lm3s6965evb), in headless Chromium: the
//! firmware's UART0 goes through `protolink bridge` to UDP on 127.0.0.1 (as the box's WiFi
//! side would send it), `protolink web` shows it, and "a pause" goes back to the box through
//! the bridge. The page loads without a console error, its horizon's pixels show the
//! firmware's bank within 1 degree, the heading turns at the rate of the firmware's
//! coordinated turn, the track grows, and the paused box turns every rate stale.
//!
//! Skipped when QEMU is missing (the harness says so), and when chromium is missing outside
//! CI (`CI=true` fails instead). A screenshot is kept in `target/web-qemu.png`.
//! One board: the firmware's telemetry on both boards is the QEMU tests' business
//! (`qemu_firmware.rs`); this test is about the page.

mod harness;

use std::net::UdpSocket;
use std::process::Child;
use std::time::Duration;

use aeolus_proto::CrcMode;
use aeolus_proto::message::{Message, Text};
use flight_sim::FlightParams;
use harness::*;
use protolink_tests::browser::{Page, chromium};

/// Kills a started process when the test ends, passed or not.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn the_page_flies_the_firmwares_turn() {
    let Some(chromium) = chromium() else { return };
    let board = Board::Lm3s6965evb;
    let ports = Ports::WEB.on(board);
    let Some(mut q) = boot(board, ports) else {
        return;
    };
    q.uart0.disconnect();
    let (box_in, box_out, page_port) = (ports.uart(0) + 5, ports.uart(0) + 6, ports.uart(0) + 7);
    let _web = Running(spawn_protolink(&[
        "web".to_string(),
        "--from".into(),
        format!("udp:{box_out}"),
        "--listen".into(),
        format!("127.0.0.1:{page_port}"),
        "--seconds".into(),
        "120".into(),
    ]));
    let _bridge = Running(spawn_protolink(&[
        "bridge".to_string(),
        "--uart".into(),
        format!("tcp:127.0.0.1:{}", ports.uart(0)),
        "--udp-out".into(),
        format!("127.0.0.1:{box_out}"),
        "--udp-in".into(),
        box_in.to_string(),
        "--seconds".into(),
        "120".into(),
    ]));
    // The page server needs a moment to bind.
    let url = format!("http://127.0.0.1:{page_port}/");
    let mut tries = 0;
    while std::net::TcpStream::connect(("127.0.0.1", page_port)).is_err() {
        tries += 1;
        assert!(tries < 200, "protolink web does not listen on {url}");
        std::thread::sleep(Duration::from_millis(50));
    }
    let page = Page::open(&chromium, &url);
    page.wait_for("the first drawn attitude", Duration::from_secs(20), |e| {
        e["roll_deg"].is_number()
            && e["heading_deg"].is_number()
            && e["track_points"].as_u64() > Some(0)
    });

    let bank = f64::from(FlightParams::DEFAULT.bank_deg);
    for _ in 0..3 {
        let h = page.horizon().expect("a sky/ground edge in both columns");
        println!("horizon: {h:?}, firmware bank {bank}");
        assert!((h.measured_deg - bank).abs() <= 1.0, "pixels show {h:?}");
        assert!((h.drawn_deg - bank).abs() <= 1.0, "drawn {h:?}");
        std::thread::sleep(Duration::from_millis(300));
    }

    let first = page.efis();
    std::thread::sleep(Duration::from_secs(3));
    let second = page.efis();
    let num = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    let dt_s = (num(&second, "heading_time_ms") - num(&first, "heading_time_ms")) / 1000.0;
    let mut dh = num(&second, "heading_deg") - num(&first, "heading_deg");
    if dh < -180.0 {
        dh += 360.0;
    }
    let rate = dh / dt_s;
    let tas = f64::from(FlightParams::DEFAULT.airspeed_mps);
    let expected = (9.806_65 * bank.to_radians().tan() / tas).to_degrees();
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
    page.screenshot(&target_dir().join("web-qemu.png"));

    // "a pause" to the box through the bridge: every rate turns stale.
    let mut datagram = [0u8; 64];
    let n = Message::Command(Text::new("a pause").expect("short"))
        .encode(&mut datagram, CrcMode::Compute)
        .expect("fits");
    UdpSocket::bind("127.0.0.1:0")
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
    assert_eq!(
        page.eval("document.getElementById('toast').textContent"),
        "AEOLUS paused"
    );
    let errors = page.errors();
    assert!(errors.is_empty(), "the page logged errors: {errors:#?}");
    drop(page);
    let _ = q.stop();
}
