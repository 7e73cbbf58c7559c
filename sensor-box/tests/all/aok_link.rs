//! The AOK link on UART2, driven like a PC would drive it: in-memory serial ports (the
//! `QueuedSerial`/`SerialIsr` pair the boards use), a simulated clock, commands built with
//! `aok_proto`'s encoders and the device's output read with its `MessageDecoder` (and, end to end,
//! with its `Client`).

use std::cell::Cell;
use std::rc::Rc;

use aok_proto::{
    Action, ActionWord, Client, ClientError, Command, Config, DebugValue, ExternalControl, Message,
    Motor, MotorTest, ParameterValue, Stick, Waypoint, WaypointNumber, WaypointSlot,
};
use aok_proto::{Decode, Expect, MessageDecoder};
use embedded_hal_nb::serial::{ErrorType, Read, Write};
use sensor_box::aok_link::{
    AokLink, ControlSource, DebugId, FIRMWARE, GAP_MS, MOTOR_LAPSE_MS, STATUS_EXTERNAL,
    STATUS_FLYING, STATUS_MOTOR_TEST,
};
use sensor_box::serial::Ring;
use sensor_box::serial::{PortStats, QueuedSerial, SerialIsr};
use sensor_box::state::StoredWaypoint;
use sensor_box::storage::MemFlash;
use sensor_box::{App, Control, Persisted, Shared};

/// A port pair over queues that live for the whole test binary (leaked: a few KiB per test).
fn ports<const TX: usize>() -> (
    QueuedSerial<'static, 1024, TX>,
    SerialIsr<'static, 1024, TX>,
) {
    let rx = Box::leak(Box::new(Ring::<1024>::new()));
    let tx = Box::leak(Box::new(Ring::<TX>::new()));
    let stats = Box::leak(Box::new(PortStats::new()));
    QueuedSerial::split(rx, tx, stats, || {})
}

/// The link, its shared state, its port and a simulated clock.
struct Rig<const TX: usize = 1024> {
    shared: Shared,
    link: AokLink,
    port: QueuedSerial<'static, 1024, TX>,
    isr: SerialIsr<'static, 1024, TX>,
    now: u64,
    /// Whether `step` hands the device's output to the PC (false: the port's TX queue fills).
    draining: bool,
    out: Vec<u8>,
}

impl Rig {
    fn new() -> Self {
        Self::with(Persisted::default(), ports::<1024>())
    }
}

impl<const TX: usize> Rig<TX> {
    fn with(
        persisted: Persisted,
        (port, isr): (
            QueuedSerial<'static, 1024, TX>,
            SerialIsr<'static, 1024, TX>,
        ),
    ) -> Self {
        let shared = Shared::new(persisted, 0);
        let link = AokLink::new(&shared);
        Rig {
            shared,
            link,
            port,
            isr,
            now: 0,
            draining: true,
            out: Vec::new(),
        }
    }

    /// The PC sends raw bytes.
    fn send(&mut self, bytes: &[u8]) {
        for &b in bytes {
            assert!(self.isr.received(b), "RX queue full");
        }
    }

    /// The PC sends a command.
    fn cmd(&mut self, c: Command) {
        let mut frame = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = c.emit(&mut frame).unwrap();
        self.send(&frame[..n]);
    }

    /// One poll at the current time; the PC reads what the port sent.
    fn poll(&mut self) {
        self.link.poll(self.now, &mut self.port, &mut self.shared);
        if self.draining {
            while let Some(b) = self.isr.next_to_send() {
                self.out.push(b);
            }
        }
    }

    /// Polls once per millisecond for `ms` milliseconds, starting at the current time.
    fn run(&mut self, ms: u64) {
        for _ in 0..ms {
            self.poll();
            self.now += 1;
        }
    }

    /// Polls until the silence after what was sent is observed ([`GAP_MS`] after the poll that
    /// took the last byte): the burst is obeyed (or discarded) by then.
    fn settle(&mut self) {
        self.run(GAP_MS + 1);
    }

    /// Everything the device sent since the last call.
    fn take(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.out)
    }

    /// Debug off, and whatever was still queued read away.
    fn quiet(&mut self) {
        self.cmd(Command::DebugOff);
        self.run(5);
        self.take();
    }

    /// The PC sends `bytes`; the device's answer after 5 ms.
    fn exchange(&mut self, bytes: &[u8]) -> Vec<u8> {
        self.send(bytes);
        self.run(5);
        self.take()
    }

    fn exchange_cmd(&mut self, c: Command) -> Vec<u8> {
        let mut frame = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = c.emit(&mut frame).unwrap();
        self.exchange(&frame[..n])
    }
}

/// Decodes the device's stream as the PC would with `expect` pending; every byte must belong
/// to a frame.
fn decode(bytes: &[u8], expect: Expect) -> Vec<Message> {
    let mut pc = MessageDecoder::new(FIRMWARE);
    pc.expect(expect);
    let mut got = Vec::new();
    for &b in bytes {
        pc.feed(&[b], |ev| got.extend(ev.ok()));
    }
    assert_eq!(pc.stats().unknown_bytes, 0, "stray bytes in {bytes:02x?}");
    assert_eq!(pc.stats().checksum_errors, 0, "bad frames in {bytes:02x?}");
    assert_eq!(
        pc.held_bytes(),
        0,
        "partial frame at the end of {bytes:02x?}"
    );
    got
}

fn debug_values(bytes: &[u8]) -> Vec<DebugValue> {
    decode(bytes, Expect::Nothing)
        .into_iter()
        .map(|m| match m {
            Message::Debug(d) => d,
            other => panic!("not a debug frame: {other:?}"),
        })
        .collect()
}

fn value_of(frames: &[DebugValue], id: DebugId) -> i32 {
    frames
        .iter()
        .find(|d| d.number == id as u8)
        .unwrap_or_else(|| panic!("no value {id:?}"))
        .value
}

fn land<const TX: usize>(rig: &mut Rig<TX>) {
    rig.shared.paused = true;
}

// ---------------------------------------------------------------------------------------------
// Debug stream

#[test]
fn debug_stream_at_boot_cycles_through_the_list_with_the_flight_status() {
    let mut rig = Rig::new();
    rig.run(300); // default period 20 ms: frames at 0, 20, .., 280
    let out = rig.take();
    // The first frame, whole: roll at t = 0 is the 20° bank: 2000 = 00 00 07 D0.
    assert_eq!(&out[..7], &[0x1c, 0x01, 0x00, 0x00, 0x07, 0xd0, 0xd6]);
    // The flight status frame: flying (the simulated flight runs, telemetry not paused).
    assert_eq!(&out[out.len() - 7..], &[0x1c, 0x56, 0, 0, 0, 1, 0x57]);
    let frames = debug_values(&out);
    let numbers: Vec<u8> = frames.iter().map(|d| d.number).collect();
    assert_eq!(numbers, [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 86]);
    // The default flight: 50 m/s, 20° right bank, 1000 m, level.
    assert_eq!(value_of(&frames, DebugId::Pitch), 0);
    assert_eq!(value_of(&frames, DebugId::Airspeed), 5000);
    assert_eq!(value_of(&frames, DebugId::Altitude), 100_000);
    // ISA at 1000 m: 101325 * (1 - 0.0065 * 1000 / 288.15)^5.2559 = 89874.6 Pa, 8.50 °C.
    assert!((value_of(&frames, DebugId::StaticPressure) - 89_875).abs() <= 2);
    assert_eq!(value_of(&frames, DebugId::Temperature), 850);
    // q = rho/2 * V^2 with rho(1000 m) = 1.1117 kg/m^3: 1389.6 Pa.
    assert!((value_of(&frames, DebugId::PitotPressure) - 1390).abs() <= 2);
    // Turn rate g * tan(20°) / V = 4.090 °/s.
    assert!((value_of(&frames, DebugId::TurnRate) - 409).abs() <= 1);
    // Start position 48.3538 N 11.7861 E, moved at most a few metres in 0.3 s.
    assert!((value_of(&frames, DebugId::Latitude) - 483_538_000).abs() < 2_000);
    assert!((value_of(&frames, DebugId::Longitude) - 117_861_000).abs() < 2_000);
    // Heading starts at 0 and turns right at ~4°/s: after 40 ms it is a small positive angle.
    let heading = value_of(&frames, DebugId::Heading);
    assert!((0..100).contains(&heading), "heading {heading}");
    let gs = value_of(&frames, DebugId::GroundSpeed);
    assert!((4500..=5500).contains(&gs), "ground speed {gs}");
    assert_eq!(value_of(&frames, DebugId::ControlSource), 0);
    assert_eq!(value_of(&frames, DebugId::MotorTestMask), 0);
    assert_eq!(value_of(&frames, DebugId::FlightStatus), STATUS_FLYING);
    assert_eq!(rig.link.counters().debug_frames, 15);
}

