//! The AYDP link on UART1, driven through the whole `App` with in-memory serial ports and a
//! simulated clock: every exchange of the firmware issue (UART1 part) with literal bytes.

use aeolus_proto::message::SetTime;
use aydp_proto::{
    Decode, Decoder, DirectOutputBuilder, Encoder, FixQuality, Message, OutputEntry, Payload,
    Position, Profile, SystemControl, SystemValueUpdate, Timestamp, UpdateMode,
};
use sensor_box::aydp_link::{self, addr};
use sensor_box::serial::Ring;
use sensor_box::serial::{PortStats, QueuedSerial, SerialIsr};
use sensor_box::storage::MemFlash;
use sensor_box::{App, Control, Persisted, Settings};

/// One UART: the application's half and the interrupt half the test plays.
struct Port {
    app: QueuedSerial<'static, 4096, 8192>,
    isr: SerialIsr<'static, 4096, 8192>,
}

fn port() -> Port {
    let rx: &'static mut Ring<4096> = Box::leak(Box::new(Ring::new()));
    let tx: &'static mut Ring<8192> = Box::leak(Box::new(Ring::new()));
    let stats: &'static PortStats = Box::leak(Box::new(PortStats::new()));
    let (app, isr) = QueuedSerial::split(rx, tx, stats, || {});
    Port { app, isr }
}

/// A message the box sent on UART1.
#[derive(Debug, Clone, PartialEq)]
struct Sent {
    type_byte: u8,
    timestamp: Option<Timestamp>,
    data: Vec<u8>,
}

impl Sent {
    fn message(&self) -> Message<'_> {
        Message::parse(
            self.type_byte & 0x7F,
            self.type_byte & 0x80 != 0,
            &self.data,
            Profile::Spec,
        )
        .expect("the box sends well-formed messages")
    }
}

/// The box: the App, its flash, its three UARTs and the simulated time.
struct Rig {
    app: App,
    flash: MemFlash<'static>,
    uart0: Port,
    uart1: Port,
    uart2: Port,
    now: u64,
    decoder: Decoder<256>,
    /// Every message the box sent on UART1 so far, in order.
    sent: Vec<Sent>,
    /// Every byte the box sent on UART1 so far.
    wire: Vec<u8>,
}

impl Rig {
    fn new() -> Rig {
        let mem: &'static mut [u8; 8192] = Box::leak(Box::new([0u8; 8192]));
        let mut flash = MemFlash::new(mem);
        let app = App::new(&mut flash, 0);
        Rig {
            app,
            flash,
            uart0: port(),
            uart1: port(),
            uart2: port(),
            now: 0,
            decoder: Decoder::new(Profile::Spec),
            sent: Vec::new(),
            wire: Vec::new(),
        }
    }

    /// One main-loop pass at the current time, then the interrupt handlers send everything.
    fn poll(&mut self) -> Control {
        let control = self.app.poll(
            self.now,
            &mut self.uart0.app,
            &mut self.uart1.app,
            &mut self.uart2.app,
            &mut self.flash,
        );
        while self.uart0.isr.next_to_send().is_some() {}
        while self.uart2.isr.next_to_send().is_some() {}
        while let Some(b) = self.uart1.isr.next_to_send() {
            self.wire.push(b);
            let sent = &mut self.sent;
            self.decoder.feed(&[b], |e| {
                let f = e.expect("the box sends valid frames");
                sent.push(Sent {
                    type_byte: f.type_byte(),
                    timestamp: f.timestamp(),
                    data: f.data().to_vec(),
                });
            });
        }
        control
    }

    /// Polls every ms until `t` (exclusive), then sets the time to `t`.
    fn run_until(&mut self, t: u64) {
        while self.now < t {
            self.poll();
            self.now += 1;
        }
    }

    /// Warm reset: a new App over the same flash, booted at t = 0 like [`Rig::booted`].
    fn reboot(&mut self) {
        self.app = App::new(&mut self.flash, 0);
        self.now = 0;
        self.poll();
        self.now = 1;
        self.sent.clear();
        self.wire.clear();
    }

