//! AOK on UART2: the flight-controller side of the AOK protocol.
//!
//! [`AokLink::poll`] reads the commands the PC sends (through `aok_proto`'s [`DeviceDecoder`]),
//! answers them, and sends the debug value stream. Nothing in it blocks: replies go into a
//! small TX queue of [`TX_CAPACITY`] bytes which is handed to the port with non-blocking
//! writes, and a debug frame is only built when that queue is empty, so a reply never waits
//! behind more than one debug frame.
//!
//! What the link holds:
//! - the RAM parameters ([`AOK_PARAMS`] of them, loaded at boot from the start set in flash);
//! - the RAM waypoints (slots 0..=30, 254 POI and 255 FBC target; slot 31, the mission POI,
//!   lives in the flash record [`AokFlash::waypoints`](super::state::AokFlash));
//! - the motor-test outputs (held [`MOTOR_LAPSE_MS`] after the last frame) and the
//!   external-control sticks with their expiry.
//!
//! The parameter sets, the start set and the flash waypoints are in [`Shared::persisted`];
//! commands that change them set `shared.requests.store` and the [`App`](super::App) writes
//! the flash. The firmware README (section "UART2: AOK") lists every protocol decision.
//!
//! ```
//! use sensor_box::{Persisted, Shared, aok_link::{AokLink, DebugId}};
//! use firmware_example::{PortStats, QueuedSerial};
//! use heapless::spsc::Queue;
//!
//! let shared = &mut Shared::new(Persisted::default(), 0);
//! let mut link = AokLink::new(shared);
//! let (mut rxq, mut txq) = (Queue::<u8, 64>::new(), Queue::<u8, 64>::new());
//! let stats = PortStats::new();
//! let (mut port, mut isr) = QueuedSerial::split(&mut rxq, &mut txq, &stats, || {});
//! // Debug is on at boot: the first poll sends the first value of the cycle (roll).
//! link.poll(0, &mut port, shared);
//! let frame: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
//! assert_eq!(frame.len(), 7);
//! assert_eq!(&frame[..2], &[0x1c, DebugId::Roll as u8]);
//! // Read parameter 3: the >= 0.31 reply `FF 03 B1..B4 CRC`.
//! for b in [0x63, 0x01, 0x67, 0x03] {
//!     isr.received(b);
//! }
//! link.poll(1, &mut port, shared);
//! let reply: Vec<u8> = core::iter::from_fn(|| isr.next_to_send()).collect();
//! assert_eq!(reply, [0xff, 0x03, 0, 0, 0, 0, 0]);
//! ```

use super::Shared;
use super::state::{AOK_FLASH_WAYPOINTS, AOK_PARAMS, StoredWaypoint};
use aok_proto::message::{DEBUG_LEN, HEADED_REPLY_LEN};
use aok_proto::{
    Ack, ActionWord, Command, DebugValue, DeviceDecoder, Error as AokError, ExternalControl,
    FirmwareVersion, MotorTest, ParameterValue, Stats, Waypoint, WaypointSlot, device,
};
use embedded_hal_nb::serial::{Read, Write};
use heapless::Deque;

/// The AOK firmware version this box claims: 0.35, so parameter replies use the headed
/// (>= 0.31) form `FF NUM B1..B4 CRC` and bulk read (`47`, >= 0.35) is supported.
pub const FIRMWARE: FirmwareVersion = FirmwareVersion::new(0, 35);
const _: () = assert!(FIRMWARE.has_bulk_read());