#[test]
fn debug_rate_follows_the_setting() {
    let mut rig = Rig::new();
    rig.shared.persisted.settings.aok_debug_period_ms = 50;
    rig.run(1000);
    let frames = debug_values(&rig.take());
    assert_eq!(frames.len(), 20);
    // 86 is sent once per cycle of 15.
    assert_eq!(frames.iter().filter(|d| d.number == 86).count(), 1);
    assert_eq!(frames[15].number, 1);

    // Period 0: as fast as the link takes them; here one per poll.
    rig.shared.persisted.settings.aok_debug_period_ms = 0;
    rig.run(150);
    let frames = debug_values(&rig.take());
    assert_eq!(frames.len(), 150);
    assert_eq!(frames.iter().filter(|d| d.number == 86).count(), 10);
}

#[test]
fn late_debug_frames_after_debug_off_are_only_what_was_queued() {
    // A port whose TX queue holds 15 bytes: the line is slow, frames back up.
    let mut rig = Rig::with(Persisted::default(), ports::<16>());
    rig.shared.persisted.settings.aok_debug_period_ms = 0;
    rig.run(10);
    let before = debug_values(&rig.take()).len();
    assert_eq!(before, 10);
    // The line stalls: nothing leaves the port for 20 ms.
    rig.draining = false;
    rig.run(20);
    // 15 bytes in the port, 6 in the link: two whole frames and one split between them.
    assert_eq!(rig.link.tx_pending(), 6);
    let queued = rig.link.counters().debug_frames;
    assert_eq!(queued, 13);
    rig.cmd(Command::DebugOff);
    rig.settle();
    assert!(!rig.link.debug_enabled());
    rig.draining = true;
    rig.run(500);
    let late = debug_values(&rig.take());
    // Exactly the three frames already queued, complete; nothing was built after debug-off.
    assert_eq!(late.len(), 3);
    assert_eq!(rig.link.counters().debug_frames, queued);
    assert_eq!(
        late.iter().map(|d| d.number).collect::<Vec<_>>(),
        [11, 12, 13]
    );
    // Debug on: the stream resumes where the cycle was.
    let out = rig.exchange_cmd(Command::DebugOn);
    assert_eq!(debug_values(&out)[0].number, 14);
}

#[test]
fn debug_off_then_silence_then_on() {
    let mut rig = Rig::new();
    rig.run(100);
    rig.quiet();
    rig.run(1000);
    assert_eq!(rig.take(), []);
    rig.cmd(Command::DebugOn);
    rig.run(100);
    assert_eq!(debug_values(&rig.take()).len(), 5);
}

// ---------------------------------------------------------------------------------------------
// Reset

#[test]
fn reset_requests_a_reboot_landed_and_is_refused_in_flight() {
    let mut rig = Rig::new();
    rig.quiet();
    // Flying: refused with 'I', like every other state change.
    assert_eq!(rig.exchange(&[0x63, 0x07]), b"I");
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().refused_in_flight, 1);
    land(&mut rig);
    rig.send(&[0x63, 0x07]);
    rig.poll();
    // Not before the silence after it is observed.
    assert!(!rig.shared.requests.reboot);
    rig.settle();
    assert!(rig.shared.requests.reboot);
    assert_eq!(rig.take(), []);
}

// ---------------------------------------------------------------------------------------------
// Parameters

#[test]
fn set_and_get_parameters_with_acks() {
    let mut rig = Rig::new();
    rig.quiet();
    // 73 NUM B1..B4 CRC: parameter 5 = 1500, CRC = 05^00^00^05^DC.
    assert_eq!(
        rig.exchange(&[0x73, 0x05, 0x00, 0x00, 0x05, 0xdc, 0xdc]),
        b"O"
    );
    assert_eq!(rig.link.parameters()[5], 1500);
    // 67 05: FF 05 00 00 05 DC D9 (CRC over B1..B4 only).
    assert_eq!(
        rig.exchange(&[0x67, 0x05]),
        [0xff, 0x05, 0x00, 0x00, 0x05, 0xdc, 0xd9]
    );
    // Negative values, MSB first: parameter 0 = -2.
    assert_eq!(
        rig.exchange(&[0x73, 0x00, 0xff, 0xff, 0xff, 0xfe, 0x01]),
        b"O"
    );
    assert_eq!(
        rig.exchange(&[0x67, 0x00]),
        [0xff, 0x00, 0xff, 0xff, 0xff, 0xfe, 0x01]
    );
    // Parameter 32 does not exist (AOK_PARAMS = 32): 'E', nothing changes.
    assert_eq!(
        rig.exchange_cmd(Command::SetParameter(ParameterValue {
            number: 32,
            value: 1
        })),
        b"E"
    );
    // A bad checksum: 'E', parameter 5 keeps 1500.
    assert_eq!(
        rig.exchange(&[0x73, 0x05, 0x00, 0x00, 0x00, 0x07, 0x00]),
        b"E"
    );
    assert_eq!(rig.link.parameters()[5], 1500);
    // Reading past the table answers 0: 67 28 (40).
    assert_eq!(rig.exchange(&[0x67, 0x28]), [0xff, 0x28, 0, 0, 0, 0, 0]);
    assert_eq!(rig.link.counters().rejected, 2);
}

#[test]
fn non_in_flight_parameters_are_refused_while_flying() {
    let mut rig = Rig::new();
    rig.quiet();
    // Flying: parameter 17 (not in flight) -> 'I', unchanged; parameter 15 (in flight) -> 'O'.
    assert_eq!(
        rig.exchange(&[0x73, 0x11, 0x00, 0x00, 0x04, 0xd2, 0xc7]),
        b"I"
    );
    assert_eq!(rig.link.parameters()[17], 0);
    assert_eq!(
        rig.exchange_cmd(Command::SetParameter(ParameterValue {
            number: 15,
            value: 7
        })),
        b"O"
    );
    assert_eq!(rig.link.parameters()[15], 7);
    assert_eq!(rig.link.counters().refused_in_flight, 1);
    // The flight status says flying.
    let status = rig
        .link
        .debug_value(DebugId::FlightStatus, rig.now, &rig.shared);
    assert_eq!(status & STATUS_FLYING, STATUS_FLYING);
    // Landed ("a pause" on AEOLUS): parameter 17 is accepted.
    land(&mut rig);
    assert_eq!(
        rig.link
            .debug_value(DebugId::FlightStatus, rig.now, &rig.shared),
        0
    );
    assert_eq!(
        rig.exchange(&[0x73, 0x11, 0x00, 0x00, 0x04, 0xd2, 0xc7]),
        b"O"
    );
    assert_eq!(rig.link.parameters()[17], 1234);
}

