//! Dispatch: what the link does with each message it receives (updates, requests, store
//! configuration, direct output).

use super::Ctx;
use super::periodic::timestamp;
use super::registry::View;
use crate::Shared;
use crate::store_policy::Verdict;
use aydp_proto::registry::Registry;
use aydp_proto::{Frame, Message, Stats, SystemControl, SystemValueUpdate, Timestamp};

impl Ctx {
    /// Acts on one received message; a reply goes into the TX queue.
    pub(super) fn handle(
        &mut self,
        frame: &Frame<'_>,
        stats: &Stats,
        now_ms: u64,
        shared: &mut Shared,
    ) {
        let message = match frame.message() {
            Ok(m) => m,
            Err(e) => {
                self.counters.malformed = self.counters.malformed.wrapping_add(1);
                crate::warn!("AYDP: malformed type {=u8}: {}", frame.base_type(), e);
                return;
            }
        };
        match message {
            Message::SystemValueUpdate(update) => self.update(&update, stats, now_ms, shared),
            Message::SystemControl(SystemControl::RequestData { address }) => {
                let ts = (!frame.is_expedited()).then(|| timestamp(shared, now_ms));
                self.request(address, ts, stats, shared);
            }
            Message::SystemControl(SystemControl::StoreConfiguration) => {
                // No answer in the protocol: a refusal is counted (0x0310) and logged.
                self.counters.stores_requested = self.counters.stores_requested.wrapping_add(1);
                let flying = crate::aok_link::flying(shared);
                if shared.request_store(now_ms, flying) == Verdict::Accepted {
                    crate::info!("AYDP: store configuration");
                }
            }
            Message::DirectOutput(out) => self.direct(&out, shared),
            Message::Heartbeat => {
                self.counters.heartbeats_received =
                    self.counters.heartbeats_received.wrapping_add(1);
            }
            _ => {
                self.counters.ignored = self.counters.ignored.wrapping_add(1);
                crate::debug!("AYDP: ignored type {=u8}", frame.base_type());
            }
        }
    }

    /// A candidate the decoder dropped: counted (see [`crate::port`], "Receive errors").
    pub(super) fn rx_error(&mut self, e: aydp_proto::Error) {
        self.counters.rx_errors = self.counters.rx_errors.wrapping_add(1);
        crate::debug!("AYDP: dropped a candidate: {}", e);
    }

    fn update(
        &mut self,
        update: &SystemValueUpdate<'_>,
        stats: &Stats,
        now_ms: u64,
        shared: &mut Shared,
    ) {
        let mut view = View::new(shared, stats, &self.counters);
        let result = Registry::new(&mut view.slots()).apply(update);
        match result {
            Ok(()) => {
                view.write_back(shared, now_ms);
                self.counters.updates_applied = self.counters.updates_applied.wrapping_add(1);
                crate::info!("AYDP: value at {=u16:#x} updated", update.address);
            }
            Err(e) => {
                self.counters.rejected = self.counters.rejected.wrapping_add(1);
                crate::warn!("AYDP: update of {=u16:#x} rejected: {}", update.address, e);
            }
        }
    }

    fn request(&mut self, address: u16, ts: Option<Timestamp>, stats: &Stats, shared: &Shared) {
        let mut view = View::new(shared, stats, &self.counters);
        let mut slots = view.slots();
        let registry = Registry::new(&mut slots);
        let mut out = [0u8; 64];
        match registry.read(address, &mut out) {
            Ok(reply) => {
                self.counters.requests_answered = self.counters.requests_answered.wrapping_add(1);
                self.send(&reply, ts, 0);
            }
            Err(e) => {
                self.counters.rejected = self.counters.rejected.wrapping_add(1);
                crate::warn!("AYDP: request for {=u16:#x} rejected: {}", address, e);
            }
        }
    }

    fn direct(&mut self, out: &aydp_proto::DirectOutput<'_>, shared: &mut Shared) {
        if !shared.direct_control {
            self.counters.direct_refused = self.counters.direct_refused.wrapping_add(1);
            crate::warn!("AYDP: direct output refused: direct control is off (0x0000 = 0)");
            return;
        }
        let mut outputs = shared.outputs;
        for e in out.entries() {
            let slot = outputs
                .iter_mut()
                .find(|o| o.device == e.device && o.channel == e.channel);
            match slot {
                Some(o) if e.value.is_finite() => o.value = e.value,
                _ => {
                    self.counters.direct_refused = self.counters.direct_refused.wrapping_add(1);
                    crate::warn!(
                        "AYDP: direct output refused: output {=u8}.{=u8} = {=f32}",
                        e.device,
                        e.channel,
                        e.value
                    );
                    return;
                }
            }
        }
        for (o, new) in shared.outputs.iter().zip(outputs.iter()) {
            if o.value.to_bits() != new.value.to_bits() {
                crate::info!(
                    "AYDP: output {=u8}.{=u8} = {=f32}",
                    new.device,
                    new.channel,
                    new.value
                );
            }
        }
        shared.outputs = outputs;
        self.counters.direct_applied = self.counters.direct_applied.wrapping_add(1);
    }
}
