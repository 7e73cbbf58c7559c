//! Motors and external control: the motor-test outputs and their lapse, the external-control
//! sticks and their expiry.

use super::{AokLink, External, MOTOR_LAPSE_MS};
use aok_proto::{ExternalControl, MotorTest};

impl AokLink {
    /// Motor-test values and external control run out.
    pub(super) fn expire(&mut self, now_ms: u64) {
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

    /// A motor-test frame: refused in flight; a motor at rest is armed by the first frame and
    /// runs from the second of a later burst within [`MOTOR_LAPSE_MS`] (see [`AokLink`],
    /// "Motor test"); value 0 stops it at once.
    pub(super) fn motor_test(&mut self, m: MotorTest, now_ms: u64, flying: bool) {
        if flying {
            crate::warn!("AOK motor test refused: flying");
            self.counters.refused_in_flight = self.counters.refused_in_flight.wrapping_add(1);
            return;
        }
        let index = usize::from(m.motor.get()).wrapping_sub(1);
        let burst = self.bursts_obeyed;
        let Some(out) = self.motors.get_mut(index) else {
            return;
        };
        let running = out.value != 0;
        let repeat = out.armed_until_ms > now_ms && out.armed_burst != burst;
        if m.value != 0 && !running && !repeat {
            // The first frame for a motor at rest: armed, not driven.
            out.armed_until_ms = now_ms.saturating_add(MOTOR_LAPSE_MS);
            out.armed_burst = burst;
            self.counters.motor_frames_armed = self.counters.motor_frames_armed.wrapping_add(1);
            return;
        }
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
        out.armed_until_ms = 0;
    }

    /// `53`: external control takes over (or goes on) until `expiry_ms` from now.
    pub(super) fn take_external(&mut self, e: ExternalControl, now_ms: u64) {
        if self.external.is_none() {
            crate::info!("AOK external control takes over from RC");
        }
        self.external = Some(External {
            control: e,
            until_ms: now_ms.saturating_add(u64::from(e.expiry_ms)),
        });
    }
}
