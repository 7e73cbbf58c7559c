//! The release firmware in QEMU, driven through the real `protolink` binary, as a person at a
//! desk would: `bridge` between UART0 and UDP on 127.0.0.1, `aydp` on UART1, `aok` on UART2.
//! The harness (QEMU, ports, the firmware build) is `harness/mod.rs`.

use crate::harness::*;
use aeolus_proto::message::{Message, SetTime};
use protolink_tests::aeolus_udp::{App, Received};
use std::net::Shutdown;
use std::time::Duration;

on_every_board!(
    bridge_carries_telemetry_and_commands_over_udp,
    protolink_aydp_set_get_store,
    protolink_aok_get_set_waypoint,
);

/// Runs `protolink ARGS`, asserts a zero exit, returns stdout.
fn protolink_ok(args: &[&str]) -> String {
    succeeded(args, finish(spawn_protolink(args)))
}

/// Asserts that the run of `protolink ARGS` that gave `out` exited 0; its stdout.
fn succeeded(args: &[&str], out: std::process::Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "protolink {args:?} failed ({:?})\nstdout:\n{stdout}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// Boots QEMU and checks the boot TOAST on UART0; `None` when QEMU is not installed.
fn boot_checked(board: Board, ports: Ports) -> Option<Qemu> {
    let mut q = boot(board, ports)?;
    let first = q.uart0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(
        q.uart0.frames[first].toast().as_deref(),
        Some("AEOLUS on"),
        "log: {}",
        q.log().display()
    );
    Some(q)
}

// ------------------------------------------------------------------ bridge

fn bridge_carries_telemetry_and_commands_over_udp(board: Board) {
    let ports = Ports::BRIDGE.on(board);
    let Some(mut q) = boot_checked(board, ports) else {
        return;
    };
    // The bridge takes UART0 from the harness.
    q.uart0.disconnect();
    let in_port = ports.uart(0) + 5;
    let mut udp = App::new(in_port);
    let out_port = udp.port();
    let bridge = spawn_protolink(&[
        "bridge",
        "--uart",
        &format!("tcp:127.0.0.1:{}", ports.uart(0)),
        "--udp-out",
        &format!("127.0.0.1:{out_port}"),
        "--udp-in",
        &in_port.to_string(),
        "--seconds",
        "9",
    ]);

    // 3 s of datagrams: every frame with a good CRC, every telemetry type present.
    udp.read_for(Duration::from_secs(3));
    let n = udp.frames.len();
    println!(
        "3 s through the bridge: {n} frames in {} datagrams",
        udp.datagrams
    );
    for p in &TELEMETRY {
        let count = udp.frames.iter().filter(|f| f.id == p.id).count();
        println!("{:>10}: {count}", p.name);
        assert!(count >= 1, "no {} through the bridge", p.name);
    }
    // At the spec rates 3 s carry about 3,000 frames; allow for the bridge's start. The
    // simulated STM32 falls behind real time on a loaded two-core host and skips late slots,
    // as the box must (`boot_with`), so a quarter of the rate is asked of it.
    let least = if board == Board::Stm32f411 {
        750
    } else {
        1_500
    };
    assert!(n >= least, "only {n} frames in 3 s");
    assert_eq!(udp.datagrams, n, "one frame per datagram (no --pack)");

    // SETTIME and "a pause" as datagrams to the in-port: the answer, then no telemetry.
    let time = SetTime {
        year_since_1900: 126,
        month0: 10,
        day: 21,
        hour: 12,
        minute: 34,
        second: 56,
    };
    udp.send(&Message::SetTime(time));
    udp.command("a pause");
    let ack = udp.read_until_toast(Duration::from_secs(3));
    assert_eq!(udp.frames[ack].toast().as_deref(), Some("AEOLUS paused"));
    udp.read_for(Duration::from_millis(700));
    let during: Vec<&Received> = udp.frames[ack + 1..].iter().collect();
    assert!(during.is_empty(), "sent while paused: {during:?}");

    // "a resume": the answer, then telemetry again.
    udp.command("a resume");
    let ack = udp.read_until_toast(Duration::from_secs(3));
    assert_eq!(udp.frames[ack].toast().as_deref(), Some("AEOLUS resumed"));
    udp.read_for(Duration::from_millis(500));
    let resumed = &udp.frames[ack + 1..];
    // Half a second at half the rate asked above: 125 frames from the lm3s6965evb boards, 62
    // from the simulated STM32 (a CI run saw fewer than 200 from it).
    assert!(
        resumed.len() >= least / 12
            && resumed
                .iter()
                .all(|f| TELEMETRY.iter().any(|p| p.id == f.id)),
        "{} frames after the resume",
        resumed.len()
    );

    // The bridge ends by itself (--seconds) and reports its counters.
    let out = finish(bridge);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "bridge failed: {out:?}");
    println!("{stdout}");
    let counters = stdout
        .lines()
        .find(|l| l.starts_with("bridge: "))
        .expect("the bridge's counters");
    for want in [
        "datagrams_received=3 ",
        "send_errors=0 ",
        "uart_write_errors=0",
    ] {
        assert!(counters.contains(want), "{want} not in {counters}");
    }
    let decoder = stdout
        .lines()
        .find(|l| l.starts_with("uart decoder: "))
        .expect("the decoder's counters");
    assert!(decoder.contains("checksum_errors=0 "), "{decoder}");

    // The firmware's log shows it took the SETTIME and the commands.
    let log = q.stop();
    println!("{log}");
    assert!(
        log.contains("SETTIME 2026-11-21 12:34:56"),
        "SETTIME not in the firmware's log"
    );
    assert!(log.contains("AEOLUS: a pause") && log.contains("AEOLUS: a resume"));
}

