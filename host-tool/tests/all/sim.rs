//! `protolink sim` end to end: the real binary sends to a plain UDP socket in the test, and the
//! test drives it with COMMAND and SETTIME datagrams on its in-port.

use std::time::Duration;

use crate::common::*;
use aeolus_proto::message::{Message, SetTime};
use protolink_tests::aeolus_udp::{App, Received};

fn timestamp(f: &Received) -> Option<f64> {
    f.message()?.timestamp_ms()
}

/// Starts `protolink sim` for `app` with `extra` arguments.
fn sim(app: &App, extra: &[&str]) -> std::process::Child {
    let out = format!("127.0.0.1:{}", app.port());
    let inp = app.box_port.to_string();
    let mut args = vec!["sim", "--udp-out", &out, "--udp-in", &inp];
    args.extend_from_slice(extra);
    spawn(&args)
}

/// The spec's periodic messages (figure 1c): ID, name, interval in ms.
const PERIODIC: [(u8, &str, f64); 9] = [
    (62, "GYRO", 7.0),
    (63, "ACCEL", 7.0),
    (64, "MAGNET", 7.0),
    (71, "ATTITUDE", 7.0),
    (72, "COMPASS", 7.0),
    (61, "PRESSURE", 5.0),
    (66, "GPS", 92.0),
    (65, "TEMP", 829.0),
    (73, "WIND", 1000.0),
];

#[test]
fn sim_sends_every_type_at_the_spec_rates_and_obeys_commands() {
    let mut link = App::new(free_udp_port());
    let child = sim(&link, &["--seconds", "6"]);

    // The boot TOAST first, then 2 s of telemetry, every frame with a good CRC.
    let first = link.read_until_toast(Duration::from_secs(5));
    assert_eq!(first, 0, "the boot TOAST comes first");
    assert_eq!(link.frames[0].toast().as_deref(), Some("AEOLUS on"));
    link.read_for(Duration::from_secs(2));
    for (id, name, interval) in PERIODIC {
        let ts: Vec<f64> = link
            .frames
            .iter()
            .filter(|f| f.id == id)
            .filter_map(timestamp)
            .collect();
        assert!(!ts.is_empty(), "no {name} in 2 s");
        if ts.len() >= 3 {
            // The firmware's drift-free schedule: the frames stand on a grid of the spec's
            // interval, each stamped when it was sent. A sim that the host starves of CPU sends
            // a slot late, or several in a burst when it gets the CPU back, or skips a slot, as
            // the box must on a late CPU. So: the grid's slots between the first frame and the
            // last hold at most a quarter skipped and never more frames than slots (2 % kept
            // for a late first or last frame), and the median gap, that of frames on time, is
            // the interval within 2 %. (A gap's own slot count is no measure: a burst's first
            // gap spans the slots the burst then sends, which counted them twice, 6.81 ms for
            // GYRO's 7 in a CI-like run under load.)
            let gaps: Vec<f64> = ts.windows(2).map(|w| w[1] - w[0]).collect();
            let slots = ((ts[ts.len() - 1] - ts[0]) / interval).round();
            let skipped = slots - gaps.len() as f64;
            assert!(
                (-0.02 * slots..=0.25 * slots).contains(&skipped),
                "{name}: {} gaps over {slots} slots of {interval} ms; gaps {gaps:?}",
                gaps.len()
            );
            if gaps.len() >= 5 {
                let mut sorted = gaps.clone();
                sorted.sort_by(f64::total_cmp);
                let median = sorted[sorted.len() / 2];
                assert!(
                    (median - interval).abs() <= 0.02 * interval,
                    "{name}: median gap {median} ms, spec {interval} ms; gaps {gaps:?}"
                );
            }
        }
    }
    assert!(link.frames.iter().any(|f| f.id == 51), "no AEOLUSINFO");
    // One frame per datagram by default.
    assert_eq!(link.datagrams, link.frames.len());

    // SETTIME, then "a pause": the answer, then silence.
    link.send(&Message::SetTime(SetTime {
        year_since_1900: 126,
        month0: 10,
        day: 21,
        hour: 12,
        minute: 0,
        second: 0,
    }));
    link.command("a pause");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS paused"));
    link.read_for(Duration::from_millis(400));
    assert_eq!(link.frames.len(), ack + 1, "telemetry while paused");

    // "a resume": the answer, then telemetry again.
    link.command("a resume");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS resumed"));
    link.read_for(Duration::from_millis(300));
    let after = link.frames.len() - ack - 1;
    assert!(
        after >= 40,
        "only {after} frames in 300 ms after the resume"
    );

    // An unknown command is answered; "a reboot" is refused in flight, and landed ("a pause")
    // restarts the box with its boot TOAST.
    link.command("a hello");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(
        link.frames[ack].toast().as_deref(),
        Some("unknown command: a hello")
    );
    link.command("a reboot");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(
        link.frames[ack].toast().as_deref(),
        Some("AEOLUS reboot refused: flying")
    );
    link.command("a pause");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS paused"));
    link.command("a reboot");
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(
        link.frames[ack].toast().as_deref(),
        Some("AEOLUS rebooting")
    );
    let ack = link.read_until_toast(Duration::from_secs(2));
    assert_eq!(link.frames[ack].toast().as_deref(), Some("AEOLUS on"));

    // The counters on exit: every datagram it received was acted on.
    let out = ok(&finish(child));
    let summary = out.lines().find(|l| l.starts_with("sim: ")).unwrap();
    for want in [
        "settime=1 ",
        "commands=4 ",
        "unknown_commands=1 ",
        "refused_in_flight=1 ",
        "reboots=1 ",
        "rx_errors=0 ",
        "send_errors=0 ",
        "datagrams_received=7",
    ] {
        assert!(summary.contains(want), "{want} not in {summary}");
    }
}