    /// Boot traffic out of the way: one poll at t = 0, and the messages it sent forgotten.
    fn booted() -> Rig {
        let mut rig = Rig::new();
        rig.poll();
        rig.now = 1;
        rig.sent.clear();
        rig.wire.clear();
        rig
    }

    /// The peer sends `bytes` (the UART interrupt queues them), then the box polls once.
    /// Returns what the box sent in that poll.
    fn exchange(&mut self, bytes: &[u8]) -> Vec<Sent> {
        for &b in bytes {
            assert!(self.uart1.isr.received(b));
        }
        let before = self.sent.len();
        self.poll();
        self.sent.split_off(before)
    }

    /// Sends an expedited message and returns what the box answered.
    fn send<P: Payload>(&mut self, payload: &P) -> Vec<Sent> {
        let bytes = expedited(payload);
        self.exchange(&bytes)
    }

    /// Request data (expedited) at `address`; returns the reply's value update as
    /// (mode, data), or `None` if the box did not answer.
    fn read(&mut self, address: u16) -> Option<(UpdateMode, Vec<u8>)> {
        let replies = self.send(&SystemControl::RequestData { address });
        assert!(replies.len() <= 1, "one reply at most: {replies:?}");
        let reply = replies.first()?;
        assert_eq!(reply.type_byte, 0x88, "an expedited system value update");
        match reply.message() {
            Message::SystemValueUpdate(u) => {
                assert_eq!(u.address, address);
                Some((u.mode, u.data.to_vec()))
            }
            other => panic!("not a value update: {other:?}"),
        }
    }

    fn update(&mut self, address: u16, mode: UpdateMode, data: &[u8]) -> Vec<Sent> {
        self.send(&SystemValueUpdate {
            address,
            mode,
            data,
        })
    }
}

fn expedited<P: Payload + ?Sized>(p: &P) -> Vec<u8> {
    let mut buf = [0u8; 256];
    let n = Encoder::new(Profile::Spec)
        .encode(p, None, &mut buf)
        .unwrap();
    buf[..n].to_vec()
}