// ------------------------------------------------------------------ aydp

fn protolink_aydp_set_get_store(board: Board) {
    let ports = Ports::CLI_AYDP.on(board);
    let Some(mut q) = boot_checked(board, ports) else {
        return;
    };
    // protolink takes UART1 from the harness.
    q.uart1.shutdown(Shutdown::Both).expect("close UART1");
    let to = format!("tcp:127.0.0.1:{}", ports.uart(1));
    let aydp = |args: &[&str]| {
        let mut all = vec!["aydp", "--to", to.as_str()];
        all.extend_from_slice(args);
        protolink_ok(&all)
    };

    // Read-only identity, then the simulated airspeed from its default to 64.5 m/s.
    assert_eq!(
        aydp(&["get", "0x0001", "--as", "char[40]"]),
        "0x0001 char[40] = \"protolink sensor box\"\n"
    );
    assert_eq!(
        aydp(&["get", "0x0110", "--as", "f32"]),
        "0x0110 f32 = 50.0\n"
    );
    // `set` reads the value back and prints what the device holds.
    assert_eq!(
        aydp(&["set", "0x0110", "64.5", "--as", "f32"]),
        "0x0110 f32 = 64.5: confirmed (read back)\n"
    );
    assert_eq!(
        aydp(&["get", "0x0110", "--as", "f32"]),
        "0x0110 f32 = 64.5\n"
    );
    // The element form and the array form on the AEOLUS intervals.
    assert_eq!(
        aydp(&["set", "0x0100[1]", "6", "--as", "u32[6]"]),
        "0x0100 u32[6] = [7, 6, 92, 829, 1000, 1000]: confirmed (read back)\n"
    );
    assert_eq!(
        aydp(&["set", "0x0100", "7,5,92,829,1000,1000", "--as", "u32[6]"]),
        "0x0100 u32[6] = [7, 5, 92, 829, 1000, 1000]: confirmed (read back)\n"
    );
    // A value out of the registry's range is refused by the device, in one sentence.
    let out = finish(spawn_protolink(&[
        "aydp", "--to", &to, "set", "0x0110", "400", "--as", "f32",
    ]));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{err}");
    // One sentence, the last line (a slow box gets a "waiting for the answer" line before it).
    assert!(
        err.lines().last().is_some_and(|l| l.starts_with("error: ")) && !err.contains("panicked"),
        "{err}"
    );

    // In flight a store is refused, and `--verify` says so from the box's store counters, with
    // a non-zero exit.
    let out = finish(spawn_protolink(&["aydp", "--to", &to, "store", "--verify"]));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("refused") && err.contains("flying"), "{err}");

    // Land ("a pause"), store (written, then unchanged: nothing to write), then "a reboot" over
    // AEOLUS: the stored airspeed is back after the boot.
    q.uart0.land();
    assert!(aydp(&["store"]).starts_with("store configuration: unconfirmed"));
    assert!(
        aydp(&["store", "--verify"]).starts_with("store configuration: confirmed (unchanged"),
        "the plain store above wrote this configuration already"
    );
    assert_eq!(
        aydp(&["set", "0x0110", "64.0", "--as", "f32"]),
        "0x0110 f32 = 64.0: confirmed (read back)\n"
    );
    assert!(aydp(&["store", "--verify"]).starts_with("store configuration: confirmed (written"));
    q.uart0.command("a reboot");
    let seen = q.uart0.frames.len();
    let again = q.uart0.read_until(Duration::from_secs(10), |f| {
        f.toast().as_deref() == Some("AEOLUS on")
    });
    assert!(again >= seen, "a second boot TOAST");
    assert_eq!(
        aydp(&["get", "0x0110", "--as", "f32"]),
        "0x0110 f32 = 64.0\n"
    );
    q.stop();
}