/// A motor-test value lapses (back to 0) this long after the last frame for that motor.
pub const MOTOR_LAPSE_MS: u64 = 500;
/// Number of motors the test command addresses (`31..39`, `41..43`).
pub const MOTORS: usize = 12;
/// RAM waypoint slots 0..=30 (waypoints 1..=31).
pub const RAM_WAYPOINTS: usize = 31;
/// Index of the mission POI (wire slot 31) in the flash waypoints.
pub const MISSION_POI: usize = AOK_FLASH_WAYPOINTS - 1;
/// Parameters that may be set while flying: bit `n` set = parameter `n` is "in-flight"
/// settable. Parameters 0..=15 are (tuning values); 16..=31 are not (configuration).
pub const IN_FLIGHT_PARAMS: u32 = 0x0000_ffff;
/// A partial frame is abandoned (the decoder rescans behind it) after this much silence.
pub const IDLE_MS: u64 = 50;
/// Capacity of the link's own TX queue, in bytes: one bulk reply (112 bytes) plus room.
pub const TX_CAPACITY: usize = 128;
/// The longest reply one command produces: the 16 frames of a bulk read.
const MAX_REPLY: usize = HEADED_REPLY_LEN * 16;
/// At most this many received bytes are decoded per poll, so one poll stays short.
pub const RX_BUDGET: usize = 64;

/// The debug values the box sends, with their numbers on the wire. One value per frame,
/// cycling through [`DebugId::CYCLE`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
#[repr(u8)]
pub enum DebugId {
    /// Roll angle, 0.01°.
    Roll = 1,
    /// Pitch angle, 0.01°.
    Pitch = 2,
    /// True heading, 0.01° in 0..36000.
    Heading = 3,
    /// True airspeed, cm/s.
    Airspeed = 4,
    /// Altitude, cm.
    Altitude = 5,
    /// Static pressure, Pa.
    StaticPressure = 6,
    /// Pitot (dynamic) pressure, Pa.
    PitotPressure = 7,
    /// Outside air temperature, 0.01 °C.
    Temperature = 8,
    /// Latitude, 1e-7°.
    Latitude = 9,
    /// Longitude, 1e-7°.
    Longitude = 10,
    /// Ground speed, cm/s.
    GroundSpeed = 11,
    /// Turn rate, 0.01°/s (positive: right).
    TurnRate = 12,
    /// Who steers: 0 = RC, 1 = external control (`53`).
    ControlSource = 13,
    /// Motor test: bit `n - 1` set while motor `n` has a non-zero test value.
    MotorTestMask = 14,
    /// Flight status, always in the cycle (K2): bit 0 flying, bit 1 external control,
    /// bit 2 motor test running.
    FlightStatus = 86,
}

impl DebugId {
    /// The order the values are sent in.
    pub const CYCLE: [DebugId; 15] = [
        DebugId::Roll,
        DebugId::Pitch,
        DebugId::Heading,
        DebugId::Airspeed,
        DebugId::Altitude,
        DebugId::StaticPressure,
        DebugId::PitotPressure,
        DebugId::Temperature,
        DebugId::Latitude,
        DebugId::Longitude,
        DebugId::GroundSpeed,
        DebugId::TurnRate,
        DebugId::ControlSource,
        DebugId::MotorTestMask,
        DebugId::FlightStatus,
    ];
}

/// Flight status (debug value 86) bit: the box is flying (see [`flying`]).
pub const STATUS_FLYING: i32 = 1;
/// Flight status bit: external control has the sticks.
pub const STATUS_EXTERNAL: i32 = 2;
/// Flight status bit: a motor-test value is active.
pub const STATUS_MOTOR_TEST: i32 = 4;

/// Who steers the (simulated) aircraft.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub enum ControlSource {
    /// The RC transmitter (the default, and after external control expires).
    Rc,
    /// External control (`53` frames) until its expiry runs out.
    External,
}

/// "Flying", for the in-flight checks and the flight status: the simulated flight runs and
/// AEOLUS telemetry is not paused ("a pause" lands the box).
pub fn flying(shared: &Shared) -> bool {
    !shared.paused
}

/// Is parameter `number` settable while flying ([`IN_FLIGHT_PARAMS`])?
pub const fn in_flight_settable(number: u8) -> bool {
    match IN_FLIGHT_PARAMS.checked_shr(number as u32) {
        Some(bits) => bits & 1 == 1,
        None => false,
    }
}

