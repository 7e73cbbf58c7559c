//! Parameters: reading one or sixteen, setting one in RAM with the in-flight rule, and the
//! parameter sets in flash (load, save, choose the start set).

use super::{AokLink, FIRMWARE, MAX_REPLY, in_flight_settable};
use crate::Shared;
use crate::store_policy::Verdict;
use aok_proto::message::HEADED_REPLY_LEN;
use aok_proto::{Ack, BulkReply, Message, ParameterValue};

impl AokLink {
    pub(super) fn parameter(&self, number: u8) -> i32 {
        self.params.get(usize::from(number)).copied().unwrap_or(0)
    }

    /// `73`: one parameter into RAM ('I' while flying unless it is in-flight settable).
    pub(super) fn set_parameter(&mut self, p: ParameterValue, flying: bool) {
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

    /// `67`: one parameter, in the reply form of [`FIRMWARE`].
    pub(super) fn read_parameter(&mut self, number: u8) {
        let value = self.parameter(number);
        let mut buf = [0u8; HEADED_REPLY_LEN];
        let reply = ParameterValue { number, value };
        if let Ok(n) = Message::Parameter(reply).emit(&mut buf, FIRMWARE.reply_form()) {
            self.queue(buf.get(..n).unwrap_or_default());
        }
    }

    /// `47`: sixteen parameters from `first` (numbers wrap at 255).
    pub(super) fn bulk_read(&mut self, first: u8) {
        let mut values = [0i32; 16];
        let mut number = first;
        for v in values.iter_mut() {
            *v = self.parameter(number);
            number = number.wrapping_add(1);
        }
        let mut buf = [0u8; MAX_REPLY];
        let reply = BulkReply { first, values };
        if let Ok(n) = reply.emit(&mut buf) {
            self.queue(buf.get(..n).unwrap_or_default());
        }
    }

    /// `63 03 NUM`: the RAM parameters from set `n` (not while flying).
    pub(super) fn load_set(&mut self, n: u8, flying: bool, shared: &Shared) {
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

    /// `63 04 NUM`: the RAM parameters into set `n` and the flash (when the [store
    /// policy](crate::store_policy) allows: 'I' flying, 'E' too soon).
    pub(super) fn save_set(&mut self, n: u8, flying: bool, now_ms: u64, shared: &mut Shared) {
        let ack = match shared.persisted.aok.sets.get(usize::from(n)) {
            None => Ack::Error,
            Some(_) => store_ack(shared.request_store(now_ms, flying)),
        };
        if let (Ack::Ok, Some(set)) = (ack, shared.persisted.aok.sets.get_mut(usize::from(n))) {
            crate::info!("AOK parameters saved to set {=u8}", n);
            *set = self.params;
        }
        self.ack(ack);
    }

    /// `63 05 NUM`: the set loaded at boot (stored as `63 04` is).
    pub(super) fn start_set(&mut self, n: u8, flying: bool, now_ms: u64, shared: &mut Shared) {
        let ack = if usize::from(n) >= shared.persisted.aok.sets.len() {
            Ack::Error
        } else {
            store_ack(shared.request_store(now_ms, flying))
        };
        if ack == Ack::Ok {
            crate::info!("AOK start set {=u8}", n);
            shared.persisted.aok.start_set = n;
        }
        self.ack(ack);
    }
}

/// The AOK answer to the store policy's verdict: 'O' accepted, 'I' flying, 'E' too soon (K6
/// has no "busy"; 'I' would tell the PC the box is flying).
pub(super) fn store_ack(verdict: Verdict) -> Ack {
    match verdict {
        Verdict::Accepted => Ack::Ok,
        Verdict::InFlight => Ack::InFlight,
        Verdict::TooSoon => Ack::Error,
    }
}
