//! The registry: the addresses, the prescribed texts, and the view of [`Shared`] that the
//! registry's slots point at.

use super::LinkCounters;
use crate::Shared;
use crate::state::{Intervals, OUTPUTS};
use aydp_proto::Stats;
use aydp_proto::registry::{Cell, Slot};

/// The registry's addresses.
pub mod addr {
    /// Enable direct control, u8 0/1, read-write (prescribed, Y9).
    pub const DIRECT_CONTROL: u16 = 0x0000;
    /// System name, char\[40\], read-only (prescribed).
    pub const SYSTEM_NAME: u16 = 0x0001;
    /// System ID, char\[40\], read-only (prescribed).
    pub const SYSTEM_ID: u16 = 0x0002;
    /// Hardware version, char\[40\], read-only (prescribed).
    pub const HARDWARE_VERSION: u16 = 0x0003;
    /// Firmware version, char\[40\], read-only (prescribed).
    pub const FIRMWARE_VERSION: u16 = 0x0004;
    /// AEOLUS telemetry intervals in ms, u32\[6\]: IMU (GYRO, ACCEL, MAGNET, ATTITUDE,
    /// COMPASS), PRESSURE, GPS, TEMP, WIND, AEOLUSINFO.
    pub const INTERVALS: u16 = 0x0100;
    /// Simulated true airspeed, m/s, f32.
    pub const AIRSPEED: u16 = 0x0110;
    /// Simulated bank angle, degrees (positive: right turn), f32.
    pub const BANK: u16 = 0x0111;
    /// Simulated altitude, m, f32.
    pub const ALTITUDE: u16 = 0x0112;
    /// AOK debug value stream period, ms, u32 (0: as fast as the link allows).
    pub const AOK_DEBUG_PERIOD: u16 = 0x0120;
    /// The direct outputs (device 1, channels 0..=7), f32\[8\], read-only.
    pub const OUTPUTS: u16 = 0x0200;
    /// The link counters, u32\[10\], read-only (order: [`COUNTER_NAMES`](crate::aydp_link::COUNTER_NAMES)).
    pub const LINK_COUNTERS: u16 = 0x0300;
    /// The flash store counters of every link, u32\[5\], read-only (order:
    /// [`STORE_COUNTER_NAMES`](crate::aydp_link::STORE_COUNTER_NAMES)).
    pub const STORE_COUNTERS: u16 = 0x0310;
    /// Setting groups whose newest copy in flash did not verify at the last boot (an older
    /// copy was loaded), u32, read-only.
    pub const CORRUPT_ITEMS: u16 = 0x0311;
}

/// Names of the u32\[5\] at [`addr::STORE_COUNTERS`], in order: the store counters of
/// [`Counters`](crate::state::Counters), for all links (see [`crate::store_policy`]).
pub const STORE_COUNTER_NAMES: [&str; 5] = [
    "stores written",
    "stores unchanged (not written)",
    "stores failed",
    "stores refused in flight",
    "stores refused by the rate limit",
];

/// Length of the prescribed texts.
pub const TEXT_LEN: usize = 40;

/// `s` as a NUL-padded `char[40]` (cut at 40 bytes).
const fn text(s: &str) -> [u8; TEXT_LEN] {
    let b = s.as_bytes();
    let mut out = [0u8; TEXT_LEN];
    let mut i = 0;
    while i < b.len() && i < TEXT_LEN {
        out[i] = b[i];
        i += 1;
    }
    out
}

/// 0x0001 system name.
pub const SYSTEM_NAME: [u8; TEXT_LEN] = text("protolink sensor box");
/// 0x0002 system ID.
pub const SYSTEM_ID: [u8; TEXT_LEN] = text("SBX-0001");
/// 0x0003 hardware version: the board the firmware was built for (board features only take
/// effect on the target, like the rest of the board support).
pub const HARDWARE_VERSION: [u8; TEXT_LEN] = text(
    if cfg!(all(target_os = "none", feature = "hardware-stm32f411")) {
        "STM32F411"
    } else if cfg!(all(target_os = "none", feature = "hardware-lm3s6965evb")) {
        "QEMU lm3s6965evb"
    } else {
        "host"
    },
);
/// 0x0004 firmware version.
pub const FIRMWARE_VERSION: [u8; TEXT_LEN] =
    text(concat!("sensor-box ", env!("CARGO_PKG_VERSION")));

