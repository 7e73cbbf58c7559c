//! `protolink aydp` end to end against a fake AYDP device: a thread on a loopback TCP socket
//! built from `aydp_proto`'s decoder, registry and encoder. It sends heartbeats and noise
//! between replies, so the tool must pick its reply out of other traffic.

use std::io::{Read, Write};
use std::net::TcpListener;
use std::thread::JoinHandle;

use crate::common::*;
use aydp_proto::registry::{Cell, Registry, Slot};
use aydp_proto::{
    Decode, Decoder, Encoder, Message, OutputEntry, Profile, SystemControl, Timestamp,
};

/// What the fake device ended with.
#[derive(Debug, Default)]
struct DeviceLog {
    direct: u8,
    name: String,
    speed: f32,
    rates: [u16; 3],
    offset: i32,
    stores: u32,
    rejected: u32,
    outputs: Vec<OutputEntry>,
    ignored_outputs: u32,
}

fn fake_device(listener: TcpListener, profile: Profile) -> JoinHandle<DeviceLog> {
    std::thread::spawn(move || {
        let mut log = DeviceLog::default();
        let mut direct = 0u8;
        let mut name = [0u8; 40];
        name[..9].copy_from_slice(b"demo boat");
        let mut speed = 4.5f32;
        let mut rates = [7u16, 92, 829];
        let mut offset = -3i32;
        let mut stores = 0;
        let mut rejected = 0;
        let mut outputs = Vec::new();
        let mut ignored = 0;
        {
            let mut slots = [
                Slot::value(0x0000, Cell::u8(&mut direct)).with_range(0.0, 1.0),
                Slot::value(0x0001, Cell::Chars(&mut name)).read_only(),
                Slot::value(0x0100, Cell::f32(&mut speed)).with_range(0.0, 50.0),
                Slot::array(0x0101, Cell::U16(&mut rates)),
                Slot::value(0x0102, Cell::i32(&mut offset)),
            ];
            let mut registry = Registry::new(&mut slots);
            let Some(mut stream) = accept(&listener) else {
                return log;
            };
            stream.set_nodelay(true).unwrap();
            let encoder = Encoder::new(profile);
            // Expedited where the profile has the form; the Reference software sends the same
            // messages with a normal header.
            let quick = |m: &dyn aydp_proto::Payload, wire: &mut [u8]| {
                if profile.has_expedited() {
                    encoder.encode(m, None, wire)
                } else {
                    encoder.encode(m, Some(Timestamp::new(10, 6)), wire)
                }
            };
            let mut decoder = Decoder::<512>::new(profile);
            let mut buf = [0u8; 256];
            loop {
                let n = match stream.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => n,
                };
                let mut replies: Vec<Vec<u8>> = Vec::new();
                decoder.feed(&buf[..n], |ev| {
                    let Ok(frame) = ev else { return };
                    match frame.message() {
                        Ok(Message::SystemValueUpdate(u)) => {
                            rejected += u32::from(registry.apply(&u).is_err());
                        }
                        Ok(Message::SystemControl(SystemControl::RequestData { address })) => {
                            let mut value = [0u8; 64];
                            if let Ok(reply) = registry.read(address, &mut value) {
                                // A heartbeat, a timed position and noise first: not the reply.
                                let mut wire = vec![0u8; 128];
                                let hb = quick(&Message::Heartbeat, &mut wire).unwrap();
                                let mut out = wire[..hb].to_vec();
                                let pos = aydp_proto::Position {
                                    latitude: 1.0,
                                    longitude: 2.0,
                                    altitude: 3.0,
                                };
                                let n = encoder
                                    .encode(&pos, Some(Timestamp::new(10, 5)), &mut wire)
                                    .unwrap();
                                out.extend(&wire[..n]);
                                out.extend([0x00, 0x13, 0x37]);
                                let n = quick(&reply, &mut wire).unwrap();
                                out.extend(&wire[..n]);
                                replies.push(out);
                            }
                        }
                        Ok(Message::SystemControl(SystemControl::StoreConfiguration)) => {
                            stores += 1
                        }
                        Ok(Message::DirectOutput(d)) => {
                            if registry.get::<u8>(0x0000, 0) == Some(1) {
                                outputs.extend(d.entries());
                            } else {
                                ignored += 1;
                            }
                        }
                        _ => {}
                    }
                });
                for r in replies {
                    // Split the reply in two writes so the tool sees partial frames.
                    let (a, b) = r.split_at(r.len() / 2);
                    if stream.write_all(a).is_err() || stream.write_all(b).is_err() {
                        break;
                    }
                }
            }
        }
        log.direct = direct;
        log.name = String::from_utf8_lossy(&name)
            .trim_end_matches('\0')
            .to_string();
        log.speed = speed;
        log.rates = rates;
        log.offset = offset;
        log.stores = stores;
        log.rejected = rejected;
        log.outputs = outputs;
        log.ignored_outputs = ignored;
        log
    })
}