#[test]
fn bulk_read_answers_sixteen_replies_and_zero_past_the_table() {
    let mut persisted = Persisted::default();
    for (i, p) in persisted.aok.sets[0].iter_mut().enumerate() {
        *p = 100 * i as i32 - 1000;
    }
    let mut rig = Rig::with(persisted, ports::<1024>());
    rig.quiet();
    // Parameters come from the start set (0) at boot.
    assert_eq!(rig.link.parameters()[31], 2100);
    let out = rig.exchange(&[0x47, 0x00]);
    assert_eq!(out.len(), 112);
    assert_eq!(&out[..7], &[0xff, 0x00, 0xff, 0xff, 0xfc, 0x18, 0xe4]); // -1000
    assert_eq!(&out[105..], &[0xff, 0x0f, 0x00, 0x00, 0x01, 0xf4, 0xf5]); // 500
    let replies = decode(&out, Expect::Bulk(0));
    assert_eq!(replies.len(), 16);
    for (i, m) in replies.iter().enumerate() {
        assert_eq!(
            *m,
            Message::Parameter(ParameterValue {
                number: i as u8,
                value: 100 * i as i32 - 1000
            })
        );
    }
    // 47 1C: 28..=31 from the table, 32..=43 answered 0.
    let replies = decode(&rig.exchange(&[0x47, 0x1c]), Expect::Bulk(0x1c));
    let values: Vec<(u8, i32)> = replies
        .iter()
        .map(|m| match m {
            Message::Parameter(p) => (p.number, p.value),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        &values[..5],
        &[(28, 1800), (29, 1900), (30, 2000), (31, 2100), (32, 0)]
    );
    assert_eq!(values[15], (43, 0));
    // 47 FA: numbers wrap at 255 (250..=255, then 0..=9).
    let replies = decode(&rig.exchange(&[0x47, 0xfa]), Expect::Bulk(0xfa));
    assert_eq!(
        replies[6],
        Message::Parameter(ParameterValue {
            number: 0,
            value: -1000
        })
    );
    assert_eq!(
        replies[15],
        Message::Parameter(ParameterValue {
            number: 9,
            value: -100
        })
    );
}

// ---------------------------------------------------------------------------------------------
// Parameter sets

#[test]
fn save_load_and_start_set_change_the_flash_record() {
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    for (n, v) in [(0u8, 11), (17, 1234), (31, -5)] {
        let out = rig.exchange_cmd(Command::SetParameter(ParameterValue {
            number: n,
            value: v,
        }));
        assert_eq!(out, b"O");
    }
    // 63 04 02: save into set 2 -> 'O' and a flash write requested.
    assert_eq!(rig.exchange(&[0x63, 0x04, 0x02]), b"O");
    assert!(std::mem::take(&mut rig.shared.requests.store));
    let set2 = rig.shared.persisted.aok.sets[2];
    assert_eq!((set2[0], set2[17], set2[31], set2[1]), (11, 1234, -5, 0));
    assert_eq!(rig.shared.persisted.aok.sets[0], [0; 32]);
    // Change RAM, then 63 03 02 loads set 2 back (no flash write).
    assert_eq!(
        rig.exchange(&[0x73, 0x11, 0x00, 0x00, 0x00, 0x01, 0x10]),
        b"O"
    );
    assert_eq!(rig.link.parameters()[17], 1);
    assert_eq!(rig.exchange(&[0x63, 0x03, 0x02]), b"O");
    assert_eq!(rig.link.parameters()[17], 1234);
    assert!(!rig.shared.requests.store);
    // 63 03 00 loads the empty set 0.
    assert_eq!(rig.exchange(&[0x63, 0x03, 0x00]), b"O");
    assert_eq!(rig.link.parameters(), &[0; 32]);
    // 63 05 02: start set 2.
    assert_eq!(rig.shared.persisted.aok.start_set, 0);
    assert_eq!(rig.exchange(&[0x63, 0x05, 0x02]), b"O");
    assert_eq!(rig.shared.persisted.aok.start_set, 2);
    assert!(std::mem::take(&mut rig.shared.requests.store));
    // Sets 0..=4 exist: 5 is 'E' for all three, nothing changes.
    for sub in [3, 4, 5] {
        assert_eq!(rig.exchange(&[0x63, sub, 0x05]), b"E");
    }
    assert!(!rig.shared.requests.store);
    assert_eq!(rig.shared.persisted.aok.start_set, 2);
    // A new link over the same record (what a reboot does) boots with set 2.
    let link = AokLink::new(&rig.shared);
    assert_eq!(link.parameters()[17], 1234);
    assert_eq!(link.parameters()[31], -5);
}

#[test]
fn set_commands_are_refused_while_flying() {
    let mut persisted = Persisted::default();
    persisted.aok.sets[1][3] = 33;
    let mut rig = Rig::with(persisted, ports::<1024>());
    rig.quiet();
    assert_eq!(rig.exchange(&[0x63, 0x04, 0x01]), b"I");
    assert_eq!(rig.exchange(&[0x63, 0x03, 0x01]), b"I");
    assert_eq!(rig.exchange(&[0x63, 0x05, 0x01]), b"I");
    assert_eq!(rig.exchange(&[0x63, 0x08]), b"I");
    assert!(!rig.shared.requests.store);
    assert_eq!(rig.shared.persisted.aok.sets[1][3], 33);
    assert_eq!(rig.shared.persisted.aok.start_set, 0);
    assert_eq!(rig.link.parameters()[3], 0);
    assert_eq!(rig.link.counters().refused_in_flight, 4);
    // An unknown set is an error first, flying or not.
    assert_eq!(rig.exchange(&[0x63, 0x04, 0x09]), b"E");
}

#[test]
fn stores_past_the_rate_limit_are_answered_e_and_change_nothing() {
    use sensor_box::store_policy::{STORE_BURST, STORE_INTERVAL_MS};
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    // A PC saving everything at once: the burst.
    for n in 0..5u8 {
        assert_eq!(rig.exchange(&[0x63, 0x04, n]), b"O");
    }
    assert_eq!(rig.exchange(&[0x63, 0x05, 0x01]), b"O");
    assert_eq!(rig.exchange(&[0x63, 0x08]), b"O");
    let mut poi = WP3;
    poi.slot = WaypointSlot::MissionPoi;
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(poi)), b"O");
    assert_eq!(STORE_BURST, 8);
    // The ninth within the minute: 'E', counted, and neither the record nor RAM touched.
    let p3 = ParameterValue {
        number: 3,
        value: 42,
    };
    assert_eq!(rig.exchange_cmd(Command::SetParameter(p3)), b"O");
    let before = rig.shared.persisted.clone();
    for command in [&[0x63, 0x04, 0x02][..], &[0x63, 0x05, 0x03], &[0x63, 0x08]] {
        assert_eq!(rig.exchange(command), b"E");
    }
    poi.longitude = 1;
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(poi)), b"E");
    assert_eq!(rig.shared.persisted, before);
    assert_eq!(rig.shared.counters.stores_rate_limited, 4);
    assert_eq!(rig.link.counters().rejected, 4);
    // A minute later one more store is allowed.
    rig.now += STORE_INTERVAL_MS;
    assert_eq!(rig.exchange(&[0x63, 0x04, 0x02]), b"O");
    assert_eq!(rig.shared.persisted.aok.sets[2][3], 42);
    assert_eq!(rig.exchange(&[0x63, 0x04, 0x02]), b"E");
}

// ---------------------------------------------------------------------------------------------
// Waypoints

const WP3: Waypoint = Waypoint {
    slot: WaypointSlot::Waypoint(match WaypointNumber::new(1) {
        Ok(n) => n,
        Err(_) => panic!(),
    }),
    longitude: 0x1122_3344,
    latitude: 0x5566_7788u32 as i32,
    action1: ActionWord::new(Action::Pause, 10),
    action2: ActionWord::NONE,
};

/// The `77` frame of WP3 in slot 0, written out by hand (MSB first, CRC = XOR of NUM..D4).
const WP3_FRAME: [u8; 19] = [
    0x77, 0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x00, 0x01, 0x80, 0x0a, 0x00, 0x00,
    0x80, 0x00, 0x83,
];

