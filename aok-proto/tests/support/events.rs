//! Every event of one byte (`push`, then `poll` until `None`) and of a quiet line (`idle`), for
//! either decoder: the byte-by-byte reference the bulk paths and readers are held to.
#![allow(dead_code)]

use aok_proto::{Command, DeviceDecoder, Error, Message, PcDecoder};

/// `push` + `poll` of either decoder.
pub trait Events {
    /// What one event carries.
    type Item;
    /// `push`.
    fn push_one(&mut self, byte: u8) -> Option<Result<Self::Item, Error>>;
    /// `poll`.
    fn poll_one(&mut self) -> Option<Result<Self::Item, Error>>;
    /// `idle_next`.
    fn idle_one(&mut self) -> Option<Result<Self::Item, Error>>;
}

impl Events for DeviceDecoder {
    type Item = Command;
    fn push_one(&mut self, byte: u8) -> Option<Result<Command, Error>> {
        self.push(byte)
    }
    fn poll_one(&mut self) -> Option<Result<Command, Error>> {
        self.poll()
    }
    fn idle_one(&mut self) -> Option<Result<Command, Error>> {
        self.idle_next()
    }
}

impl Events for PcDecoder {
    type Item = Message;
    fn push_one(&mut self, byte: u8) -> Option<Result<Message, Error>> {
        self.push(byte)
    }
    fn poll_one(&mut self) -> Option<Result<Message, Error>> {
        self.poll()
    }
    fn idle_one(&mut self) -> Option<Result<Message, Error>> {
        self.idle_next()
    }
}

/// Every event of pushing `byte`: `push`, then `poll` until `None`.
pub fn push_all<D: Events>(d: &mut D, byte: u8) -> Vec<Result<D::Item, Error>> {
    let mut out = Vec::new();
    let mut event = d.push_one(byte);
    while let Some(ev) = event {
        out.push(ev);
        event = d.poll_one();
    }
    out
}

/// Every event of `idle`.
pub fn idle_all<D: Events>(d: &mut D) -> Vec<Result<D::Item, Error>> {
    let mut out = Vec::new();
    while let Some(ev) = d.idle_one() {
        out.push(ev);
    }
    out
}

/// Every event of pushing each byte of `bytes` in turn.
pub fn push_bytes<D: Events>(d: &mut D, bytes: &[u8]) -> Vec<Result<D::Item, Error>> {
    bytes.iter().flat_map(|&b| push_all(d, b)).collect()
}