fn with_device(profile: Profile, args: &[&str]) -> (std::process::Output, DeviceLog) {
    let (listener, ep) = listener();
    let device = fake_device(listener, profile);
    let mut full = vec!["aydp", "--to", ep.as_str()];
    if profile == Profile::Reference {
        full.extend(["--profile", "reference"]);
    }
    full.extend_from_slice(args);
    let out = run(&full);
    (out, device.join().expect("device thread"))
}

#[test]
fn get_prints_typed_values() {
    let (out, _) = with_device(Profile::Spec, &["get", "0x0001", "--as", "char[40]"]);
    assert_eq!(ok(&out), "0x0001 char[40] = \"demo boat\"\n");
    let (out, _) = with_device(Profile::Spec, &["get", "0x0101", "--as", "u16[3]"]);
    assert_eq!(ok(&out), "0x0101 u16[3] = [7, 92, 829]\n");
    let (out, _) = with_device(Profile::Spec, &["get", "258", "--as", "i32"]);
    assert_eq!(ok(&out), "0x0102 i32 = -3\n");
    let (out, _) = with_device(Profile::Spec, &["get", "0x0100"]);
    assert_eq!(ok(&out), "0x0100 = 00009040 (4 bytes, single)\n");
}

#[test]
fn set_single_array_and_element_forms() {
    let (out, log) = with_device(Profile::Spec, &["set", "0x0100", "25.5", "--as", "f32"]);
    assert_eq!(ok(&out), "0x0100 f32 = 25.5: confirmed (read back)\n");
    assert_eq!(log.speed, 25.5);

    let (out, log) = with_device(
        Profile::Spec,
        &["set", "0x0101", "10,20,30", "--as", "u16[3]"],
    );
    assert_eq!(
        ok(&out),
        "0x0101 u16[3] = [10, 20, 30]: confirmed (read back)\n"
    );
    assert_eq!(log.rates, [10, 20, 30]);

    let (out, log) = with_device(
        Profile::Spec,
        &["set", "0x0101[2]", "1000", "--as", "u16[3]"],
    );
    assert_eq!(
        ok(&out),
        "0x0101 u16[3] = [7, 92, 1000]: confirmed (read back)\n"
    );
    assert_eq!(log.rates, [7, 92, 1000]);

    let (out, log) = with_device(Profile::Spec, &["set", "0x0102", "-70000", "--as", "i32"]);
    assert_eq!(ok(&out), "0x0102 i32 = -70000: confirmed (read back)\n");
    assert_eq!(log.offset, -70000);
}

#[test]
fn the_reference_profile_works_the_same() {
    let (out, log) = with_device(
        Profile::Reference,
        &["set", "0x0100", "12.25", "--as", "f32"],
    );
    assert_eq!(ok(&out), "0x0100 f32 = 12.25: confirmed (read back)\n");
    assert_eq!(log.speed, 12.25);
}

#[test]
fn a_value_the_device_refuses_is_an_error() {
    // Out of the slot's range: the registry changes nothing; the read-back shows it.
    let (out, log) = with_device(Profile::Spec, &["set", "0x0100", "99", "--as", "f32"]);
    let err = failed(&out);
    assert!(
        err.contains("the device did not take the value (read back: 0x0100 f32 = 4.5)"),
        "{err}"
    );
    assert_eq!((log.speed, log.rejected), (4.5, 1));
    // Read-only text.
    let (out, log) = with_device(
        Profile::Spec,
        &["set", "0x0001", "new name", "--as", "char[40]"],
    );
    failed(&out);
    assert_eq!(log.name, "demo boat");
}

#[test]
fn bad_values_are_refused_before_anything_is_sent() {
    let (out, log) = with_device(Profile::Spec, &["set", "0x0101", "1,2", "--as", "u16[3]"]);
    let err = usage_failed(&out);
    assert!(
        err.contains("u16[3] needs exactly 3 comma-separated values, got 2"),
        "{err}"
    );
    assert_eq!(log.rates, [7, 92, 829]);
    let (out, _) = with_device(Profile::Spec, &["set", "0x0000", "300", "--as", "u8"]);
    assert!(usage_failed(&out).contains("'300' is not a u8 value"));
}

#[test]
fn store_is_sent_and_confirmed() {
    let (out, log) = with_device(Profile::Spec, &["store"]);
    assert_eq!(
        ok(&out),
        "store configuration: unconfirmed (AYDP has no acknowledgement; the device answered a \
         request sent after it, so it received the store; --verify reads the box's store \
         counters)\n"
    );
    assert_eq!(log.stores, 1);
}