#[test]
fn waypoints_set_and_read_in_ram() {
    let mut rig = Rig::new();
    rig.quiet();
    // Flying does not matter for RAM waypoints.
    assert_eq!(rig.exchange(&WP3_FRAME), b"O");
    assert_eq!(rig.exchange(&[0x78, 0x00]), WP3_FRAME);
    // The POI in RAM (254) and the FBC target (255).
    let poi = Waypoint {
        slot: WaypointSlot::RamPoi,
        longitude: -2,
        latitude: 246,
        action1: ActionWord::new(Action::SetFlySpeed, 100),
        action2: ActionWord::NONE,
    };
    let mut frame = [0u8; aok_proto::command::MAX_COMMAND_LEN];
    Command::SetWaypoint(poi).emit(&mut frame).unwrap();
    assert_eq!(
        frame,
        [
            0x77, 0xfe, 0xff, 0xff, 0xff, 0xfe, 0x00, 0x00, 0x00, 0xf6, 0x00, 0x06, 0x80, 0x64,
            0x00, 0x00, 0x80, 0x00, 0x6b
        ]
    );
    assert_eq!(rig.exchange(&frame), b"O");
    let fbc = Waypoint {
        slot: WaypointSlot::FbcTarget,
        ..poi
    };
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(fbc)), b"O");
    assert_eq!(
        decode(&rig.exchange(&[0x78, 0xfe]), Expect::Nothing),
        [Message::Waypoint(poi)]
    );
    assert_eq!(
        decode(&rig.exchange(&[0x78, 0xff]), Expect::Nothing),
        [Message::Waypoint(fbc)]
    );
    // An unset slot reads 0/0 with zero action words.
    let out = rig.exchange(&[0x78, 0x1e]);
    assert_eq!(out, {
        let mut f = [0u8; 19];
        f[0] = 0x77;
        f[1] = 0x1e;
        f[18] = 0x1e;
        f
    });
    // Nothing of this went to flash.
    assert!(!rig.shared.requests.store);
    assert_eq!(
        rig.shared.persisted.aok.waypoints,
        Persisted::default().aok.waypoints
    );
    // Slot 32 does not exist: a 77 with a good checksum is answered 'E'; so is a bad checksum.
    // The decoder drops only its first byte (docs/protocol-notes.md, AOK item 4) and its
    // rescan of the frame's body meets one more false start with a bad checksum and a partial
    // one that the silence after the burst cuts short: the burst is discarded whole and
    // answered one 'E'.
    let mut bad = WP3_FRAME;
    bad[1] = 0x20;
    bad[18] ^= 0x20;
    rig.send(&bad);
    rig.run(GAP_MS + 10);
    assert_eq!(rig.take(), b"E");
    assert_eq!(rig.link.counters().bursts_discarded, 1);
    assert_eq!(rig.exchange(&[0x78, 0x20]), b"E");
    // (A frame whose bytes hold no other command start: the rescan after a bad checksum
    // finds nothing else to answer.)
    let mut bad = [0u8; 19];
    bad[0] = 0x77;
    bad[1] = 0x1e;
    bad[18] = 0x1f; // should be 0x1e
    assert_eq!(rig.exchange(&bad), b"E");
    assert_eq!(rig.exchange(&[0x78, 0x00]), WP3_FRAME);
}

#[test]
fn waypoints_move_between_ram_and_flash() {
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    assert_eq!(rig.exchange(&WP3_FRAME), b"O");
    let poi = Waypoint {
        slot: WaypointSlot::RamPoi,
        longitude: 7,
        latitude: 8,
        action1: ActionWord::NONE,
        action2: ActionWord::NONE,
    };
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(poi)), b"O");
    // 63 08: RAM -> flash; the RAM POI (254) overwrites the mission POI (31).
    assert_eq!(rig.exchange(&[0x63, 0x08]), b"O");
    assert!(std::mem::take(&mut rig.shared.requests.store));
    let flash = &rig.shared.persisted.aok.waypoints;
    assert_eq!(
        flash[0],
        StoredWaypoint {
            lon: 0x1122_3344,
            lat: 0x5566_7788u32 as i32,
            action1: 0x0001_800a,
            action2: 0x0000_8000
        }
    );
    assert_eq!(
        flash[31],
        StoredWaypoint {
            lon: 7,
            lat: 8,
            action1: 0x8000,
            action2: 0x8000
        }
    );
    // 78 1F reads the mission POI from flash.
    let mission_poi = Waypoint {
        slot: WaypointSlot::MissionPoi,
        ..poi
    };
    assert_eq!(
        decode(&rig.exchange(&[0x78, 0x1f]), Expect::Nothing),
        [Message::Waypoint(mission_poi)]
    );
    // RAM changes: waypoint 1 moved, POI moved.
    let moved = Waypoint {
        longitude: 1,
        latitude: 1,
        ..WP3
    };
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(moved)), b"O");
    assert_eq!(
        rig.exchange_cmd(Command::SetWaypoint(Waypoint {
            longitude: 99,
            ..poi
        })),
        b"O"
    );
    // `77 1F` writes the flash mission POI directly (and asks for a flash write).
    let new_mission_poi = Waypoint {
        longitude: 50,
        latitude: 60,
        ..mission_poi
    };
    assert_eq!(
        rig.exchange_cmd(Command::SetWaypoint(new_mission_poi)),
        b"O"
    );
    assert!(std::mem::take(&mut rig.shared.requests.store));
    assert_eq!(rig.shared.persisted.aok.waypoints[31].lon, 50);
    // 63 09: flash -> RAM; waypoint 1 is back, and the mission POI (31) goes to the RAM POI.
    assert_eq!(rig.exchange(&[0x63, 0x09]), b"O");
    assert!(!rig.shared.requests.store);
    assert_eq!(rig.exchange(&[0x78, 0x00]), WP3_FRAME);
    assert_eq!(
        decode(&rig.exchange(&[0x78, 0xfe]), Expect::Nothing),
        [Message::Waypoint(Waypoint {
            slot: WaypointSlot::RamPoi,
            ..new_mission_poi
        })]
    );
}

#[test]
fn mission_poi_in_flash_is_refused_while_flying() {
    let mut rig = Rig::new();
    rig.quiet();
    let w = Waypoint {
        slot: WaypointSlot::MissionPoi,
        ..WP3
    };
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(w)), b"I");
    assert!(!rig.shared.requests.store);
    // 63 09 (no flash write, but no check of its own either: `67 09` with one bit flipped)
    // is refused in flight, and the RAM waypoints stay as they are.
    assert_eq!(rig.exchange_cmd(Command::SetWaypoint(WP3)), b"O");
    assert_eq!(rig.exchange(&[0x63, 0x09]), b"I");
    assert_eq!(rig.exchange(&[0x78, 0x00]), WP3_FRAME);
    assert_eq!(rig.link.counters().refused_in_flight, 2);
}

// ---------------------------------------------------------------------------------------------
// Motor test

#[test]
fn motor_test_values_lapse_500_ms_after_the_last_frame() {
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    // 31 64 55: motor 1 = 100 (CRC = 0x31 ^ 0x64); 43 20 63: motor 12 = 32. The first burst
    // arms both motors, the second, 20 ms later, runs them when the silence after it is
    // observed, GAP_MS after it arrived: `start`.
    rig.send(&[0x31, 0x64, 0x55, 0x43, 0x20, 0x63]);
    rig.run(20);
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    assert_eq!(rig.link.counters().motor_frames_armed, 2);
    let start = rig.now + GAP_MS;
    rig.send(&[0x31, 0x64, 0x55, 0x43, 0x20, 0x63]);
    rig.run(GAP_MS);
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    rig.run(1);
    let mut expect = [0u8; 12];
    expect[0] = 100;
    expect[11] = 32;
    assert_eq!(rig.link.motor_outputs(), expect);
    assert_eq!(
        rig.link
            .debug_value(DebugId::MotorTestMask, rig.now, &rig.shared),
        0x801
    );
    assert_eq!(
        rig.link
            .debug_value(DebugId::FlightStatus, rig.now, &rig.shared),
        STATUS_MOTOR_TEST
    );
    // Motor 12 is refreshed at +300 ms (sent at +298); motor 1 is not.
    rig.run(297);
    assert_eq!(rig.now, start + 300 - GAP_MS);
    rig.send(&[0x43, 0x20, 0x63]);
    rig.run(199 + GAP_MS);
    assert_eq!(rig.now, start + 499);
    rig.poll();
    assert_eq!(rig.link.motor_outputs()[0], 100); // +499: still held
    rig.now += 1;
    rig.poll();
    assert_eq!(rig.link.motor_outputs()[0], 0); // +500: lapsed
    assert_eq!(rig.link.motor_outputs()[11], 32);
    rig.now = start + 300 + MOTOR_LAPSE_MS - 1;
    rig.poll();
    assert_eq!(rig.link.motor_outputs()[11], 32);
    rig.now += 1;
    rig.poll();
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    assert_eq!(
        rig.link
            .debug_value(DebugId::MotorTestMask, rig.now, &rig.shared),
        0
    );
    // No ack for motor test; a bad checksum is 'E' and changes nothing.
    assert_eq!(rig.take(), []);
    assert_eq!(rig.exchange(&[0x35, 0x10, 0x00]), b"E");
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
}