/// The link's own counters (the decoder's are in [`AokLink::decoder_stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(all(feature = "defmt", target_os = "none"), derive(defmt::Format))]
pub struct AokCounters {
    /// 'E' acks sent (bad checksum, invalid waypoint slot, unknown parameter or set number).
    pub rejected: u32,
    /// Commands refused because the box is flying ('I' sent, or motor test ignored).
    pub refused_in_flight: u32,
    /// Replies dropped because the TX queue was full.
    pub replies_dropped: u32,
    /// Debug frames queued.
    pub debug_frames: u32,
    /// Receive errors reported by the port.
    pub rx_errors: u32,
    /// Transmit errors reported by the port.
    pub tx_errors: u32,
}

#[derive(Debug, Clone, Copy, Default)]
struct MotorOutput {
    value: u8,
    until_ms: u64,
}

#[derive(Debug, Clone, Copy)]
struct External {
    control: ExternalControl,
    until_ms: u64,
}

/// The AOK link.
pub struct AokLink {
    decoder: DeviceDecoder,
    tx: Deque<u8, TX_CAPACITY>,
    debug_on: bool,
    next_debug_ms: u64,
    debug_index: usize,
    last_rx_ms: u64,
    params: [i32; AOK_PARAMS],
    waypoints: [StoredWaypoint; RAM_WAYPOINTS],
    ram_poi: StoredWaypoint,
    fbc_target: StoredWaypoint,
    motors: [MotorOutput; MOTORS],
    external: Option<External>,
    counters: AokCounters,
}

impl AokLink {
    /// The link at boot: debug on, the parameters of the start set, the waypoints from flash
    /// (as `63 09` would load them: flash slot 31 into the RAM POI), FBC target 0/0.
    pub fn new(shared: &Shared) -> Self {
        let aok = &shared.persisted.aok;
        let params = match aok.sets.get(usize::from(aok.start_set)) {
            Some(set) => *set,
            None => {
                crate::warn!(
                    "AOK: start set {=u8} does not exist, parameters are 0",
                    aok.start_set
                );
                [0; AOK_PARAMS]
            }
        };
        let mut link = AokLink {
            decoder: DeviceDecoder::new(),
            tx: Deque::new(),
            debug_on: true,
            next_debug_ms: 0,
            debug_index: 0,
            last_rx_ms: 0,
            params,
            waypoints: [StoredWaypoint::default(); RAM_WAYPOINTS],
            ram_poi: StoredWaypoint::default(),
            fbc_target: StoredWaypoint::default(),
            motors: [MotorOutput::default(); MOTORS],
            external: None,
            counters: AokCounters::default(),
        };
        link.load_waypoints(shared);
        link
    }

    /// Reads what arrived on the port, answers, and sends what is due at `now_ms`.
    pub fn poll<P: Read<u8> + Write<u8>>(
        &mut self,
        now_ms: u64,
        port: &mut P,
        shared: &mut Shared,
    ) {
        self.flush(port);
        self.receive(now_ms, port, shared);
        self.expire(now_ms);
        if self.debug_on && self.tx.is_empty() && now_ms >= self.next_debug_ms {
            self.send_debug(now_ms, shared);
        }
        self.flush(port);
    }

    /// Is the debug stream on (`63 02`) or off (`63 01`)?
    pub fn debug_enabled(&self) -> bool {
        self.debug_on
    }

    /// The RAM parameters.
    pub fn parameters(&self) -> &[i32; AOK_PARAMS] {
        &self.params
    }

    /// The RAM value of a waypoint slot; the mission POI (31) is read from the flash record.
    pub fn waypoint(&self, slot: WaypointSlot, shared: &Shared) -> StoredWaypoint {
        match slot {
            WaypointSlot::Waypoint(n) => self
                .waypoints
                .get(usize::from(n.wire()))
                .copied()
                .unwrap_or_default(),
            WaypointSlot::MissionPoi => shared
                .persisted
                .aok
                .waypoints
                .get(MISSION_POI)
                .copied()
                .unwrap_or_default(),
            WaypointSlot::RamPoi => self.ram_poi,
            WaypointSlot::FbcTarget => self.fbc_target,
        }
    }

