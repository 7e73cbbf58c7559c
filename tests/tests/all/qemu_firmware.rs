//! The release sensor-box firmware in QEMU, talked to directly over its three UART sockets
//! with the protocol crates (the harness: `harness/mod.rs`; the same firmware driven through
//! `protolink`: `protolink_e2e.rs`).

use crate::harness::*;
use std::time::{Duration, Instant};

on_every_board!(
    aeolus_telemetry_crc_rates_and_commands,
    aydp_setting_survives_store_and_reboot,
    aok_parameter_and_waypoint,
);

/// Tolerance on each type's mean interval, (last - first) / (n - 1) from the frames'
/// timestamps: the issue's ±2 %. The firmware schedules without drift on its millisecond
/// clock, so the mean only moves when QEMU (a host process) is descheduled long enough for
/// the bounded catch-up to drop a due instant; a frame lost on the way would show up the same.
const RATE_TOLERANCE: f64 = 0.02;

fn aeolus_telemetry_crc_rates_and_commands(board: Board) {
    // The simulated STM32 under -icount: its clock then follows its instructions, not the
    // host's speed (see `boot_with`); the lm3s keeps real time on its own.
    let Some(mut q) = boot_with(board, Ports::AEOLUS.on(board), board == Board::Stm32f411) else {
        return;
    };
    let log = q.log().display().to_string();
    let u0 = &mut q.uart0;

    // 1. The boot TOAST comes first, then 3 s of telemetry.
    let first = u0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(
        u0.frames[first].toast().as_deref(),
        Some("AEOLUS on"),
        "log: {log}"
    );
    // 3 s of the box's own clock (on the icount board that takes longer in host time).
    let start = u0.read_until(Duration::from_secs(10), Frame::is_telemetry);
    let t0 = u0.frames[start].timestamp().unwrap_or_default();
    let host_start = Instant::now();
    u0.read_until(Duration::from_secs(30), |f| {
        f.timestamp().is_some_and(|t| t >= t0 + 3_000.0)
    });
    // The box's pace against the host's clock (1.0 in real time; under icount it runs slower
    // while busy): host-timed waits below are judged in box time at this pace.
    let pace = (3_000.0 / host_start.elapsed().as_secs_f64() / 1_000.0).min(1.0);

    // Every frame's CRC checked (strict decoder): nothing rejected, nothing skipped.
    let s = u0.stats();
    println!(
        "3 s of UART0: {} bytes, {} frames, {s:?}",
        u0.bytes,
        u0.frames.len()
    );
    assert_eq!(s.frames_ok as usize, u0.frames.len());
    assert_eq!(
        (
            s.checksum_errors,
            s.missing_crc,
            s.frames_no_crc,
            s.overflows,
            s.too_short,
            s.bad_escapes
        ),
        (0, 0, 0, 0, 0, 0)
    );
    assert_eq!(s.bytes_discarded, 0);

    // Per-type rates from the timestamps.
    for p in TELEMETRY.iter().filter(|p| p.id != 51) {
        let ts: Vec<f64> = u0
            .frames
            .iter()
            .filter(|f| f.id == p.id)
            .filter_map(Frame::timestamp)
            .collect();
        assert!(ts.len() >= 3, "{}: only {} frames", p.name, ts.len());
        assert!(
            ts.windows(2).all(|w| w[1] > w[0]),
            "{}: timestamps go back",
            p.name
        );
        let mean = (ts[ts.len() - 1] - ts[0]) / (ts.len() - 1) as f64;
        println!(
            "{:>10}: {:4} frames, mean interval {mean:8.3} ms",
            p.name,
            ts.len()
        );
        assert!(
            (mean - p.interval_ms).abs() <= RATE_TOLERANCE * p.interval_ms,
            "{}: mean interval {mean} ms, spec {} ms",
            p.name,
            p.interval_ms
        );
    }
    let info = u0.frames.iter().filter(|f| f.id == 51).count();
    assert!((3..=4).contains(&info), "AEOLUSINFO: {info} in 3 s");
    let span = |frames: &[Frame]| {
        let ts: Vec<f64> = frames.iter().filter_map(Frame::timestamp).collect();
        ts.iter().cloned().fold(f64::MIN, f64::max) - ts.iter().cloned().fold(f64::MAX, f64::min)
    };
    assert!(
        span(&u0.frames) >= 2_500.0,
        "telemetry flowed for the whole capture"
    );

    // 2. No received byte is lost while telemetry runs at full rate: 40 commands (560 bytes,
    //    more than the QEMU board's 255-byte RX queue, whose PL011 holds bytes back while it is
    //    full; within the STM32 board's 1 KiB one, as its USART cannot hold bytes back; in one
    //    write, or at the line rate on the -icount board) are all answered, in order.
    let mark = u0.frames.len();
    let burst: Vec<String> = (0..40).map(|i| format!("a test {i:02}")).collect();
    if board == Board::Stm32f411 {
        // Under -icount the USART model takes each byte as soon as the last one is read, at
        // the host's speed while the box runs slower: a burst no wire could deliver. Sent at
        // half the line rate of the real part (921 600 Bd, 14-byte commands) in the box's
        // clock at its pace measured above (the pace drops further while it receives).
        let per_command = Duration::from_secs_f64(2.0 * 14.0 * 10.0 / 921_600.0 / pace);
        for c in &burst {
            u0.queue_command(c);
            u0.flush_commands();
            std::thread::sleep(per_command);
        }
    } else {
        for c in &burst {
            u0.queue_command(c);
        }
        u0.flush_commands();
    }
    let answers =
        |frames: &[Frame]| -> Vec<String> { frames.iter().filter_map(Frame::toast).collect() };
    // 5 s of the box's clock at its measured pace (at most 30 s of host time).
    let deadline = Instant::now() + Duration::from_secs_f64((5.0 / pace).min(30.0));
    while answers(&u0.frames[mark..]).len() < burst.len() && Instant::now() < deadline {
        u0.read_for(Duration::from_millis(50));
    }
    let want: Vec<String> = burst
        .iter()
        .map(|c| format!("unknown command: {c}"))
        .collect();
    assert_eq!(answers(&u0.frames[mark..]), want);

    // 3. "a pause": the answer, then no telemetry at all.
    let last_before = u0
        .frames
        .iter()
        .filter_map(Frame::timestamp)
        .fold(0.0, f64::max);
    u0.command("a pause");
    let ack = u0.read_until(Duration::from_secs(2), |f| f.toast().is_some());
    assert_eq!(u0.frames[ack].toast().as_deref(), Some("AEOLUS paused"));
    u0.read_for(Duration::from_millis(500));
    let after: Vec<&Frame> = u0.frames[ack + 1..].iter().collect();
    assert!(after.is_empty(), "sent while paused: {after:?}");

    // An unknown command is answered, and changes nothing.
    u0.command("a hello");
    let ack = u0.read_until(Duration::from_secs(2), |f| f.toast().is_some());
    assert_eq!(
        u0.frames[ack].toast().as_deref(),
        Some("unknown command: a hello")
    );
    u0.read_for(Duration::from_millis(200));
    assert_eq!(u0.frames.len(), ack + 1, "still paused");

    // 4. "a resume": the answer, then telemetry again, at the spec rates, later in time.
    u0.command("a resume");
    let ack = u0.read_until(Duration::from_secs(2), |f| f.toast().is_some());
    assert_eq!(u0.frames[ack].toast().as_deref(), Some("AEOLUS resumed"));
    let first = u0.read_until(Duration::from_secs(10), Frame::is_telemetry);
    let t1 = u0.frames[first].timestamp().unwrap_or_default();
    u0.read_until(Duration::from_secs(30), |f| {
        f.timestamp().is_some_and(|t| t >= t1 + 700.0)
    });
    let resumed = &u0.frames[ack + 1..];
    for p in &TELEMETRY[..6] {
        let n = resumed.iter().filter(|f| f.id == p.id).count();
        // 700 ms of the box's clock at 7 ms is 100 frames (140 at 5 ms).
        assert!(
            n as f64 >= 0.5 * 700.0 / p.interval_ms,
            "{}: {n} frames after resume",
            p.name
        );
    }
    let first_after = resumed
        .iter()
        .filter_map(Frame::timestamp)
        .fold(f64::MAX, f64::min);
    assert!(
        first_after >= last_before + 500.0 * pace,
        "the pause lasted at least 0.7 s of host time (box pace {pace:.2}): {last_before} -> {first_after}"
    );
    assert!(resumed.iter().all(|f| f.is_telemetry()));
    let s = u0.stats();
    assert_eq!((s.checksum_errors, s.bytes_discarded), (0, 0));

    // The firmware's own view (its log: boot, commands, and the 5 s status lines with the
    // stack high-water mark and the UART counters).
    let log = q.stop();
    println!("{log}");
    assert!(log.contains("AEOLUS: a pause") && log.contains("AEOLUS: a resume"));
    // The board booted is the one asked for (on the STM32 the log came over RTT), and it
    // reported its stack high-water mark.
    assert!(log.contains(board.log_name()), "not the {board:?} firmware");
    let high_water = boot_stack_high_water(&log).expect("the boot line with the stack high-water");
    println!("{board:?}: stack high-water at boot {high_water} bytes");
}

