//! `protolink web` on the release firmware in QEMU (every board), in headless Chromium: the
//! firmware's UART0 goes through `protolink bridge` to UDP on 127.0.0.1 (as the box's WiFi
//! side would send it), `protolink web` shows it, and "a pause" goes back to the box through
//! the bridge. The page loads without a console error, its horizon's pixels show the
//! firmware's bank within 1 degree, the heading turns at the rate of the firmware's
//! coordinated turn, the track grows, and the paused box turns every rate stale.
//!
//! Skipped when QEMU is missing (the harness says so), and when chromium is missing outside
//! CI (`CI=true` fails instead). A screenshot is kept in `target/web-qemu-BOARD.png`.

use std::process::Child;
use std::time::Duration;

use crate::harness::*;
use flight_sim::FlightParams;
use protolink_tests::browser::{
    Page, check_a_pause_turns_the_rates_stale, check_the_turn, chromium,
};

/// Kills a started process when the test ends, passed or not.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

on_every_board!(the_page_flies_the_firmwares_turn);

fn the_page_flies_the_firmwares_turn(board: Board) {
    let Some(chromium) = chromium() else { return };
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
    // The firmware's default flight (sensor_box::Settings::default()).
    let p = FlightParams::DEFAULT;
    check_the_turn(&page, f64::from(p.bank_deg), f64::from(p.airspeed_mps));
    page.screenshot(&target_dir().join(format!("web-qemu-{}.png", board.machine())));

    // "a pause" to the box through the bridge: every rate turns stale.
    check_a_pause_turns_the_rates_stale(&page, box_in);
    let errors = page.errors();
    assert!(errors.is_empty(), "the page logged errors: {errors:#?}");
    drop(page);
    let _ = q.stop();
}