// ------------------------------------------------------------------ aok

fn protolink_aok_get_set_waypoint(board: Board) {
    let ports = Ports::CLI_AOK.on(board);
    let Some(mut q) = boot_checked(board, ports) else {
        return;
    };
    q.uart2.shutdown(Shutdown::Both).expect("close UART2");
    // Nobody needs UART0 here: let QEMU drop what it sends.
    q.uart0.disconnect();
    let to = format!("tcp:127.0.0.1:{}", ports.uart(2));
    let aok = |args: &[&str]| {
        let mut all = vec!["aok", "--to", to.as_str()];
        all.extend_from_slice(args);
        // Once more when the box did not answer, for the reason of `harness::aok_once_more`:
        // the STM32's emulated USART takes one byte at a time, and under the parallel test load
        // QEMU can hand one write's bytes over further apart than the box's burst gap. Each
        // request here sets or reads a value, so the second asks the same; a box that never
        // answers fails both.
        let first = finish(spawn_protolink(&all));
        let unanswered = first.status.code() == Some(1)
            && String::from_utf8_lossy(&first.stderr).contains("no answer to");
        if unanswered {
            return protolink_ok(&all);
        }
        succeeded(&all, first)
    };

    assert_eq!(aok(&["get", "12"]), "parameter 12 = 0\n");
    assert_eq!(
        aok(&["set", "12", "1500"]),
        "parameter 12 = 1500: confirmed (acked 'O')\n"
    );
    assert_eq!(aok(&["get", "12"]), "parameter 12 = 1500\n");
    // Parameter 20 cannot be set in flight: the device's 'I', as one sentence and status 1.
    let out = finish(spawn_protolink(&["aok", "--to", &to, "set", "20", "7"]));
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: the device refused setting parameter 20 in flight ('I')\n"
    );

    let wp = "waypoint 1: longitude=237512345 latitude=480012345 \
              action1=hold-and-climb:15 action2=set-fly-speed:250";
    assert_eq!(
        aok(&[
            "waypoint",
            "set",
            "1",
            "237512345",
            "480012345",
            "--action1",
            "hold-and-climb:15",
            "--action2",
            "set-fly-speed:250",
        ]),
        format!("{wp}: confirmed (acked 'O')\n")
    );
    assert_eq!(aok(&["waypoint", "get", "1"]), format!("{wp}\n"));
    q.stop();
}