/// The registry's storage: a copy of the values in [`Shared`] (and the texts and counters)
/// that the registry's slots point at. An accepted update is copied back with
/// [`View::write_back`]; a rejected one is simply dropped with the view.
pub(super) struct View {
    direct: u8,
    name: [u8; TEXT_LEN],
    id: [u8; TEXT_LEN],
    hardware: [u8; TEXT_LEN],
    firmware: [u8; TEXT_LEN],
    intervals: [u32; 6],
    airspeed: f32,
    bank: f32,
    altitude: f32,
    aok_period: u32,
    outputs: [f32; OUTPUTS],
    counters: [u32; 10],
    store: [u32; 5],
    corrupt: u32,
}

impl View {
    pub(super) fn new(shared: &Shared, stats: &Stats, c: &LinkCounters) -> Self {
        let s = shared.settings();
        let mut outputs = [0.0; OUTPUTS];
        for (v, o) in outputs.iter_mut().zip(shared.outputs.iter()) {
            *v = o.value;
        }
        View {
            direct: u8::from(shared.direct_control),
            name: SYSTEM_NAME,
            id: SYSTEM_ID,
            hardware: HARDWARE_VERSION,
            firmware: FIRMWARE_VERSION,
            intervals: s.intervals.to_array(),
            airspeed: s.airspeed_mps,
            bank: s.bank_deg,
            altitude: s.altitude_m,
            aok_period: s.aok_debug_period_ms,
            outputs,
            counters: [
                stats.frames_ok,
                stats.checksum_errors,
                stats.length_errors,
                stats.bytes_discarded,
                c.updates_applied,
                c.rejected,
                c.malformed,
                c.requests_answered,
                c.direct_applied,
                c.direct_refused,
            ],
            store: {
                let s = &shared.counters;
                [
                    s.stores_written,
                    s.stores_unchanged,
                    s.store_failures,
                    s.stores_refused_in_flight,
                    s.stores_rate_limited,
                ]
            },
            corrupt: shared.counters.corrupt_items,
        }
    }

    /// The registry table over this view (see the module table).
    pub(super) fn slots(&mut self) -> [Slot<'_>; 14] {
        [
            Slot::value(addr::DIRECT_CONTROL, Cell::u8(&mut self.direct)).with_range(0.0, 1.0),
            Slot::value(addr::SYSTEM_NAME, Cell::Chars(&mut self.name)).read_only(),
            Slot::value(addr::SYSTEM_ID, Cell::Chars(&mut self.id)).read_only(),
            Slot::value(addr::HARDWARE_VERSION, Cell::Chars(&mut self.hardware)).read_only(),
            Slot::value(addr::FIRMWARE_VERSION, Cell::Chars(&mut self.firmware)).read_only(),
            Slot::array(addr::INTERVALS, Cell::U32(&mut self.intervals)).with_range(1.0, 60_000.0),
            Slot::value(addr::AIRSPEED, Cell::f32(&mut self.airspeed)).with_range(10.0, 150.0),
            Slot::value(addr::BANK, Cell::f32(&mut self.bank)).with_range(-60.0, 60.0),
            Slot::value(addr::ALTITUDE, Cell::f32(&mut self.altitude)).with_range(-500.0, 11_000.0),
            Slot::value(addr::AOK_DEBUG_PERIOD, Cell::u32(&mut self.aok_period))
                .with_range(0.0, 60_000.0),
            Slot::array(addr::OUTPUTS, Cell::F32(&mut self.outputs)).read_only(),
            Slot::array(addr::LINK_COUNTERS, Cell::U32(&mut self.counters)).read_only(),
            Slot::array(addr::STORE_COUNTERS, Cell::U32(&mut self.store)).read_only(),
            Slot::value(addr::CORRUPT_ITEMS, Cell::u32(&mut self.corrupt)).read_only(),
        ]
    }

    /// Copies the writable values back into `shared`; rebuilds the flight if airspeed, bank
    /// or altitude changed.
    pub(super) fn write_back(&self, shared: &mut Shared, now_ms: u64) {
        shared.direct_control = self.direct == 1;
        let s = &mut shared.persisted.settings;
        s.intervals = Intervals::from_array(self.intervals);
        s.aok_debug_period_ms = self.aok_period;
        let flight_changed = s.airspeed_mps.to_bits() != self.airspeed.to_bits()
            || s.bank_deg.to_bits() != self.bank.to_bits()
            || s.altitude_m.to_bits() != self.altitude.to_bits();
        s.airspeed_mps = self.airspeed;
        s.bank_deg = self.bank;
        s.altitude_m = self.altitude;
        if flight_changed {
            shared.settings_changed(now_ms);
        }
    }
}
