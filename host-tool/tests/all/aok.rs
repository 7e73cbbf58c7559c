//! `protolink aok` end to end against a fake AOK flight controller: a thread on a loopback TCP
//! socket built from `aok_proto`'s device-side decoder and encoders. It streams debug values
//! while debug output is on and keeps sending a few late ones after debug-off, as the document
//! warns a real device does.

use std::io::{Read, Write};
use std::net::TcpListener;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::common::*;
use aok_proto::{
    Ack, Action, ActionWord, Command, CommandDecoder, DebugValue, Decode, FirmwareVersion,
    Waypoint, WaypointSlot,
};
use aok_proto::{BulkReply, Message, ReplyForm};

/// How many debug frames the fake device still sends after debug-off.
const LATE_DEBUG_FRAMES: usize = 4;
/// A parameter the fake device refuses to change "in flight" ('I').
const IN_FLIGHT_ONLY: u8 = 200;
/// A parameter number the fake device answers 'E' to.
const REJECTED: u8 = 201;

#[derive(Debug, Default)]
struct DeviceLog {
    commands: Vec<Command>,
    params: Vec<(u8, i32)>,
    waypoints: Vec<Waypoint>,
    debug_frames_sent: usize,
    late_frames_sent: usize,
}

fn fake_device(listener: TcpListener, firmware: FirmwareVersion) -> JoinHandle<DeviceLog> {
    std::thread::spawn(move || {
        let mut log = DeviceLog::default();
        let Some(mut stream) = accept(&listener) else {
            return log;
        };
        stream.set_nodelay(true).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_millis(2)))
            .unwrap();
        let mut params = [0i32; 256];
        for (i, p) in params.iter_mut().enumerate() {
            *p = 1000 + i as i32;
        }
        params[12] = -1500;
        let mut waypoints = vec![Waypoint {
            slot: WaypointSlot::from_wire(0).unwrap(),
            longitude: 237_512_345,
            latitude: 480_012_345,
            action1: ActionWord::new(Action::HoldAndClimb, 15),
            action2: ActionWord::new(Action::SetFlySpeed, 250),
        }];
        let mut decoder = CommandDecoder::new();
        let mut debug_on = true;
        let mut tick = 0i32;
        let mut last_debug = Instant::now();
        let mut buf = [0u8; 64];
        loop {
            let mut out: Vec<u8> = Vec::new();
            let mut frame = [0u8; 112];
            match stream.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    for &b in &buf[..n] {
                        let mut items = Vec::new();
                        decoder.feed(&[b], |item| items.push(item));
                        for item in items {
                            let Ok(cmd) = item else {
                                let k = Message::Ack(Ack::Error)
                                    .emit(&mut frame, ReplyForm::Headed)
                                    .unwrap();
                                out.extend(&frame[..k]);
                                continue;
                            };
                            log.commands.push(cmd);
                            match cmd {
                                Command::DebugOff => {
                                    debug_on = false;
                                    // Values already queued keep coming for a while.
                                    for i in 0..LATE_DEBUG_FRAMES {
                                        let v = DebugValue {
                                            number: 86,
                                            value: 0x4f4f_4f4f + i as i32,
                                        };
                                        let k = Message::Debug(v)
                                            .emit(&mut frame, ReplyForm::Headed)
                                            .unwrap();
                                        out.extend(&frame[..k]);
                                        log.late_frames_sent += 1;
                                    }
                                }
                                Command::DebugOn => debug_on = true,
                                Command::ReadParameter(n) => {
                                    let p = aok_proto::ParameterValue {
                                        number: n,
                                        value: params[usize::from(n)],
                                    };
                                    let k = Message::Parameter(p)
                                        .emit(&mut frame, firmware.reply_form())
                                        .unwrap();
                                    out.extend(&frame[..k]);
                                }
                                Command::BulkRead(first) => {
                                    let mut values = [0i32; 16];
                                    for (i, v) in values.iter_mut().enumerate() {
                                        *v = params[usize::from(first.wrapping_add(i as u8))];
                                    }
                                    let k = BulkReply { first, values }.emit(&mut frame).unwrap();
                                    out.extend(&frame[..k]);
                                }
                                Command::SetParameter(p) => {
                                    let ack = match p.number {
                                        IN_FLIGHT_ONLY => Ack::InFlight,
                                        REJECTED => Ack::Error,
                                        n => {
                                            params[usize::from(n)] = p.value;
                                            log.params.push((n, p.value));
                                            Ack::Ok
                                        }
                                    };
                                    let k = Message::Ack(ack)
                                        .emit(&mut frame, ReplyForm::Headed)
                                        .unwrap();
                                    out.extend(&frame[..k]);
                                }
                                Command::ReadWaypoint(slot) => {
                                    if let Some(w) = waypoints.iter().find(|w| w.slot == slot) {
                                        let k = Message::Waypoint(*w)
                                            .emit(&mut frame, ReplyForm::Headed)
                                            .unwrap();
                                        out.extend(&frame[..k]);
                                    }
                                }
                                Command::SetWaypoint(w) => {
                                    waypoints.retain(|x| x.slot != w.slot);
                                    waypoints.push(w);
                                    log.waypoints.push(w);
                                    let k = Message::Ack(Ack::Ok)
                                        .emit(&mut frame, ReplyForm::Headed)
                                        .unwrap();
                                    out.extend(&frame[..k]);
                                }
                                _ => {}
                            }
                        }
                    }
                }
                Err(_) => {}
            }
            if debug_on && last_debug.elapsed() >= Duration::from_millis(3) {
                last_debug = Instant::now();
                tick += 1;
                // Values full of 'O', 'E' and 'I' bytes: never to be taken for acks.
                let v = DebugValue {
                    number: (tick % 8) as u8 + 80,
                    value: 0x4f45_4900 + tick,
                };
                let k = Message::Debug(v)
                    .emit(&mut frame, ReplyForm::Headed)
                    .unwrap();
                out.extend(&frame[..k]);
                log.debug_frames_sent += 1;
            }
            if !out.is_empty() && stream.write_all(&out).is_err() {
                break;
            }
        }
        log.params.sort_unstable();
        log
    })
}