#[test]
fn motor_test_is_ignored_while_flying() {
    let mut rig = Rig::new();
    rig.quiet();
    let test = MotorTest {
        motor: Motor::new(4).unwrap(),
        value: 200,
    };
    assert_eq!(rig.exchange_cmd(Command::MotorTest(test)), []);
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    assert_eq!(rig.link.counters().refused_in_flight, 1);
    land(&mut rig);
    rig.exchange_cmd(Command::MotorTest(test));
    rig.exchange_cmd(Command::MotorTest(test));
    assert_eq!(rig.link.motor_outputs()[3], 200);
}

/// A motor at rest runs only from the second valid frame for it, in a later burst within the
/// 500 ms hold of the first: a glitch (one burst) never starts one. Once it runs, each frame
/// holds it; value 0 stops it at once; after a lapse it needs two frames again.
#[test]
fn a_motor_runs_only_from_a_second_frame_within_the_hold() {
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    let frame = |motor: u8, value: u8| {
        let test = MotorTest {
            motor: Motor::new(motor).unwrap(),
            value,
        };
        let mut bytes = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = Command::MotorTest(test).emit(&mut bytes).unwrap();
        bytes[..n].to_vec()
    };
    // One frame: armed, nothing driven, however long the box waits.
    assert_eq!(rig.exchange(&frame(2, 50)), []);
    rig.run(MOTOR_LAPSE_MS);
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    // The second frame comes too late (over 500 ms after the first): armed again, no output.
    assert_eq!(rig.exchange(&frame(2, 50)), []);
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    // Two frames for the same motor in one burst are one burst: no output.
    rig.run(MOTOR_LAPSE_MS);
    let mut twice = frame(5, 60);
    twice.extend(frame(5, 60));
    rig.exchange(&twice);
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    // A frame for another motor does not complete motor 5's pair.
    rig.exchange(&frame(6, 60));
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    // Motor 5's own repeat, within the hold of its first frame and in a later burst: it runs.
    rig.run(100);
    rig.exchange(&frame(5, 70));
    assert_eq!(rig.link.motor_outputs()[4], 70);
    assert_eq!(rig.link.counters().motor_frames_armed, 5);
    // Running: one frame sets the value; value 0 stops it at once.
    rig.exchange(&frame(5, 80));
    assert_eq!(rig.link.motor_outputs()[4], 80);
    rig.exchange(&frame(5, 0));
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    // After the stop (or a lapse) one frame is not enough again.
    rig.run(10);
    rig.exchange(&frame(5, 80));
    assert_eq!(rig.link.motor_outputs(), [0; 12]);
    assert_eq!(rig.link.counters().motor_frames_armed, 6);
}

// ---------------------------------------------------------------------------------------------
// External control

#[test]
fn external_control_expires_back_to_rc() {
    let mut rig = Rig::new();
    rig.quiet();
    assert_eq!(rig.link.control_source(), ControlSource::Rc);
    // The spec's example: roll 32, nick -32, yaw 0, pitch 0, expiry 500 ms. Obeyed (`start`)
    // when the silence after it is observed.
    rig.send(&[
        0x53, 0x20, 0x00, 0xe0, 0xff, 0x00, 0x00, 0x00, 0x00, 0xf4, 0x01, 0xca,
    ]);
    rig.poll();
    assert_eq!(rig.link.control_source(), ControlSource::Rc);
    let start = rig.now + GAP_MS;
    rig.now = start;
    rig.poll();
    assert_eq!(rig.link.control_source(), ControlSource::External);
    let sticks = rig.link.external_control().unwrap();
    assert_eq!(
        (
            sticks.roll.get(),
            sticks.nick.get(),
            sticks.yaw.get(),
            sticks.expiry_ms
        ),
        (32, -32, 0, 500)
    );
    assert_eq!(
        rig.link
            .debug_value(DebugId::ControlSource, rig.now, &rig.shared),
        1
    );
    assert_eq!(
        rig.link
            .debug_value(DebugId::FlightStatus, rig.now, &rig.shared),
        STATUS_FLYING | STATUS_EXTERNAL
    );
    rig.now = start + 499;
    rig.poll();
    assert_eq!(rig.link.control_source(), ControlSource::External);
    rig.now = start + 500;
    rig.poll();
    assert_eq!(rig.link.control_source(), ControlSource::Rc);
    assert_eq!(rig.link.external_control(), None);
    assert_eq!(
        rig.link
            .debug_value(DebugId::ControlSource, rig.now, &rig.shared),
        0
    );

    // A new frame before the expiry extends it: frames at +0 and +300 with 400 ms each, each
    // obeyed GAP_MS after it arrived.
    let frame = |roll| {
        Command::ExternalControl(ExternalControl {
            roll: Stick::new(roll).unwrap(),
            nick: Stick::CENTER,
            yaw: Stick::new(-200).unwrap(),
            pitch: 0,
            expiry_ms: 400,
        })
    };
    let t0 = rig.now;
    rig.cmd(frame(10));
    rig.settle();
    rig.now = t0 + 300;
    rig.cmd(frame(20));
    rig.settle();
    rig.now = t0 + 699 + GAP_MS;
    rig.poll();
    assert_eq!(rig.link.external_control().unwrap().roll.get(), 20);
    rig.now = t0 + 700 + GAP_MS;
    rig.poll();
    assert_eq!(rig.link.control_source(), ControlSource::Rc);
    // External control has no ack.
    assert_eq!(rig.take(), []);
}

#[test]
fn external_control_with_a_stick_beyond_200_is_ignored() {
    let mut rig = Rig::new();
    rig.quiet();
    // Roll 201 (C9 00), good checksum: consumed, no ack, control stays with RC.
    let body = [0xc9, 0x00, 0, 0, 0, 0, 0, 0, 0xf4, 0x01];
    let crc = body.iter().fold(0, |a, b| a ^ b);
    let mut frame = vec![0x53];
    frame.extend(body);
    frame.push(crc);
    assert_eq!(rig.exchange(&frame), []);
    assert_eq!(rig.link.control_source(), ControlSource::Rc);
    assert_eq!(rig.link.decoder_stats().invalid, 1);
}

// ---------------------------------------------------------------------------------------------
// Robustness

/// A UART receive error (framing, noise, overrun, parity) or a byte dropped by a full ring
/// is line activity that spoils the burst it falls in: inside a command, or between the last
/// silence and the command, the command is discarded; after a silence it is obeyed again.
#[test]
fn a_line_fault_inside_or_before_a_burst_discards_it() {
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    // `63 07` with a framing error between its bytes (the UART hands both bytes over).
    let mut uart = [Ok(0x63), Err(()), Ok(0x07)].into_iter();
    rig.isr.receive_while(|| uart.next());
    rig.settle();
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().line_faults, 1);
    assert_eq!(rig.link.counters().bursts_discarded, 1);
    // A fault a poll sees before the command arrives, with no silence between them.
    rig.run(10);
    rig.isr.receive_error();
    rig.poll();
    rig.now += 1;
    rig.send(&[0x63, 0x07]);
    rig.settle();
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().bursts_discarded, 2);
    // A fault in the poll right after the command's bytes, before the silence is observed.
    rig.run(10);
    rig.send(&[0x63, 0x07]);
    rig.poll();
    rig.isr.receive_error();
    rig.now += 1;
    rig.settle();
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().bursts_discarded, 3);
    // After the silence that follows a fault, the same command is obeyed.
    rig.run(10);
    assert_eq!(rig.exchange(&[0x63, 0x07]), []);
    assert!(std::mem::take(&mut rig.shared.requests.reboot));
    assert_eq!(rig.link.counters().line_faults, 3);
    assert_eq!(rig.link.counters().bursts_discarded, 3);
}