    /// The motor-test outputs, motor 1 first (0 = off).
    pub fn motor_outputs(&self) -> [u8; MOTORS] {
        self.motors.map(|m| m.value)
    }

    /// Who steers now.
    pub fn control_source(&self) -> ControlSource {
        if self.external.is_some() {
            ControlSource::External
        } else {
            ControlSource::Rc
        }
    }

    /// The external-control sticks while external control has the aircraft.
    pub fn external_control(&self) -> Option<ExternalControl> {
        self.external.map(|e| e.control)
    }

    /// The link's counters.
    pub fn counters(&self) -> &AokCounters {
        &self.counters
    }

    /// The command decoder's counters.
    pub fn decoder_stats(&self) -> &Stats {
        self.decoder.stats()
    }

    /// Bytes waiting in the link's TX queue (not yet accepted by the port).
    pub fn tx_pending(&self) -> usize {
        self.tx.len()
    }

    /// Hands queued bytes to the port until it would block.
    fn flush<P: Write<u8>>(&mut self, port: &mut P) {
        while let Some(&byte) = self.tx.front() {
            match port.write(byte) {
                Ok(()) => {
                    let _ = self.tx.pop_front();
                }
                Err(nb::Error::WouldBlock) => break,
                Err(nb::Error::Other(_)) => {
                    self.counters.tx_errors = self.counters.tx_errors.wrapping_add(1);
                    break;
                }
            }
        }
    }

    /// Decodes received bytes while the TX queue has room for the longest reply (otherwise
    /// the bytes wait in the port's RX queue: back-pressure instead of lost replies).
    fn receive<P: Read<u8>>(&mut self, now_ms: u64, port: &mut P, shared: &mut Shared) {
        let mut budget = RX_BUDGET;
        let mut port_empty = false;
        while budget > 0 && self.tx_free() >= MAX_REPLY {
            budget = budget.saturating_sub(1);
            match port.read() {
                Ok(byte) => {
                    self.last_rx_ms = now_ms;
                    let mut event = self.decoder.push(byte);
                    while let Some(item) = event {
                        self.handle(item, now_ms, shared);
                        event = self.decoder.poll();
                    }
                }
                Err(nb::Error::WouldBlock) => {
                    port_empty = true;
                    break;
                }
                Err(nb::Error::Other(_)) => {
                    self.counters.rx_errors = self.counters.rx_errors.wrapping_add(1);
                }
            }
        }
        // Silence only counts when the port has nothing more: bytes held back in its RX queue
        // (back-pressure, budget) may be the rest of the partial frame.
        if port_empty
            && self.decoder.buffered() > 0
            && now_ms.saturating_sub(self.last_rx_ms) >= IDLE_MS
        {
            while let Some(item) = self.decoder.idle_next() {
                self.handle(item, now_ms, shared);
            }
        }
    }

    /// Motor-test values and external control run out.
    fn expire(&mut self, now_ms: u64) {
        for (i, m) in self.motors.iter_mut().enumerate() {
            if m.value != 0 && now_ms >= m.until_ms {
                crate::info!(
                    "AOK motor test: motor {=usize} {=u8} -> 0 (lapsed)",
                    i.wrapping_add(1),
                    m.value
                );
                m.value = 0;
            }
        }
        if let Some(e) = self.external
            && now_ms >= e.until_ms
        {
            crate::info!("AOK external control expired: RC has control");
            self.external = None;
        }
    }

    fn tx_free(&self) -> usize {
        TX_CAPACITY.saturating_sub(self.tx.len())
    }

    /// Queues a whole reply, or drops it (counted) when it does not fit.
    fn queue(&mut self, bytes: &[u8]) {
        if self.tx_free() < bytes.len() {
            crate::warn!("AOK: TX queue full, reply dropped");
            self.counters.replies_dropped = self.counters.replies_dropped.wrapping_add(1);
            return;
        }
        for &b in bytes {
            let _ = self.tx.push_back(b);
        }
    }