fn with_device(firmware: &str, args: &[&str]) -> (std::process::Output, DeviceLog) {
    let (listener, ep) = listener();
    let fw = protolink::commands::aok::parse_firmware(firmware).unwrap();
    let device = fake_device(listener, fw);
    let mut full = vec!["aok", "--to", ep.as_str(), "--firmware", firmware];
    full.extend_from_slice(args);
    let out = run(&full);
    (out, device.join().expect("device thread"))
}

#[test]
fn get_survives_late_debug_frames_in_both_reply_forms() {
    for fw in ["0.35", "0.31", "0.30"] {
        let (out, log) = with_device(fw, &["get", "12"]);
        assert_eq!(ok(&out), "parameter 12 = -1500\n", "firmware {fw}");
        assert_eq!(
            log.commands,
            [
                Command::DebugOff,
                Command::ReadParameter(12),
                Command::DebugOn
            ],
            "firmware {fw}"
        );
        assert_eq!(log.late_frames_sent, LATE_DEBUG_FRAMES);
    }
}

#[test]
fn set_waits_for_the_ack() {
    let (out, log) = with_device("0.35", &["set", "12", "-42"]);
    assert_eq!(ok(&out), "parameter 12 = -42: confirmed (acked 'O')\n");
    assert_eq!(log.params, [(12, -42)]);

    let (out, log) = with_device("0.35", &["set", &IN_FLIGHT_ONLY.to_string(), "1"]);
    let err = failed(&out);
    assert!(
        err.contains("error: the device refused setting parameter 200 in flight ('I')"),
        "{err}"
    );
    assert!(log.params.is_empty());
    // Debug output is switched back on after a refusal, too.
    assert_eq!(log.commands.last(), Some(&Command::DebugOn));

    let (out, _) = with_device("0.35", &["set", &REJECTED.to_string(), "1"]);
    assert!(failed(&out).contains("error: the device rejected setting parameter 201 ('E')"));
}

#[test]
fn bulk_reads_sixteen_values() {
    let (out, log) = with_device("0.35", &["bulk", "250"]);
    let text = ok(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 16);
    assert_eq!(lines[0], "parameter 250 = 1250");
    assert_eq!(lines[5], "parameter 255 = 1255");
    assert_eq!(lines[6], "parameter 0 = 1000");
    assert_eq!(lines[15], "parameter 9 = 1009");
    assert!(log.commands.contains(&Command::BulkRead(250)));
    // Older firmware has no bulk read: refused before anything is asked.
    let (out, log) = with_device("0.34", &["bulk", "0"]);
    assert!(usage_failed(&out).contains("bulk read needs firmware 0.35 or newer"));
    assert!(log.commands.is_empty());
}

#[test]
fn waypoints_get_and_set() {
    let (out, _) = with_device("0.35", &["waypoint", "get", "1"]);
    assert_eq!(
        ok(&out),
        "waypoint 1: longitude=237512345 latitude=480012345 action1=hold-and-climb:15 action2=set-fly-speed:250\n"
    );
    let (out, log) = with_device(
        "0.35",
        &[
            "waypoint",
            "set",
            "fbc",
            "-1000",
            "2000",
            "--action1",
            "pause:5",
        ],
    );
    assert_eq!(
        ok(&out),
        "waypoint fbc: longitude=-1000 latitude=2000 action1=pause:5 action2=none:0: confirmed (acked 'O')\n"
    );
    assert_eq!(
        log.waypoints,
        [Waypoint {
            slot: WaypointSlot::FbcTarget,
            longitude: -1000,
            latitude: 2000,
            action1: ActionWord::new(Action::Pause, 5),
            action2: ActionWord::NONE,
        }]
    );
    // A slot nobody stored is never answered: a clean timeout.
    let (out, _) = with_device(
        "0.35",
        &["--timeout-ms", "300", "waypoint", "get", "ram-poi"],
    );
    let err = failed(&out);
    assert!(
        err.contains("no answer to the read of waypoint ram-poi from tcp:127.0.0.1:"),
        "{err}"
    );
    assert!(err.contains("within 300 ms"));
}

