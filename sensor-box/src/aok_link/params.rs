//! Parameters: reading one and setting one in RAM, with the in-flight rule.

use super::{AokLink, in_flight_settable};
use aok_proto::{Ack, ParameterValue};

impl AokLink {
    pub(super) fn parameter(&self, number: u8) -> i32 {
        self.params.get(usize::from(number)).copied().unwrap_or(0)
    }

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
}