    fn ack(&mut self, ack: Ack) {
        match ack {
            Ack::Ok => {}
            Ack::Error => self.counters.rejected = self.counters.rejected.wrapping_add(1),
            Ack::InFlight => {
                self.counters.refused_in_flight = self.counters.refused_in_flight.wrapping_add(1)
            }
        }
        self.queue(&[ack.byte()]);
    }

    fn handle(&mut self, item: Result<Command, AokError>, now_ms: u64, shared: &mut Shared) {
        let command = match item {
            Ok(c) => c,
            // A frame cut by a quiet line: counted by the decoder, nothing to answer.
            Err(AokError::Truncated) => return,
            Err(AokError::ChecksumMismatch) | Err(AokError::InvalidSlot(_)) => {
                // A faulty `73`/`77` is answered 'E' (the spec); the decoder cannot say which
                // command a bad checksum belonged to, so every one is answered.
                self.ack(Ack::Error);
                return;
            }
            Err(_) => {
                // Stick values beyond ±200: external control has no ack; counted by the decoder.
                crate::warn!("AOK: command with an out-of-range field ignored");
                return;
            }
        };
        let flying = flying(shared);
        match command {
            Command::DebugOff => {
                crate::info!("AOK debug off");
                self.debug_on = false;
            }
            Command::DebugOn => {
                crate::info!("AOK debug on");
                self.debug_on = true;
                self.next_debug_ms = now_ms;
            }
            Command::Reset => {
                crate::info!("AOK reset requested");
                shared.requests.reboot = true;
            }
            Command::SetParameter(p) => self.set_parameter(p, flying),
            Command::ReadParameter(number) => {
                let value = self.parameter(number);
                let mut buf = [0u8; HEADED_REPLY_LEN];
                let reply = ParameterValue { number, value };
                if let Ok(n) = device::encode_parameter(reply, FIRMWARE.reply_form(), &mut buf) {
                    self.queue(buf.get(..n).unwrap_or_default());
                }
            }
            Command::BulkRead(first) => {
                let mut values = [0i32; 16];
                let mut number = first;
                for v in values.iter_mut() {
                    *v = self.parameter(number);
                    number = number.wrapping_add(1);
                }
                let mut buf = [0u8; MAX_REPLY];
                if let Ok(n) = device::encode_bulk(first, &values, &mut buf) {
                    self.queue(buf.get(..n).unwrap_or_default());
                }
            }
            Command::LoadSet(n) => {
                let ack = match shared.persisted.aok.sets.get(usize::from(n)) {
                    None => Ack::Error,
                    Some(_) if flying => Ack::InFlight,
                    Some(set) => {
                        crate::info!("AOK parameters loaded from set {=u8}", n);
                        self.params = *set;
                        Ack::Ok
                    }
                };
                self.ack(ack);
            }
            Command::SaveSet(n) => {
                let params = self.params;
                let ack = match shared.persisted.aok.sets.get_mut(usize::from(n)) {
                    None => Ack::Error,
                    Some(_) if flying => Ack::InFlight,
                    Some(set) => {
                        crate::info!("AOK parameters saved to set {=u8}", n);
                        *set = params;
                        shared.requests.store = true;
                        Ack::Ok
                    }
                };
                self.ack(ack);
            }
            Command::StartSet(n) => {
                let ack = if usize::from(n) >= shared.persisted.aok.sets.len() {
                    Ack::Error
                } else if flying {
                    Ack::InFlight
                } else {
                    crate::info!("AOK start set {=u8}", n);
                    shared.persisted.aok.start_set = n;
                    shared.requests.store = true;
                    Ack::Ok
                };
                self.ack(ack);
            }
            Command::SaveWaypoints => {
                let ack = if flying {
                    Ack::InFlight
                } else {
                    crate::info!("AOK waypoints saved to flash");
                    let flash = &mut shared.persisted.aok.waypoints;
                    for (f, r) in flash.iter_mut().zip(self.waypoints.iter()) {
                        *f = *r;
                    }
                    if let Some(poi) = flash.get_mut(MISSION_POI) {
                        *poi = self.ram_poi;
                    }
                    shared.requests.store = true;
                    Ack::Ok
                };
                self.ack(ack);
            }
            Command::LoadWaypoints => {
                crate::info!("AOK waypoints loaded from flash");
                self.load_waypoints(shared);
                self.ack(Ack::Ok);
            }
            Command::SetWaypoint(w) => {
                let stored = StoredWaypoint {
                    lon: w.longitude,
                    lat: w.latitude,
                    action1: w.action1.raw(),
                    action2: w.action2.raw(),
                };
                let ack = match w.slot {
                    WaypointSlot::Waypoint(n) => {
                        match self.waypoints.get_mut(usize::from(n.wire())) {
                            Some(slot) => {
                                *slot = stored;
                                Ack::Ok
                            }
                            None => Ack::Error,
                        }
                    }
                    WaypointSlot::MissionPoi if flying => Ack::InFlight,
                    WaypointSlot::MissionPoi => {
                        match shared.persisted.aok.waypoints.get_mut(MISSION_POI) {
                            Some(slot) => {
                                *slot = stored;
                                shared.requests.store = true;
                                Ack::Ok
                            }
                            None => Ack::Error,
                        }
                    }
                    WaypointSlot::RamPoi => {
                        self.ram_poi = stored;
                        Ack::Ok
                    }
                    WaypointSlot::FbcTarget => {
                        self.fbc_target = stored;
                        Ack::Ok
                    }
                };
                self.ack(ack);
            }
            Command::ReadWaypoint(slot) => {
                let s = self.waypoint(slot, shared);
                let w = Waypoint {
                    slot,
                    longitude: s.lon,
                    latitude: s.lat,
                    action1: ActionWord(s.action1),
                    action2: ActionWord(s.action2),
                };
                let mut buf = [0u8; 19];
                if let Ok(n) = device::encode_waypoint(&w, &mut buf) {
                    self.queue(buf.get(..n).unwrap_or_default());
                }
            }
            Command::MotorTest(m) => self.motor_test(m, now_ms, flying),
            Command::ExternalControl(e) => {
                if self.external.is_none() {
                    crate::info!("AOK external control takes over from RC");
                }
                self.external = Some(External {
                    control: e,
                    until_ms: now_ms.saturating_add(u64::from(e.expiry_ms)),
                });
            }
        }
    }