/// A PC polling the box while it stores (a flash erase stalls the main loop for 1.5 s): 7 reads
/// and a set, one write each, 150 ms apart, wait in the RX ring. The UART handler, told the
/// board's millisecond (`SerialIsr::at`), marks where the line fell silent, and when the main
/// loop comes back every command is answered, late, in order. A handler that marks nothing
/// (the boards before) loses them all: 8 commands in one burst are discarded unanswered.
#[test]
fn a_pc_polling_through_a_store_stall_gets_every_answer() {
    for marked in [true, false] {
        let mut rig = Rig::new();
        rig.quiet();
        land(&mut rig);
        let t0 = rig.now;
        let mut commands: Vec<Command> = (0..7).map(Command::ReadParameter).collect();
        commands.insert(
            3,
            Command::SetParameter(ParameterValue {
                number: 20,
                value: 77,
            }),
        );
        for (i, c) in commands.iter().enumerate() {
            let mut frame = [0u8; aok_proto::command::MAX_COMMAND_LEN];
            let n = c.emit(&mut frame).unwrap();
            for &b in &frame[..n] {
                if marked {
                    rig.isr.at(t0 + 150 * i as u64);
                }
                assert!(rig.isr.received(b));
            }
        }
        // The stall ends 1.5 s later: the polls resume.
        rig.now = t0 + 1_500;
        rig.run(10);
        let out = rig.take();
        if marked {
            let mut want = Vec::new();
            for n in 0..7u8 {
                want.extend([0xff, n, 0, 0, 0, 0, 0]);
                if n == 2 {
                    want.push(b'O');
                }
            }
            assert_eq!(out, want);
            assert_eq!(rig.link.parameters()[20], 77);
            assert_eq!(rig.link.counters().bursts_discarded, 0);
        } else {
            assert_eq!(out, []);
            assert_eq!(rig.link.parameters()[20], 0);
            assert_eq!(rig.link.counters().bursts_discarded, 1);
        }
    }
}

/// Burst marks are as strict as the link's own silence: bytes with less than `GAP_MS` between
/// them by the handler's clock stay one burst (a stray byte before a reset spoils it), a line
/// fault among commands that waited spoils every burst taken in that poll, and noise that
/// waited in the ring obeys nothing.
#[test]
fn burst_marks_frame_nothing_the_link_would_not() {
    let mut rig = Rig::new();
    rig.quiet();
    land(&mut rig);
    let t0 = rig.now;
    // `00` then `63 07` 1 ms later: one burst, discarded.
    rig.isr.at(t0);
    rig.isr.received(0x00);
    rig.isr.at(t0 + 1);
    rig.send(&[0x63, 0x07]);
    rig.now = t0 + 500;
    rig.run(5);
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().bursts_discarded, 1);
    // Two commands apart in time, a receive error among them: both discarded.
    let t1 = rig.now + 10;
    rig.isr.at(t1);
    rig.send(&[0x63, 0x07]);
    rig.isr.at(t1 + 100);
    rig.isr.receive_error();
    rig.isr.at(t1 + 200);
    rig.send(&[0x67, 0x01]);
    rig.now = t1 + 1_000;
    rig.run(5);
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.take(), []);
    assert_eq!(rig.link.counters().bursts_discarded, 3);
    // And with nothing wrong, the same two are obeyed.
    let t2 = rig.now + 10;
    rig.isr.at(t2);
    rig.send(&[0x63, 0x07]);
    rig.isr.at(t2 + 200);
    rig.send(&[0x67, 0x01]);
    rig.now = t2 + 1_000;
    rig.run(5);
    assert!(rig.shared.requests.reboot);
    assert_eq!(rig.take(), [0xff, 0x01, 0, 0, 0, 0, 0]);
}

/// A byte lost to a full RX ring spoils its burst too: `63 07 00` is garbage (the decoder
/// throws the `00` away, so the burst is discarded), but with the `00` dropped the rest reads
/// as a reset.
#[test]
fn a_byte_dropped_by_a_full_ring_discards_the_burst() {
    let (rxq, txq, stats) = (Ring::<2>::new(), Ring::<64>::new(), PortStats::new());
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    let mut shared = Shared::new(Persisted::default(), 0);
    let mut link = AokLink::new(&shared);
    shared.paused = true;
    // The ring holds two bytes here: the `00` is dropped.
    assert_eq!(
        [0x63, 0x07, 0x00].map(|b| isr.received(b)),
        [true, true, false]
    );
    for now in 0..5 {
        link.poll(now, &mut port, &mut shared);
    }
    assert_eq!(port.counters().rx_dropped, 1);
    assert!(!shared.requests.reboot);
    assert_eq!(link.counters().line_faults, 1);
    assert_eq!(link.counters().bursts_discarded, 1);
}

#[test]
fn garbage_before_a_command_and_a_dead_partial_frame() {
    let mut rig = Rig::new();
    rig.quiet();
    // Noise, a 73 with a bad checksum, then a read, in one burst: not a command as a PC sends
    // it, so nothing of it is obeyed (the read neither); the bad checksum is answered 'E'.
    let out = rig.exchange(&[0x00, 0x12, 0x73, 0x01, 0, 0, 0, 5, 0x00, 0x67, 0x01]);
    assert_eq!(out, b"E");
    assert_eq!(rig.link.decoder_stats().frames_ok, 2); // 63 01 and the read, found
    assert_eq!(rig.link.counters().bursts_discarded, 1);
    // The read on its own, framed by silence, is answered.
    assert_eq!(rig.exchange(&[0x67, 0x01]), [0xff, 0x01, 0, 0, 0, 0, 0]);
    // A partial 73 and then silence: after GAP_MS it is abandoned with its burst, so the read
    // that follows is not swallowed as its body.
    rig.send(&[0x73, 0x01]);
    rig.settle();
    assert_eq!(rig.link.decoder_stats().abandoned, 1);
    assert_eq!(rig.link.counters().bursts_discarded, 2);
    assert_eq!(rig.exchange(&[0x67, 0x02]), [0xff, 0x02, 0, 0, 0, 0, 0]);
    // Garbage with a reset in it and no decode error (0x00 is skipped): discarded unanswered.
    land(&mut rig);
    assert_eq!(rig.exchange(&[0x00, 0x63, 0x07]), []);
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().bursts_discarded, 3);
    // More than BURST_COMMANDS commands in one burst: discarded.
    let five = [0x67, 0x01].repeat(sensor_box::aok_link::BURST_COMMANDS + 1);
    assert_eq!(rig.exchange(&five), []);
    assert_eq!(rig.link.counters().bursts_discarded, 4);
    // A burst that the poll's RX budget splits is still one burst: a stalled main loop that
    // then finds many bytes at once does not see a gap inside them.
    let mut long = vec![0u8; sensor_box::aok_link::RX_BUDGET];
    long.extend([0x63, 0x07]);
    rig.send(&long);
    rig.now += 100;
    rig.run(10);
    assert!(!rig.shared.requests.reboot);
    assert_eq!(rig.link.counters().bursts_discarded, 5);
}

#[test]
fn a_slow_port_never_blocks_and_loses_no_reply() {
    // The port's TX queue holds 7 bytes: a bulk reply (112 bytes) leaves over 16 polls.
    let mut rig = Rig::with(Persisted::default(), ports::<8>());
    rig.quiet();
    rig.send(&[
        0x47, 0x00, 0x67, 0x03, 0x73, 0x03, 0, 0, 0, 9, 0x0a, 0x67, 0x03,
    ]);
    let mut polls = 0;
    let mut out = Vec::new();
    while out.len() < 112 + 7 + 1 + 7 {
        rig.link.poll(rig.now, &mut rig.port, &mut rig.shared);
        polls += 1;
        // The UART sends at most 7 bytes between two polls.
        for _ in 0..7 {
            out.extend(rig.isr.next_to_send());
        }
        rig.now += 2;
        assert!(polls < 100, "stuck after {} bytes", out.len());
    }
    assert!(polls >= 18);
    let replies = decode(&out[..119], Expect::Bulk(0));
    assert_eq!(replies.len(), 17);
    assert_eq!(
        replies[16],
        Message::Parameter(ParameterValue {
            number: 3,
            value: 0
        })
    );
    assert_eq!(out[119], b'O');
    assert_eq!(&out[120..], &[0xff, 0x03, 0, 0, 0, 9, 9]);
    assert_eq!(rig.link.counters().replies_dropped, 0);
}

// ---------------------------------------------------------------------------------------------
// End to end with the PC-side client, debug stream running

/// The PC's serial port: every read lets the device run at the current simulated time.
struct Wire {
    rig: Rig,
    clock: Rc<Cell<u64>>,
}

impl ErrorType for Wire {
    type Error = core::convert::Infallible;
}

impl Read<u8> for Wire {
    fn read(&mut self) -> nb::Result<u8, Self::Error> {
        self.rig.now = self.clock.get();
        self.rig.poll();
        if self.rig.out.is_empty() {
            Err(nb::Error::WouldBlock)
        } else {
            Ok(self.rig.out.remove(0))
        }
    }
}