// ------------------------------------------------------------------ AYDP over UART1

fn aydp_setting_survives_store_and_reboot(board: Board) {
    let Some(mut q) = boot(board, Ports::AYDP.on(board)) else {
        return;
    };
    let log = q.log().display().to_string();
    let first = q.uart0.read_until(Duration::from_secs(10), |_| true);
    assert_eq!(
        q.uart0.frames[first].toast().as_deref(),
        Some("AEOLUS on"),
        "log: {log}"
    );

    // Airspeed (0x0110, f32) from its default to 72 m/s, read back; landed (a store is refused
    // in flight), store configuration, then "a reboot" over AEOLUS: the box comes back with
    // TOAST "AEOLUS on".
    store_airspeed(&mut q, 72.0, &log);
    let value = 72.0f32.to_le_bytes();
    q.uart0.command("a reboot");
    let seen = q.uart0.frames.len();
    let again = q.uart0.read_until(Duration::from_secs(10), |f| {
        f.toast().as_deref() == Some("AEOLUS on")
    });
    assert!(
        again >= seen,
        "a second boot TOAST after the reboot; log: {log}"
    );

    // After the reboot the stored airspeed is back.
    assert_eq!(
        request(&mut q.uart1, AIRSPEED).as_deref(),
        Some(&value[..]),
        "log: {log}"
    );
    let fw_log = q.stop();
    println!("firmware log after the reboot test:\n{fw_log}");
}