    fn parameter(&self, number: u8) -> i32 {
        self.params.get(usize::from(number)).copied().unwrap_or(0)
    }

    fn set_parameter(&mut self, p: ParameterValue, flying: bool) {
        let settable = in_flight_settable(p.number);
        let ack = match self.params.get_mut(usize::from(p.number)) {
            None => Ack::Error,
            Some(_) if flying && !settable => Ack::InFlight,
            Some(slot) => {
                *slot = p.value;
                Ack::Ok
            }
        };
        self.ack(ack);
    }

    fn motor_test(&mut self, m: MotorTest, now_ms: u64, flying: bool) {
        if flying {
            crate::warn!("AOK motor test refused: flying");
            self.counters.refused_in_flight = self.counters.refused_in_flight.wrapping_add(1);
            return;
        }
        let index = usize::from(m.motor.get()).wrapping_sub(1);
        if let Some(out) = self.motors.get_mut(index) {
            if out.value != m.value {
                crate::info!(
                    "AOK motor test: motor {=u8} {=u8} -> {=u8}",
                    m.motor.get(),
                    out.value,
                    m.value
                );
            }
            out.value = m.value;
            out.until_ms = now_ms.saturating_add(MOTOR_LAPSE_MS);
        }
    }

    /// `63 09` (and boot): flash slots 0..=30 into RAM, flash slot 31 into the RAM POI.
    fn load_waypoints(&mut self, shared: &Shared) {
        let flash = &shared.persisted.aok.waypoints;
        for (r, f) in self.waypoints.iter_mut().zip(flash.iter()) {
            *r = *f;
        }
        self.ram_poi = flash.get(MISSION_POI).copied().unwrap_or_default();
    }