impl Write<u8> for Wire {
    fn write(&mut self, byte: u8) -> nb::Result<(), Self::Error> {
        self.rig.send(&[byte]);
        Ok(())
    }

    fn flush(&mut self) -> nb::Result<(), Self::Error> {
        Ok(())
    }
}

#[test]
fn client_reads_and_sets_through_the_debug_stream() {
    let mut rig = Rig::new();
    // The debug stream runs for a while; the PC has not read it yet.
    rig.run(200);
    let clock = Rc::new(Cell::new(rig.now));
    let wire = Wire {
        rig,
        clock: clock.clone(),
    };
    let mut client = Client::new(wire, Config::new(FIRMWARE));
    let tick = || {
        clock.set(clock.get() + 1);
        clock.get() as u32
    };
    assert_eq!(client.set_parameter(3, -77, tick), Ok(()));
    assert_eq!(client.read_parameter(3, tick), Ok(-77));
    assert_eq!(
        client.set_parameter(20, 1, tick),
        Err(ClientError::RefusedInFlight)
    );
    assert_eq!(
        client.set_parameter(40, 1, tick),
        Err(ClientError::Rejected)
    );
    let bulk = client.bulk_read(0, tick).unwrap();
    assert_eq!(bulk[3], -77);
    assert_eq!(bulk[15], 0);
    let w = Waypoint {
        slot: WaypointSlot::Waypoint(WaypointNumber::new(5).unwrap()),
        ..WP3
    };
    assert_eq!(client.set_waypoint(w, tick), Ok(()));
    assert_eq!(client.read_waypoint(w.slot, tick), Ok(w));
    // The client turned debug back on after each request; the device agrees once it has read
    // the `63 02`, and the stream runs again.
    assert!(client.debug_enabled());
    let rig = &mut client.serial_mut().rig;
    rig.out.clear();
    rig.run(100);
    assert!(rig.link.debug_enabled());
    assert_eq!(debug_values(&rig.take()).len(), 5);
}

// ---------------------------------------------------------------------------------------------
// Through the App: reset, and sets and waypoints surviving a reboot

type Port = (
    QueuedSerial<'static, 1024, 1024>,
    SerialIsr<'static, 1024, 1024>,
);

fn app_poll(app: &mut App, now: u64, uarts: &mut [Port; 3], flash: &mut MemFlash<'_>) -> Control {
    let [(u0, i0), (u1, i1), (u2, _)] = uarts;
    let c = app.poll(now, u0, u1, u2, flash);
    while i0.next_to_send().is_some() {}
    while i1.next_to_send().is_some() {}
    c
}

#[test]
fn sets_and_waypoints_survive_a_reboot() {
    let mut mem = vec![0xffu8; 8192];
    let mut flash = MemFlash::new(&mut mem);
    let mut uarts = [ports::<1024>(), ports::<1024>(), ports::<1024>()];
    let mut app = App::new(&mut flash, 0);
    app.shared.paused = true;
    let mut now = 0;
    let mut run = |app: &mut App, uarts: &mut [Port; 3], bytes: &[u8]| {
        for &b in bytes {
            assert!(uarts[2].1.received(b));
        }
        let mut control = Control::Run;
        for _ in 0..5 {
            if app_poll(app, now, uarts, &mut flash) == Control::Reboot {
                control = Control::Reboot;
            }
            now += 1;
        }
        let mut out = Vec::new();
        while let Some(b) = uarts[2].1.next_to_send() {
            out.push(b);
        }
        (control, out)
    };
    run(&mut app, &mut uarts, &[0x63, 0x01]);
    // Parameter 17 = 1234 into set 3, set 3 as the start set, waypoint 1 and the POI to flash.
    let steps: [&[u8]; 5] = [
        &[0x73, 0x11, 0x00, 0x00, 0x04, 0xd2, 0xc7],
        &[0x63, 0x04, 0x03],
        &[0x63, 0x05, 0x03],
        &WP3_FRAME,
        &[0x63, 0x08],
    ];
    for s in steps {
        assert_eq!(run(&mut app, &mut uarts, s), (Control::Run, b"O".to_vec()));
    }
    // The App took the store requests.
    assert!(!app.shared.requests.store);
    // 63 07: the App asks the main loop for a reset.
    assert_eq!(run(&mut app, &mut uarts, &[0x63, 0x07]).0, Control::Reboot);

    // The warm reset: a new App from the same flash.
    let app = App::new(&mut flash, 0);
    assert_eq!(app.shared.persisted.aok.start_set, 3);
    assert_eq!(app.aok.parameters()[17], 1234);
    assert!(app.aok.debug_enabled());
    let w = app.aok.waypoint(WP3.slot, &app.shared);
    assert_eq!(
        (w.lon, w.lat, w.action1),
        (0x1122_3344, 0x5566_7788u32 as i32, 0x0001_800a)
    );
}

#[test]
fn a_burst_held_back_by_a_full_tx_queue_is_obeyed_in_full_and_in_order() {
    let mut rig = Rig::with(Persisted::default(), ports::<8>());
    rig.quiet();
    // The line stalls: nothing leaves the port.
    rig.draining = false;
    // A bulk read and a set of parameter 3 in one write: the bulk reply (112 bytes) leaves the
    // link's TX queue too full for the next reply, so the set waits, and so does a read sent
    // meanwhile (in the port: not silence, not a new burst yet).
    rig.send(&[0x47, 0x00, 0x73, 0x03, 0x00, 0x00, 0x00, 0x09, 0x0a]);
    rig.settle();
    assert_eq!(rig.link.parameters()[3], 0);
    rig.send(&[0x67, 0x03]);
    rig.run(100);
    assert_eq!(rig.link.parameters()[3], 0);
    assert_eq!(rig.link.counters().bursts_discarded, 0);
    assert_eq!(rig.link.decoder_stats().abandoned, 0);
    // The line moves again: everything is answered, in order.
    rig.draining = true;
    rig.run(50);
    let out = rig.take();
    assert_eq!(out.len(), 112 + 1 + 7);
    assert_eq!(decode(&out[..112], Expect::Bulk(0)).len(), 16);
    assert_eq!(out[112], b'O');
    assert_eq!(&out[113..], &[0xff, 0x03, 0, 0, 0, 9, 9]);
    assert_eq!(rig.link.parameters()[3], 9);
    assert_eq!(rig.link.counters().replies_dropped, 0);
    assert_eq!(rig.link.counters().bursts_discarded, 0);
}

#[test]
fn boot_loads_the_start_set_and_the_flash_waypoints() {
    let mut persisted = Persisted::default();
    persisted.aok.sets[4][0] = 44;
    persisted.aok.start_set = 4;
    persisted.aok.waypoints[30].lon = 30;
    persisted.aok.waypoints[31].lat = 31;
    let shared = Shared::new(persisted.clone(), 0);
    let link = AokLink::new(&shared);
    assert_eq!(link.parameters()[0], 44);
    assert!(link.debug_enabled());
    let slot = |n| WaypointSlot::from_wire(n).unwrap();
    assert_eq!(link.waypoint(slot(30), &shared).lon, 30);
    // Flash slot 31 (the mission POI) is also the RAM POI (254) after boot.
    assert_eq!(link.waypoint(slot(254), &shared).lat, 31);
    assert_eq!(link.waypoint(slot(31), &shared).lat, 31);
    assert_eq!(link.waypoint(slot(255), &shared), StoredWaypoint::default());
    // A start set beyond the table (a corrupt record): all parameters 0.
    persisted.aok.start_set = 5;
    let link = AokLink::new(&Shared::new(persisted, 0));
    assert_eq!(link.parameters(), &[0; 32]);
}

#[test]
fn external_control_with_expiry_0_hands_back_at_once() {
    let mut rig = Rig::new();
    rig.quiet();
    rig.cmd(Command::ExternalControl(ExternalControl {
        roll: Stick::new(-200).unwrap(),
        nick: Stick::CENTER,
        yaw: Stick::CENTER,
        pitch: 0,
        expiry_ms: 0,
    }));
    rig.settle();
    assert_eq!(rig.link.control_source(), ControlSource::Rc);
    assert_eq!(rig.link.decoder_stats().frames_ok, 2); // 63 01 and the 53
    assert_eq!(rig.link.counters().bursts_discarded, 0);
}