#[test]
fn fire_and_forget_commands_go_out_as_encoded() {
    let cases: &[(&[&str], Command)] = &[
        (&["debug", "off"], Command::DebugOff),
        (&["debug", "on"], Command::DebugOn),
        (&["save-set", "2"], Command::SaveSet(2)),
        (&["load-set", "3"], Command::LoadSet(3)),
        (&["reset"], Command::Reset),
        (
            &["motor", "3", "40"],
            Command::MotorTest(aok_proto::MotorTest {
                motor: aok_proto::Motor::new(3).unwrap(),
                value: 40,
            }),
        ),
        (
            &["extern", "32", "-32", "0", "0", "--expiry", "500"],
            Command::ExternalControl(aok_proto::ExternalControl {
                roll: aok_proto::Stick::new(32).unwrap(),
                nick: aok_proto::Stick::new(-32).unwrap(),
                yaw: aok_proto::Stick::new(0).unwrap(),
                pitch: 0,
                expiry_ms: 500,
            }),
        ),
    ];
    for (args, want) in cases {
        let (out, log) = with_device("0.35", args);
        ok(&out);
        assert!(log.commands.contains(want), "{args:?}: {:?}", log.commands);
    }
}

#[test]
fn out_of_range_arguments_are_usage_errors() {
    for args in [
        &["motor", "13", "1"][..],
        &["extern", "201", "0", "0", "0", "--expiry", "5"],
        &["waypoint", "get", "32"],
        &["waypoint", "set", "1", "0", "0", "--action1", "loop:1"],
    ] {
        let mut full = vec!["aok", "--to", "tcp:127.0.0.1:9"];
        full.extend_from_slice(args);
        let out = run(&full);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&out).contains("error: invalid value"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn reads_over_a_line_that_never_stops_talking_time_out_cleanly() {
    // A device that ignores debug-off and never answers: the request times out, no panic.
    let (listener, ep) = listener();
    let chatter = std::thread::spawn(move || {
        let Some(mut s) = accept(&listener) else {
            return;
        };
        let mut frame = [0u8; 7];
        let k = Message::Debug(DebugValue {
            number: 86,
            value: 1,
        })
        .emit(&mut frame, ReplyForm::Headed)
        .unwrap();
        let started = Instant::now();
        while started.elapsed() < Duration::from_secs(5) {
            if s.write_all(&frame[..k]).is_err() {
                break;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    });
    let out = run(&["aok", "--to", &ep, "--timeout-ms", "200", "get", "7"]);
    let err = failed(&out);
    assert!(
        err.contains("no answer to the read of parameter 7"),
        "{err}"
    );
    chatter.join().unwrap();
}

/// The box runs a motor at rest only from a second frame within the 500 ms hold of the first
/// (docs/protocol-notes.md PL41): without --hold-ms, `motor` sends two, 20 ms apart.
/// How many motor-test frames for `motor` with `value` the device received.
fn motor_frames(log: &DeviceLog, motor: u8, value: u8) -> usize {
    log.commands
        .iter()
        .filter(
            |c| matches!(c, Command::MotorTest(m) if m.motor.get() == motor && m.value == value),
        )
        .count()
}

#[test]
fn motor_sends_the_second_frame_the_box_runs_the_motor_from() {
    let (out, log) = with_device("0.35", &["motor", "2", "30"]);
    let text = ok(&out);
    let sent = motor_frames(&log, 2, 30);
    assert_eq!(sent, 2);
    assert!(
        text.starts_with("motor 2 test value 30 (2 frame(s)): "),
        "{text}"
    );
}

#[test]
fn motor_hold_repeats_the_value_before_it_lapses() {
    let (out, log) = with_device("0.35", &["motor", "2", "30", "--hold-ms", "450"]);
    let text = ok(&out);
    let sent = motor_frames(&log, 2, 30);
    // Every 200 ms for 450 ms: at least at 0, 200 and 400 ms, so the 500 ms lapse never hits.
    assert!(sent >= 3, "{sent} sends");
    assert_eq!(
        text,
        format!(
            "motor 2 test value 30 ({sent} frame(s)): unconfirmed (AOK defines no answer to a \
             motor test; pass --verify to check the debug values)\n"
        )
    );
}