    fn send_debug(&mut self, now_ms: u64, shared: &Shared) {
        let id = DebugId::CYCLE
            .get(self.debug_index)
            .copied()
            .unwrap_or(DebugId::FlightStatus);
        self.debug_index = self.debug_index.wrapping_add(1);
        if self.debug_index >= DebugId::CYCLE.len() {
            self.debug_index = 0;
        }
        let value = DebugValue {
            number: id as u8,
            value: self.debug_value(id, now_ms, shared),
        };
        let mut buf = [0u8; DEBUG_LEN];
        if let Ok(n) = device::encode_debug(value, &mut buf) {
            self.queue(buf.get(..n).unwrap_or_default());
            self.counters.debug_frames = self.counters.debug_frames.wrapping_add(1);
        }
        let period = u64::from(shared.settings().aok_debug_period_ms);
        let next = self.next_debug_ms.saturating_add(period);
        // On time: keep the grid. Late (slow polls, a full port): restart from now, no burst.
        self.next_debug_ms = if next <= now_ms {
            now_ms.saturating_add(period)
        } else {
            next
        };
    }

    /// The value of one debug id at `now_ms`, scaled to i32 (see [`DebugId`]).
    pub fn debug_value(&self, id: DebugId, now_ms: u64, shared: &Shared) -> i32 {
        let s = shared.flight_state(now_ms);
        match id {
            DebugId::Roll => scaled(s.euler.roll.to_degrees(), 100.0),
            DebugId::Pitch => scaled(s.euler.pitch.to_degrees(), 100.0),
            DebugId::Heading => scaled(s.heading_deg, 100.0),
            DebugId::Airspeed => scaled(s.airspeed_mps, 100.0),
            DebugId::Altitude => scaled(s.gps_altitude_m, 100.0),
            DebugId::StaticPressure => scaled(s.static_pressure_mbar, 100.0),
            DebugId::PitotPressure => scaled(s.pitot_pressure_mbar, 100.0),
            DebugId::Temperature => scaled(s.oat_celsius, 100.0),
            DebugId::Latitude => scaled64(s.latitude_deg, 1e7),
            DebugId::Longitude => scaled64(s.longitude_deg, 1e7),
            DebugId::GroundSpeed => scaled(s.ground_speed_mps, 100.0),
            DebugId::TurnRate => scaled(s.turn_rate_rad_s.to_degrees(), 100.0),
            DebugId::ControlSource => match self.control_source() {
                ControlSource::Rc => 0,
                ControlSource::External => 1,
            },
            DebugId::MotorTestMask => self.motor_mask(),
            DebugId::FlightStatus => {
                let mut status = 0;
                if flying(shared) {
                    status |= STATUS_FLYING;
                }
                if self.external.is_some() {
                    status |= STATUS_EXTERNAL;
                }
                if self.motor_mask() != 0 {
                    status |= STATUS_MOTOR_TEST;
                }
                status
            }
        }
    }

    fn motor_mask(&self) -> i32 {
        self.motors
            .iter()
            .rev()
            .fold(0, |mask, m| (mask << 1) | i32::from(m.value != 0))
    }
}

/// `x * scale` rounded to the nearest integer; saturates, NaN gives 0 (`as` from float).
fn scaled(x: f32, scale: f32) -> i32 {
    let v = x * scale;
    (if v >= 0.0 { v + 0.5 } else { v - 0.5 }) as i32
}

fn scaled64(x: f64, scale: f64) -> i32 {
    let v = x * scale;
    (if v >= 0.0 { v + 0.5 } else { v - 0.5 }) as i32
}