// ------------------------------------------------------------------ AOK over UART2

fn aok_parameter_and_waypoint(board: Board) {
    use aok_proto::{ActionWord, Client, Waypoint, WaypointSlot};
    let Some(mut q) = boot(board, Ports::AOK.on(board)) else {
        return;
    };
    let log = q.log().display().to_string();
    q.uart0.read_until(Duration::from_secs(10), |_| true);
    let port = q.uart2.try_clone().expect("clone UART2");
    port.set_nonblocking(true).expect("nonblocking");
    let mut client = Client::new(NbSerial::new(port), emulated_aok_config());
    let t0 = Instant::now();
    let mut now = || t0.elapsed().as_millis() as u32;

    // Parameter 12 (settable in flight) to 1500, read back; the debug stream runs meanwhile.
    aok_once_more(|| client.set_parameter(12, 1500, &mut now)).expect("set parameter 12");
    assert_eq!(
        aok_once_more(|| client.read_parameter(12, &mut now)),
        Ok(1500),
        "log: {log}"
    );
    // Parameter 20 is not settable in flight: 'I' while the simulated flight runs.
    assert_eq!(
        aok_once_more(|| client.set_parameter(20, 7, &mut now)),
        Err(aok_proto::ClientError::RefusedInFlight)
    );

    // Waypoint 1 (slot 0) set in RAM and read back as the same 77 frame.
    let wp = Waypoint {
        slot: WaypointSlot::from_wire(0).expect("slot 0"),
        longitude: 237_512_345,
        latitude: 480_012_345,
        action1: ActionWord(0x0002_800F),
        action2: ActionWord(0x0006_80FA),
    };
    aok_once_more(|| client.set_waypoint(wp, &mut now)).expect("set waypoint 1");
    assert_eq!(
        aok_once_more(|| client.read_waypoint(wp.slot, &mut now)),
        Ok(wp),
        "log: {log}"
    );
    q.stop();
}