fn f32s(data: &[u8]) -> Vec<f32> {
    data.chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn u32s(data: &[u8]) -> Vec<u32> {
    data.chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn le_u32s(values: &[u32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn text(data: &[u8]) -> &str {
    let end = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    core::str::from_utf8(&data[..end]).unwrap()
}

// ---------------------------------------------------------------- periodic messages

#[test]
fn boot_sends_heartbeat_position_and_fix_quality() {
    let mut rig = Rig::new();
    rig.poll();
    let types: Vec<u8> = rig.sent.iter().map(|s| s.type_byte).collect();
    assert_eq!(types, [0x80, 3, 4]);
    // The heartbeat is the 7-byte expedited type 0 (checksum 0x78).
    assert_eq!(&rig.wire[..7], &[0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78]);
    // Position at t = 0: the flight's start point (near Munich) at 1000 m; time since boot.
    assert_eq!(rig.sent[1].timestamp, Some(Timestamp::new(0, 0)));
    let Message::Position(p) = rig.sent[1].message() else {
        panic!("not a position")
    };
    assert_eq!(p.latitude, 48.3538);
    assert!((p.longitude - 11.7861).abs() < 1e-9, "{}", p.longitude);
    assert_eq!(p.altitude, 1000.0);
    // Fix quality: 3D fix, DOPs 1.25 / 0.875 / 1.5 as binary16, 10 satellites.
    assert_eq!(
        rig.sent[2].data,
        [0x03, 0x00, 0x3D, 0x00, 0x3B, 0x00, 0x3E, 0x0A]
    );
    assert_eq!(
        rig.sent[2].message(),
        Message::FixQuality(FixQuality {
            fix_type: 3,
            mean_dop: 1.25,
            hdop: 0.875,
            vdop: 1.5,
            satellites: 10
        })
    );
}

#[test]
fn heartbeat_position_and_fix_quality_at_1_hz_over_10_s() {
    let mut rig = Rig::new();
    rig.run_until(10_000);
    let count = |t: u8| rig.sent.iter().filter(|s| s.type_byte == t).count();
    assert_eq!(count(0x80), 10);
    assert_eq!(count(3), 10);
    assert_eq!(count(4), 10);
    assert_eq!(rig.sent.len(), 30);
    // One second apart, on the second (time since boot: no SETTIME yet).
    let times: Vec<Timestamp> = rig
        .sent
        .iter()
        .filter(|s| s.type_byte == 3)
        .map(|s| s.timestamp.unwrap())
        .collect();
    let expected: Vec<Timestamp> = (0..10).map(|s| Timestamp::new(s, 0)).collect();
    assert_eq!(times, expected);
    // The positions follow the flight: they move every second, by about the ground speed
    // (50 m/s airspeed with 5 m/s of wind: 45..=55 m per second).
    let positions: Vec<Position> = rig
        .sent
        .iter()
        .filter_map(|s| match s.message() {
            Message::Position(p) => Some(p),
            _ => None,
        })
        .collect();
    for w in positions.windows(2) {
        let dlat = (w[1].latitude - w[0].latitude) * 111_195.0;
        let dlon = (w[1].longitude - w[0].longitude) * 111_195.0 * 48.3538f64.to_radians().cos();
        let d = (dlat * dlat + dlon * dlon).sqrt();
        assert!((44.0..=56.0).contains(&d), "moved {d} m in 1 s");
    }
}

#[test]
fn a_late_poll_sends_once_and_keeps_the_grid() {
    let mut rig = Rig::new();
    rig.poll(); // t = 0
    rig.now = 3_500; // the main loop was busy for 3.5 s
    rig.poll();
    rig.run_until(5_001);
    let beats: Vec<u64> = rig
        .sent
        .iter()
        .filter(|s| s.type_byte == 3)
        .map(|s| {
            let t = s.timestamp.unwrap();
            (t.seconds * 1000 + t.subsec) as u64
        })
        .collect();
    // 0, then one at 3.5 s (not three), then back on the 1 s grid: 4 s and 5 s.
    assert_eq!(beats, [0, 3_500, 4_000, 5_000]);
}

#[test]
fn normal_messages_carry_the_settime_wall_clock() {
    let mut rig = Rig::booted();
    // The AEOLUS link stores SETTIME here; 2024-03-01 12:00:00 UTC arrives at t = 200 ms.
    let t = SetTime {
        year_since_1900: 124,
        month0: 2,
        day: 1,
        hour: 12,
        minute: 0,
        second: 0,
    };
    rig.app.shared.wall_clock = Some((t, 200));
    rig.run_until(1_001);
    let pos = rig.sent.iter().find(|s| s.type_byte == 3).unwrap();
    // 1000 ms - 200 ms after the SETTIME.
    assert_eq!(pos.timestamp, Some(Timestamp::new(1_709_294_400, 800)));
    // An impossible date (February 30) falls back to the time since boot.
    rig.app.shared.wall_clock = Some((
        SetTime {
            month0: 1,
            day: 30,
            ..t
        },
        200,
    ));
    rig.sent.clear();
    rig.run_until(2_001);
    let pos = rig.sent.iter().find(|s| s.type_byte == 3).unwrap();
    assert_eq!(pos.timestamp, Some(Timestamp::new(2, 0)));
}

// ---------------------------------------------------------------- system value update

#[test]
fn single_value_update_then_request_data_with_literal_bytes() {
    let mut rig = Rig::booted();
    // Airspeed (0x0110) := 62.5 m/s, mode 1, expedited.
    let set = [
        0xFF, 0x88, 0x12, 0x00, 0x00, 0x00, 0x01, 0x10, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x7A, 0x42, 0x4D,
    ];
    assert_eq!(rig.exchange(&set), vec![], "an update is not answered");
    assert_eq!(rig.app.shared.settings().airspeed_mps, 62.5);
    // The flight was rebuilt with the new airspeed at the time of the update.
    assert_eq!(rig.app.shared.flight.params().airspeed_mps, 62.5);
    assert_eq!(rig.app.shared.flight_epoch_ms, 1);
    assert_eq!(rig.app.aydp.counters().updates_applied, 1);

    // Request data at 0x0110, expedited: FF 89 0A 00 00 00 01 10 01 6C.
    rig.wire.clear();
    let reply = rig.exchange(&[0xFF, 0x89, 0x0A, 0x00, 0x00, 0x00, 0x01, 0x10, 0x01, 0x6C]);
    assert_eq!(reply.len(), 1);
    // The answer is the same value update, byte for byte.
    assert_eq!(rig.wire, set);
    assert_eq!(rig.app.aydp.counters().requests_answered, 1);
}

#[test]
fn a_normal_request_gets_a_normal_reply_with_a_timestamp() {
    let mut rig = Rig::booted();
    rig.now = 4_321;
    // Request data at 0x0112 (altitude), normal message, header time 0.
    let mut buf = [0u8; 64];
    let n = Encoder::new(Profile::Spec)
        .encode(
            &SystemControl::RequestData {
                address: addr::ALTITUDE,
            },
            Some(Timestamp::new(0, 0)),
            &mut buf,
        )
        .unwrap();
    let reply = rig.exchange(&buf[..n]);
    let svu = reply.iter().find(|s| s.type_byte & 0x7F == 8).unwrap();
    assert_eq!(svu.type_byte, 0x08);
    assert_eq!(svu.timestamp, Some(Timestamp::new(4, 321)));
    assert_eq!(
        svu.message(),
        Message::SystemValueUpdate(SystemValueUpdate {
            address: 0x0112,
            mode: UpdateMode::Single,
            data: &1000.0f32.to_le_bytes(),
        })
    );
}

#[test]
fn whole_array_update_mode_2() {
    let mut rig = Rig::booted();
    let new = [10, 6, 100, 1000, 2000, 500];
    let answer = rig.update(
        addr::INTERVALS,
        UpdateMode::Array { count: 6 },
        &le_u32s(&new),
    );
    assert!(answer.is_empty());
    let i = rig.app.shared.settings().intervals;
    assert_eq!(
        [
            i.imu_ms,
            i.pressure_ms,
            i.gps_ms,
            i.temp_ms,
            i.wind_ms,
            i.info_ms
        ],
        new
    );
    let (mode, data) = rig.read(addr::INTERVALS).unwrap();
    assert_eq!(mode, UpdateMode::Array { count: 6 });
    assert_eq!(u32s(&data), new);
}

#[test]
fn element_update_mode_3() {
    let mut rig = Rig::booted();
    // GPS interval (element 2) := 250 ms.
    rig.update(
        addr::INTERVALS,
        UpdateMode::Element { index: 2 },
        &250u32.to_le_bytes(),
    );
    assert_eq!(rig.app.shared.settings().intervals.gps_ms, 250);
    let (mode, data) = rig.read(addr::INTERVALS).unwrap();
    assert_eq!(mode, UpdateMode::Array { count: 6 });
    assert_eq!(u32s(&data), [7, 5, 250, 829, 1000, 1000]);
}

#[test]
fn every_setting_reads_back_after_it_is_set() {
    let mut rig = Rig::booted();
    rig.update(addr::BANK, UpdateMode::Single, &(-30.0f32).to_le_bytes());
    rig.update(addr::ALTITUDE, UpdateMode::Single, &2500.0f32.to_le_bytes());
    rig.update(
        addr::AOK_DEBUG_PERIOD,
        UpdateMode::Single,
        &100u32.to_le_bytes(),
    );
    assert_eq!(rig.app.aydp.counters().updates_applied, 3);
    assert_eq!(
        rig.read(addr::BANK),
        Some((UpdateMode::Single, (-30.0f32).to_le_bytes().to_vec()))
    );
    assert_eq!(
        rig.read(addr::ALTITUDE),
        Some((UpdateMode::Single, 2500.0f32.to_le_bytes().to_vec()))
    );
    assert_eq!(
        rig.read(addr::AOK_DEBUG_PERIOD),
        Some((UpdateMode::Single, vec![100, 0, 0, 0]))
    );
    let s = rig.app.shared.settings();
    assert_eq!(
        (s.bank_deg, s.altitude_m, s.aok_debug_period_ms),
        (-30.0, 2500.0, 100)
    );
    // The flight follows: left turn at 2500 m.
    let p = rig.app.shared.flight.params();
    assert_eq!((p.bank_deg, p.altitude_m), (-30.0, 2500.0));
}

#[test]
fn prescribed_texts_read_back_and_are_read_only() {
    let mut rig = Rig::booted();
    let (mode, name) = rig.read(addr::SYSTEM_NAME).unwrap();
    assert_eq!(mode, UpdateMode::Array { count: 40 });
    assert_eq!(name.len(), 40);
    assert_eq!(text(&name), "protolink sensor box");
    assert_eq!(text(&rig.read(addr::SYSTEM_ID).unwrap().1), "SBX-0001");
    assert_eq!(text(&rig.read(addr::HARDWARE_VERSION).unwrap().1), "host");
    assert_eq!(
        text(&rig.read(addr::FIRMWARE_VERSION).unwrap().1),
        "sensor-box 0.1.0"
    );

    // Renaming the box is refused and counted; nothing changes.
    rig.update(addr::SYSTEM_NAME, UpdateMode::Single, b"evil box");
    assert_eq!(rig.app.aydp.counters().rejected, 1);
    assert_eq!(rig.app.aydp.counters().updates_applied, 0);
    assert_eq!(
        text(&rig.read(addr::SYSTEM_NAME).unwrap().1),
        "protolink sensor box"
    );
    // So is writing the outputs or the counters through the registry.
    rig.update(
        addr::OUTPUTS,
        UpdateMode::Element { index: 0 },
        &1.0f32.to_le_bytes(),
    );
    rig.update(
        addr::LINK_COUNTERS,
        UpdateMode::Element { index: 5 },
        &0u32.to_le_bytes(),
    );
    assert_eq!(rig.app.aydp.counters().rejected, 3);
    assert_eq!(rig.app.shared.outputs[0].value, 0.0);
}

#[test]
fn rejected_updates_change_nothing_and_are_counted() {
    let mut rig = Rig::booted();
    let defaults = Settings::default();
    let epoch = rig.app.shared.flight_epoch_ms;
    let bad: [(u16, UpdateMode, Vec<u8>); 11] = [
        // Out of range.
        (
            addr::AIRSPEED,
            UpdateMode::Single,
            200.0f32.to_le_bytes().to_vec(),
        ),
        (
            addr::AIRSPEED,
            UpdateMode::Single,
            9.5f32.to_le_bytes().to_vec(),
        ),
        (
            addr::AIRSPEED,
            UpdateMode::Single,
            f32::NAN.to_le_bytes().to_vec(),
        ),
        (
            addr::BANK,
            UpdateMode::Single,
            60.5f32.to_le_bytes().to_vec(),
        ),
        (
            addr::ALTITUDE,
            UpdateMode::Single,
            11_001.0f32.to_le_bytes().to_vec(),
        ),
        (addr::DIRECT_CONTROL, UpdateMode::Single, vec![2]),
        // One bad element rejects the whole array.
        (
            addr::INTERVALS,
            UpdateMode::Array { count: 6 },
            le_u32s(&[10, 0, 100, 1000, 2000, 500]),
        ),
        // Element beyond the array.
        (
            addr::INTERVALS,
            UpdateMode::Element { index: 6 },
            100u32.to_le_bytes().to_vec(),
        ),
        // Wrong mode and wrong size.
        (
            addr::AIRSPEED,
            UpdateMode::Element { index: 0 },
            60.0f32.to_le_bytes().to_vec(),
        ),
        (addr::AOK_DEBUG_PERIOD, UpdateMode::Single, vec![100, 0]),
        // Unknown address.
        (0x0999, UpdateMode::Single, vec![1]),
    ];
    for (i, (address, mode, data)) in bad.iter().enumerate() {
        rig.update(*address, *mode, data);
        assert_eq!(
            rig.app.aydp.counters().rejected,
            i as u32 + 1,
            "{address:#06x}"
        );
    }
    assert_eq!(*rig.app.shared.settings(), defaults);
    assert!(!rig.app.shared.direct_control);
    assert_eq!(rig.app.shared.flight_epoch_ms, epoch, "flight not rebuilt");
    assert_eq!(rig.app.aydp.counters().updates_applied, 0);
    // A request for an unknown address is not answered, and counted too.
    assert_eq!(rig.read(0x0999), None);
    assert_eq!(rig.app.aydp.counters().rejected, 12);
    // The counters are readable: 12 rejected, 0 applied.
    let (_, c) = rig.read(addr::LINK_COUNTERS).unwrap();
    let c = u32s(&c);
    assert_eq!(c.len(), 10);
    assert_eq!((c[4], c[5]), (0, 12));
}

#[test]
fn the_document_example_with_two_data_bytes_is_malformed() {
    let mut rig = Rig::booted();
    // Y6: "enable direct control" as printed carries 2 data bytes: the frame is good, the
    // typed parse fails.
    rig.exchange(&[0xFF, 0x88, 0x09, 0x00, 0x00, 0x00, 0x00, 0x01, 0x7F]);
    assert_eq!(rig.app.aydp.decoder_stats().frames_ok, 1);
    assert_eq!(rig.app.aydp.counters().malformed, 1);
    assert!(!rig.app.shared.direct_control);
}

// ---------------------------------------------------------------- system control

#[test]
fn store_configuration_writes_the_flash_and_survives_a_reboot() {
    let mut rig = Rig::booted();
    rig.update(addr::AIRSPEED, UpdateMode::Single, &72.0f32.to_le_bytes());
    rig.update(
        addr::INTERVALS,
        UpdateMode::Element { index: 3 },
        &500u32.to_le_bytes(),
    );
    rig.update(
        addr::AOK_DEBUG_PERIOD,
        UpdateMode::Single,
        &40u32.to_le_bytes(),
    );
    rig.update(addr::DIRECT_CONTROL, UpdateMode::Single, &[1]);
    // Store configuration: FF 89 08 00 00 00 02 7C (the document's example, Y6 checksum).
    // Flying (the box boots flying): refused, counted, nothing stored.
    let store = [0xFF, 0x89, 0x08, 0x00, 0x00, 0x00, 0x02, 0x7C];
    rig.exchange(&store);
    assert_eq!(rig.app.aydp.counters().stores_requested, 1);
    assert_eq!(rig.app.shared.counters.stores_refused_in_flight, 1);
    assert_eq!(rig.app.shared.counters.stores_written, 0);
    assert_eq!(
        rig.read(addr::STORE_COUNTERS)
            .map(|(_, v)| v[12..16].to_vec()),
        Some(1u32.to_le_bytes().to_vec()),
        "0x0310 element 3: refused in flight"
    );
    // Landed: obeyed.
    rig.app.shared.paused = true;
    rig.exchange(&store);
    assert_eq!(rig.app.aydp.counters().stores_requested, 2);
    assert_eq!(rig.app.shared.counters.stores_written, 1);
    assert!(!rig.app.shared.requests.store, "the App took the request");
    assert_eq!(rig.app.shared.counters.store_failures, 0);
    let stored = rig.app.shared.persisted.clone();
    // The same again: nothing changed, nothing written.
    rig.exchange(&store);
    assert_eq!(rig.app.shared.counters.stores_unchanged, 1);
    // The rate limit: a burst of 8 (2 taken), then refused and counted.
    for _ in 0..8 {
        rig.exchange(&store);
    }
    assert_eq!(rig.app.shared.counters.stores_unchanged, 7);
    assert_eq!(rig.app.shared.counters.stores_rate_limited, 2);

    // Reboot: a new App over the same flash.
    rig.reboot();
    let s = rig.app.shared.settings();
    assert_eq!(s.airspeed_mps, 72.0);
    assert_eq!(s.intervals.temp_ms, 500);
    assert_eq!(s.aok_debug_period_ms, 40);
    assert_eq!(rig.app.shared.persisted, stored);
    assert_eq!(rig.app.shared.flight.params().airspeed_mps, 72.0);
    // Direct control is not a stored setting: it is off after a reboot.
    assert!(!rig.app.shared.direct_control);
    assert_eq!(
        rig.read(addr::AIRSPEED),
        Some((UpdateMode::Single, 72.0f32.to_le_bytes().to_vec()))
    );
}

#[test]
fn without_store_configuration_a_reboot_forgets_the_update() {
    let mut rig = Rig::booted();
    rig.update(addr::AIRSPEED, UpdateMode::Single, &72.0f32.to_le_bytes());
    rig.reboot();
    assert_eq!(*rig.app.shared.settings(), Settings::default());
    assert_eq!(rig.app.shared.persisted, Persisted::default());
}

// ---------------------------------------------------------------- direct output control

#[test]
fn direct_output_is_refused_while_disabled_and_obeyed_when_enabled() {
    let mut rig = Rig::booted();
    // Rudder +10 on device 1, channel 2 (the document's example entry).
    let rudder = [
        0xFF, 0x87, 0x0F, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x00, 0x20, 0x41, 0x14,
    ];
    rig.exchange(&rudder);
    assert_eq!(rig.app.aydp.counters().direct_refused, 1);
    assert_eq!(rig.app.shared.outputs[2].value, 0.0);

    // Enable direct control: 0x0000 := 1 (FF 88 0F 00 00 00 01 00 00 00 00 00 00 01 78).
    rig.exchange(&[
        0xFF, 0x88, 0x0F, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x78,
    ]);
    assert!(rig.app.shared.direct_control);
    assert_eq!(
        rig.read(addr::DIRECT_CONTROL),
        Some((UpdateMode::Single, vec![1]))
    );

    rig.exchange(&rudder);
    assert_eq!(rig.app.aydp.counters().direct_applied, 1);
    assert_eq!(rig.app.shared.outputs[2].value, 10.0);
    let (mode, data) = rig.read(addr::OUTPUTS).unwrap();
    assert_eq!(mode, UpdateMode::Array { count: 8 });
    assert_eq!(f32s(&data), [0.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0, 0.0]);

    // Several channels; a channel named twice takes the last value.
    let mut buf = [0u8; 64];
    let mut b = DirectOutputBuilder::new(&mut buf);
    for (channel, value) in [(0, -5.5), (7, 0.25), (0, 3.0)] {
        b.push(OutputEntry {
            device: 1,
            channel,
            value,
        })
        .unwrap();
    }
    rig.send(&b.finish());
    assert_eq!(
        f32s(&rig.read(addr::OUTPUTS).unwrap().1),
        [3.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0, 0.25]
    );

    // An unknown channel (device 1, channel 8) rejects the whole message.
    let mut buf = [0u8; 64];
    let mut b = DirectOutputBuilder::new(&mut buf);
    b.push(OutputEntry {
        device: 1,
        channel: 1,
        value: 9.0,
    })
    .unwrap();
    b.push(OutputEntry {
        device: 1,
        channel: 8,
        value: 9.0,
    })
    .unwrap();
    rig.send(&b.finish());
    assert_eq!(rig.app.aydp.counters().direct_refused, 2);
    assert_eq!(rig.app.shared.outputs[1].value, 0.0);

    // Disable again: refused, outputs keep their values.
    rig.update(addr::DIRECT_CONTROL, UpdateMode::Single, &[0]);
    assert!(!rig.app.shared.direct_control);
    rig.exchange(&rudder);
    assert_eq!(rig.app.aydp.counters().direct_refused, 3);
    assert_eq!(rig.app.aydp.counters().direct_applied, 2);
    assert_eq!(rig.app.shared.outputs[0].value, 3.0);
}

// ---------------------------------------------------------------- stream robustness

#[test]
fn a_request_behind_garbage_and_split_byte_by_byte_is_answered_once() {
    let mut rig = Rig::booted();
    let mut stream = vec![0x13, 0xFF, 0x37, 0x00, 0xFF];
    stream.extend_from_slice(&[0xFF, 0x89, 0x0A, 0x00, 0x00, 0x00, 0x01, 0x01, 0x00, 0x7C]);
    let mut replies = Vec::new();
    for &b in &stream {
        replies.extend(rig.exchange(&[b]));
    }
    assert_eq!(replies.len(), 1);
    match replies[0].message() {
        Message::SystemValueUpdate(u) => {
            assert_eq!(u.address, addr::SYSTEM_NAME);
            assert_eq!(text(u.data), "protolink sensor box");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn heartbeats_from_the_peer_are_counted_and_other_types_ignored() {
    let mut rig = Rig::booted();
    rig.exchange(&[0xFF, 0x80, 0x07, 0x00, 0x00, 0x00, 0x78]);
    rig.send(&Position {
        latitude: 1.0,
        longitude: 2.0,
        altitude: 3.0,
    });
    assert_eq!(rig.app.aydp.counters().heartbeats_received, 1);
    assert_eq!(rig.app.aydp.counters().ignored, 1);
    assert_eq!(aydp_link::COUNTER_NAMES.len(), 10);
}

#[test]
fn a_port_that_stops_taking_bytes_keeps_messages_whole_and_never_blocks() {
    use sensor_box::{Shared, aydp_link::AydpLink};
    // A port ring with room for 4 bytes that nobody drains: the link keeps the rest of its
    // messages in its own TX queue, whole, and drops (and counts) whole messages only when
    // that queue has no room; a poll never waits.
    let rxq = Ring::<8>::new();
    let txq = Ring::<4>::new();
    let stats = PortStats::new();
    let (mut port, mut isr) = QueuedSerial::split(&rxq, &txq, &stats, || {});
    let mut shared = Shared::new(Persisted::default(), 0);
    let mut link = AydpLink::new(0);
    link.poll(0, &mut port, &mut shared);
    // Heartbeat, position and fix quality: 81 bytes, 4 of them in the port.
    assert_eq!(link.counters().tx_dropped, 0);
    assert_eq!(link.tx_pending(), 81 - 4);
    let mut polls = 0;
    while link.counters().tx_dropped == 0 {
        polls += 1;
        link.poll(polls * 1000, &mut port, &mut shared);
        // The 1 Hz messages leave room for one longest reply.
        assert!(link.tx_pending() <= aydp_link::TX_QUEUE - 128);
    }
    // 77 bytes wait; 256 - 77 - 128 = 51 bytes of room: the heartbeat (7) and the position
    // (43) of the next second fit, its fix quality (31) does not.
    assert_eq!(polls, 1);
    assert_eq!(link.counters().tx_dropped, 1);
    // Now the UART drains: every byte that goes out is part of a whole message.
    let mut out = Vec::new();
    for now in 1001..1100 {
        out.extend(core::iter::from_fn(|| isr.next_to_send()));
        link.poll(now, &mut port, &mut shared);
    }
    assert_eq!(link.tx_pending(), 0);
    assert_eq!(&out[..4], [0xFF, 0x80, 0x07, 0x00]);
    let mut decoder = Decoder::<256>::new(Profile::Spec);
    let mut types = Vec::new();
    decoder.feed(&out, |ev| {
        types.push(ev.expect("a whole message").type_byte())
    });
    let dropped = link.counters().tx_dropped as usize;
    assert_eq!(types, [0x80, 3, 4, 0x80, 3]);
    assert_eq!(dropped, 1);
    assert_eq!(decoder.stats().bytes_discarded, 0);
}

#[test]
fn the_corrupt_items_of_the_boot_are_register_0x0311() {
    let mut rig = Rig::booted();
    assert_eq!(
        rig.read(addr::CORRUPT_ITEMS).map(|(_, v)| v),
        Some(0u32.to_le_bytes().to_vec()),
        "a clean boot"
    );
    // What `persist::boot` counted (`tests/all/flash_faults.rs` counts them from a real flip).
    rig.app.shared.counters.corrupt_items = 3;
    assert_eq!(
        rig.read(addr::CORRUPT_ITEMS).map(|(_, v)| v),
        Some(3u32.to_le_bytes().to_vec())
    );
}