#[test]
fn output_enables_direct_control_only_when_asked() {
    // Direct control is off and --enable not given: the device would ignore the outputs, so
    // that is a refusal (status 1), and nothing is sent.
    let (out, log) = with_device(Profile::Spec, &["output", "1:2=10.0", "1:3=-5"]);
    assert!(
        failed(&out).contains(
            "the device refuses direct outputs: direct control is off (0x0000 = 00); pass \
             --enable to turn it on"
        ),
        "{}",
        stderr(&out)
    );
    assert_eq!((log.direct, log.outputs.len()), (0, 0));

    let (out, log) = with_device(Profile::Spec, &["output", "1:2=10.0", "1:3=-5", "--enable"]);
    assert_eq!(
        ok(&out),
        "output 1:2 = 10: unconfirmed (AYDP has no acknowledgement; --verify reads the box's \
         counters)\noutput 1:3 = -5: unconfirmed (AYDP has no acknowledgement; --verify reads \
         the box's counters)\n"
    );
    assert_eq!(log.direct, 1);
    assert_eq!(
        log.outputs,
        [
            OutputEntry {
                device: 1,
                channel: 2,
                value: 10.0
            },
            OutputEntry {
                device: 1,
                channel: 3,
                value: -5.0
            }
        ]
    );
}

#[test]
fn a_silent_device_times_out_with_a_clear_error() {
    let (listener, ep) = listener();
    let silent = std::thread::spawn(move || {
        let (s, _) = listener.accept().unwrap();
        // Swallow the request, never answer.
        read_all(s)
    });
    let out = run(&["aydp", "--to", &ep, "--timeout-ms", "300", "get", "8"]);
    let err = failed(&out);
    assert!(
        err.contains("error: no answer to request data for address 0x0008 from tcp:127.0.0.1:"),
        "{err}"
    );
    assert!(err.contains("within 300 ms"), "{err}");
    let request = silent.join().unwrap();
    // What went out: the corrected "request data at address 8" (Y6).
    assert_eq!(request, unhex("ff890a00000001080075"));
}

#[test]
fn a_device_that_hangs_up_is_reported() {
    let (listener, ep) = listener();
    let hangup = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().unwrap();
        let mut b = [0u8; 10];
        let _ = s.read(&mut b);
        drop(s);
    });
    let out = run(&["aydp", "--to", &ep, "get", "8"]);
    let err = failed(&out);
    assert!(err.contains("closed the connection"), "{err}");
    hangup.join().unwrap();
    // Nobody listening at all.
    let (gone, ep) = crate::common::listener();
    drop(gone);
    let out = run(&["aydp", "--to", &ep, "get", "8"]);
    let err = failed(&out);
    assert!(err.contains(&format!("error: cannot open {ep}: ")), "{err}");
}

/// A receiver written from the AYDP reference software's frame format alone: 0xFF, type, u32
/// data length, i64 seconds, i64 microseconds (little-endian), the data, then the XOR of
/// every byte from the 0xFF through the last data byte. A bad checksum drops the whole
/// claimed frame. Returns (type, data) of every frame accepted, and how many were dropped.
fn reference_receiver(mut bytes: &[u8]) -> (Vec<(u8, Vec<u8>)>, usize) {
    let (mut accepted, mut dropped) = (Vec::new(), 0);
    while let Some(start) = bytes.iter().position(|&b| b == 0xFF) {
        bytes = &bytes[start..];
        if bytes.len() < 22 {
            break;
        }
        let len = u32::from_le_bytes(bytes[2..6].try_into().unwrap()) as usize;
        let Some(frame) = bytes.get(..22 + len + 1) else {
            break;
        };
        if frame.iter().fold(0u8, |x, b| x ^ b) == 0 {
            accepted.push((frame[1], frame[22..22 + len].to_vec()));
        } else {
            dropped += 1;
        }
        bytes = &bytes[frame.len()..];
    }
    (accepted, dropped)
}

/// Every frame `protolink aydp --profile reference` writes has the 22-byte header the
/// reference software reads, and with `--to -` the result lines go to stderr, never between
/// the frames.
#[test]
fn reference_profile_commands_pass_the_reference_receiver() {
    let mut wire = Vec::new();
    let runs: [&[&str]; 3] = [
        &["set", "0x0100", "25.5", "--as", "f32"],
        &["store"],
        &["output", "1:2=10.0", "--enable"],
    ];
    for args in runs {
        let mut full = vec!["aydp", "--profile", "reference", "--to", "-", "--no-verify"];
        full.extend_from_slice(args);
        let out = run(&full);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        assert!(!stderr(&out).is_empty(), "the result line goes to stderr");
        wire.extend(&out.stdout);
    }
    let (frames, dropped) = reference_receiver(&wire);
    assert_eq!(dropped, 0);
    let mut set = vec![1, 0x00, 0x01, 0, 0, 0, 0];
    set.extend(25.5f32.to_le_bytes());
    let mut output = vec![1, 0, 1, 2];
    output.extend(10.0f32.to_le_bytes());
    assert_eq!(
        frames,
        [
            (8, set),
            (9, vec![2]),
            (8, vec![1, 0x00, 0x00, 0, 0, 0, 0, 1]),
            (7, output),
        ]
    );
    // The receiver does drop a frame whose checksum is wrong, and the next one survives.
    let mut bad = wire.clone();
    bad[22] ^= 0x01;
    assert_eq!(reference_receiver(&bad).1, 1);
    assert_eq!(reference_receiver(&bad).0.len(), 3);
}