#[test]
fn sim_packs_frames_into_datagrams() {
    let mut link = App::new(free_udp_port());
    let child = sim(&link, &["--pack", "4", "--seconds", "1.5"]);
    link.read_for(Duration::from_millis(1200));
    let out = ok(&finish(child));
    let mut per_datagram = vec![0usize; link.datagrams];
    for f in &link.frames {
        per_datagram[f.datagram] += 1;
    }
    assert!(link.frames.len() > 300, "{} frames", link.frames.len());
    assert!(per_datagram.iter().all(|&n| (1..=4).contains(&n)));
    assert!(
        per_datagram.iter().filter(|&&n| n == 4).count() > per_datagram.len() / 2,
        "most datagrams are full packs: {per_datagram:?}"
    );
    assert!(out.contains("send_errors=0"));
}

#[test]
fn sim_refuses_an_impossible_flight_in_one_sentence() {
    let err = usage_failed(&run(&["sim", "--airspeed", "500", "--seconds", "1"]));
    assert!(
        err.contains("'500' is out of range: expected a number from 10 to 150 m/s"),
        "{err}"
    );
    let err = usage_failed(&run(&["sim", "--bank", "-75", "--seconds", "1"]));
    assert!(
        err.contains("expected a number from -60 to 60 degrees"),
        "{err}"
    );
    // A climb steeper than half the airspeed (30° of flight path) at the default 50 m/s.
    let out = run(&["sim", "--climb", "30", "--seconds", "1"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.trim(),
        "error: cannot simulate that flight: climb rate above half the airspeed",
        "{err}"
    );
}

/// Every flight option at each end of the range its help states simulates (status 0), and
/// just past an end is refused on the command line (status 2) with the range: the help, the
/// parser and the flight agree. The airspeed's range is the box's own (AYDP 0x0110, 10..=150
/// m/s): the simulated wind blows at 5 m/s, and the flight needs an airspeed above it.
#[test]
fn sim_flies_at_every_bound_its_help_states() {
    let help = stdout(&run(&["sim", "--help"]));
    for stated in ["10..=150", "-60..=60", "-500..=11000"] {
        assert!(help.contains(stated), "{stated} not in the help:\n{help}");
    }
    let to = format!("127.0.0.1:{}", free_udp_port());
    let fly = |option: &str, value: &str, extra: &[&str]| {
        let flag = format!("--{option}={value}");
        let mut args = vec![
            "sim",
            "--udp-out",
            &to,
            "--udp-in",
            "0",
            "--seconds",
            "0.1",
            &flag,
        ];
        args.extend_from_slice(extra);
        run(&args)
    };
    for (option, value, extra) in [
        ("airspeed", "10", &[][..]),
        ("airspeed", "150", &[]),
        ("bank", "-60", &[]),
        ("bank", "60", &[]),
        ("altitude", "-500", &[]),
        ("altitude", "11000", &[]),
        // At most half the airspeed: 75 m/s at 150 m/s, 5 m/s at 10 m/s.
        ("climb", "75", &["--airspeed", "150"]),
        ("climb", "-75", &["--airspeed", "150"]),
        ("climb", "5", &["--airspeed", "10"]),
    ] {
        let out = fly(option, value, extra);
        assert!(
            out.status.success(),
            "--{option}={value} {extra:?}: {}",
            stderr(&out)
        );
    }
    for (option, value) in [
        ("airspeed", "9.99"),
        ("airspeed", "5"),
        ("airspeed", "150.01"),
        ("bank", "60.01"),
        ("altitude", "-500.01"),
        ("altitude", "11000.01"),
    ] {
        let err = usage_failed(&fly(option, value, &[]));
        assert!(
            err.contains("is out of range: expected a number from"),
            "{err}"
        );
    }
}

/// `--gps-outage 1..2`: the GPS frames the sim sends in that second have no fix, the others
/// have one; a window that is not one is refused in one sentence, with status 2.
#[test]
fn sim_gps_outage_sends_no_fix_in_its_window_and_refuses_a_bad_one() {
    let mut link = App::new(free_udp_port());
    let child = sim(&link, &["--gps-outage", "1..2", "--seconds", "3"]);
    link.read_for(Duration::from_millis(3500));
    ok(&finish(child));
    // The box's clock starts with the sim's (no reboot here): 100 ms of margin at each edge.
    let gps: Vec<_> = link
        .frames
        .iter()
        .filter_map(|f| match f.message()? {
            Message::Gps(g) => Some(g),
            _ => None,
        })
        .collect();
    let (mut inside, mut outside) = (0, 0);
    for g in &gps {
        let t = g.timestamp_ms;
        if (1100.0..1900.0).contains(&t) {
            inside += 1;
            assert!(
                !g.has_fix && g.satellites == 0 && g.latitude_deg == 0.0,
                "{g:?}"
            );
            assert!(g.valid, "the receiver works without a fix: {g:?}");
        } else if !(900.0..2100.0).contains(&t) {
            outside += 1;
            assert!(g.has_fix && g.satellites > 0, "{g:?}");
        }
    }
    assert!(
        inside >= 7 && outside >= 15,
        "{inside} GPS in the outage, {outside} out"
    );

    for (window, says) in [
        (
            "8..4",
            "'8..4' is an empty window: FROM must come before TO",
        ),
        ("4", "'4' is not a window FROM..TO"),
        ("-1..4", "'-1..4' is not a window FROM..TO"),
        ("4..nan", "'4..nan' is not a window FROM..TO"),
        ("0..86401", "each a time after the start from 0 to 86400 s"),
    ] {
        let err = usage_failed(&run(&["sim", "--gps-outage", window, "--seconds", "1"]));
        assert!(err.contains(says), "{window}: {err}");
    }
}