/// A false start's bad checksum can uncover several commands at once in the decoder's buffer:
/// none of them is obeyed (they were not framed by silence as a PC sends a command), and the
/// burst is answered with one 'E' once the silence after it is observed.
#[test]
fn commands_a_rescan_uncovers_are_not_obeyed() {
    let mut rig = Rig::new();
    rig.quiet();
    // A 77 (a waypoint frame: 19 bytes) with two parameter reads inside; the decoder holds it.
    rig.send(&[0x77, 0x67, 0x0c, 0x67, 0x0d]);
    rig.poll();
    assert!(rig.take().is_empty());
    assert_eq!(rig.link.decoder_stats().checksum_errors, 0);
    // Its last 14 bytes: the checksum fails, and the rescan finds both reads, which are not
    // answered: the burst is discarded, with one 'E'.
    let mut rest = [0u8; 14];
    rest[13] = 0x55;
    rig.send(&rest);
    let frames_ok = rig.link.decoder_stats().frames_ok;
    rig.settle();
    assert_eq!(rig.take(), b"E");
    assert_eq!(rig.link.decoder_stats().checksum_errors, 1);
    assert_eq!(rig.link.decoder_stats().frames_ok, frames_ok + 2);
    assert_eq!(rig.link.counters().bursts_discarded, 1);
}

// ---------------------------------------------------------------------------------------------
// Framing: every command as a PC sends it

/// Every AOK command, sent in one write as `protolink aok` (through `aok_proto`'s `Client`)
/// and the reference PC software send it, flying and landed: nothing happens until the poll
/// that observes the silence after it (GAP_MS after the poll that took its last byte), then it
/// is obeyed (a motor test arms its motor, which runs from a second frame), or refused in
/// flight with 'I' where it changes what must not change in the air, and the reply arrives at
/// once.
#[test]
fn every_command_sent_as_one_write_is_obeyed_after_the_gap() {
    let motor = MotorTest {
        motor: Motor::new(4).unwrap(),
        value: 9,
    };
    let sticks = ExternalControl {
        roll: Stick::new(5).unwrap(),
        nick: Stick::CENTER,
        yaw: Stick::CENTER,
        pitch: 0,
        expiry_ms: 1000,
    };
    let read_wp = |rig: &Rig| rig.link.waypoint(WP3.slot, &rig.shared).lon;
    type Check = fn(&Rig) -> bool;
    type Case = (Command, Vec<u8>, Option<Vec<u8>>, Check, Check);
    // (command, reply landed, reply flying (None: as landed), obeyed landed, obeyed flying)
    let cases: Vec<Case> = vec![
        (
            Command::DebugOn,
            vec![],
            None,
            |r| r.link.debug_enabled(),
            |r| r.link.debug_enabled(),
        ),
        (
            Command::DebugOff,
            vec![],
            None,
            |r| !r.link.debug_enabled(),
            |r| !r.link.debug_enabled(),
        ),
        (
            Command::Reset,
            vec![],
            Some(b"I".to_vec()),
            |r| r.shared.requests.reboot,
            |r| !r.shared.requests.reboot,
        ),
        (
            Command::SetParameter(ParameterValue {
                number: 3,
                value: -5,
            }),
            b"O".to_vec(),
            None,
            |r| r.link.parameters()[3] == -5,
            |r| r.link.parameters()[3] == -5,
        ),
        (
            Command::SetParameter(ParameterValue {
                number: 20,
                value: 6,
            }),
            b"O".to_vec(),
            Some(b"I".to_vec()),
            |r| r.link.parameters()[20] == 6,
            |r| r.link.parameters()[20] == 0,
        ),
        (
            Command::ReadParameter(3),
            vec![0xff, 0x03, 0, 0, 0, 0, 0],
            None,
            |_| true,
            |_| true,
        ),
        (
            Command::LoadSet(1),
            b"O".to_vec(),
            Some(b"I".to_vec()),
            |r| r.link.parameters()[0] == 11,
            |r| r.link.parameters()[0] == 0,
        ),
        (
            Command::SaveSet(1),
            b"O".to_vec(),
            Some(b"I".to_vec()),
            |r| r.shared.requests.store && r.shared.persisted.aok.sets[1][0] == 0,
            |r| !r.shared.requests.store,
        ),
        (
            Command::StartSet(1),
            b"O".to_vec(),
            Some(b"I".to_vec()),
            |r| r.shared.requests.store && r.shared.persisted.aok.start_set == 1,
            |r| !r.shared.requests.store && r.shared.persisted.aok.start_set == 0,
        ),
        (
            Command::SaveWaypoints,
            b"O".to_vec(),
            Some(b"I".to_vec()),
            |r| r.shared.requests.store,
            |r| !r.shared.requests.store,
        ),
        (
            Command::LoadWaypoints,
            b"O".to_vec(),
            Some(b"I".to_vec()),
            |r| r.link.waypoint(WP3.slot, &r.shared).lon == 77,
            |r| r.link.waypoint(WP3.slot, &r.shared).lon == WP3.longitude,
        ),
        (
            Command::SetWaypoint(WP3),
            b"O".to_vec(),
            None,
            |r| r.link.waypoint(WP3.slot, &r.shared).lon == WP3.longitude,
            |r| r.link.waypoint(WP3.slot, &r.shared).lon == WP3.longitude,
        ),
        (
            Command::ReadWaypoint(WaypointSlot::from_wire(0).unwrap()),
            WP3_FRAME.to_vec(),
            None,
            |_| true,
            |_| true,
        ),
        (
            Command::MotorTest(motor),
            vec![],
            None,
            // One frame arms the motor (it runs from the second, see
            // `a_motor_runs_only_from_a_second_frame_within_the_hold`).
            |r| r.link.motor_outputs() == [0; 12] && r.link.counters().motor_frames_armed == 1,
            |r| r.link.motor_outputs() == [0; 12] && r.link.counters().motor_frames_armed == 0,
        ),
        (
            Command::ExternalControl(sticks),
            vec![],
            None,
            |r| r.link.control_source() == ControlSource::External,
            |r| r.link.control_source() == ControlSource::External,
        ),
    ];
    for (command, landed_reply, flying_reply, landed_ok, flying_ok) in cases {
        for flying in [false, true] {
            let mut persisted = Persisted::default();
            persisted.aok.sets[1][0] = 11;
            let mut rig = Rig::with(persisted, ports::<1024>());
            rig.quiet();
            rig.shared.paused = !flying;
            // Waypoint 1 is WP3 in RAM and 77 in flash: a load from flash shows.
            if matches!(command, Command::LoadWaypoints | Command::ReadWaypoint(_)) {
                assert_eq!(rig.exchange(&WP3_FRAME), b"O");
                rig.shared.persisted.aok.waypoints[0].lon = 77;
            }
            if command == Command::DebugOn {
                rig.shared.persisted.settings.aok_debug_period_ms = 60_000;
            }
            let before = read_wp(&rig);
            rig.cmd(command);
            rig.poll(); // takes the bytes
            for _ in 1..GAP_MS {
                rig.now += 1;
                rig.poll();
            }
            assert_eq!(rig.take(), [], "{command:?}: answered before the gap");
            assert!(!rig.shared.requests.reboot && !rig.shared.requests.store);
            assert_eq!(read_wp(&rig), before);
            rig.now += 1;
            rig.poll(); // GAP_MS after the bytes: the silence is observed
            let mut out = rig.take();
            if command == Command::DebugOn {
                // The stream resumes at once: one debug frame is the only output.
                assert_eq!(debug_values(&out).len(), 1, "{command:?}");
                out.clear();
            }
            let (want, ok) = if flying {
                (
                    flying_reply.clone().unwrap_or(landed_reply.clone()),
                    flying_ok,
                )
            } else {
                (landed_reply.clone(), landed_ok)
            };
            assert_eq!(out, want, "{command:?} flying {flying}");
            assert!(
                ok(&rig),
                "{command:?} flying {flying}: not obeyed as it should be"
            );
            assert_eq!(rig.link.counters().bursts_discarded, 0);
        }
    }
    // The bulk read: 16 replies, right after the gap.
    let mut rig = Rig::new();
    rig.quiet();
    rig.cmd(Command::BulkRead(0));
    rig.run(GAP_MS);
    assert_eq!(rig.take(), []);
    rig.poll();
    assert_eq!(decode(&rig.take(), Expect::Bulk(0)).len(), 16);
}
