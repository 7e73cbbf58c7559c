//! Every event of one byte (`feed` with a one-byte slice) and of a quiet line (`finish`), for
//! either decoder: the byte-by-byte reference the bulk path, the pull form and the readers
//! are held to.
#![allow(dead_code)]

use aok_proto::{Command, CommandDecoder, Decode, Error, Event, Message, MessageDecoder};

/// Either decoder, with its events owned.
pub trait Events {
    /// What one event carries.
    type Item;
    /// Every event of `feed(bytes)`.
    fn feed_vec(&mut self, bytes: &[u8]) -> Vec<Result<Self::Item, Error>>;
    /// Every event of `finish`.
    fn finish_vec(&mut self) -> Vec<Result<Self::Item, Error>>;
    /// Every event of the pull form over `bytes`: `decode` on what is left until every byte
    /// is used, then with an empty slice until it finds nothing (as the readers call it).
    fn decode_vec(&mut self, bytes: &[u8]) -> Vec<Result<Self::Item, Error>>;
}

macro_rules! events {
    ($decoder:ty, $item:ty) => {
        impl Events for $decoder {
            type Item = $item;
            fn feed_vec(&mut self, bytes: &[u8]) -> Vec<Result<$item, Error>> {
                let mut out = Vec::new();
                self.feed(bytes, |ev| out.push(ev));
                out
            }
            fn finish_vec(&mut self) -> Vec<Result<$item, Error>> {
                let mut out = Vec::new();
                self.finish(|ev| out.push(ev));
                out
            }
            fn decode_vec(&mut self, bytes: &[u8]) -> Vec<Result<$item, Error>> {
                let mut out = Vec::new();
                let mut rest = bytes;
                loop {
                    let (used, event) = self.decode(rest);
                    rest = &rest[used..];
                    match event {
                        Some(Event::Found(found)) => out.push(Ok(self.item(&[], found))),
                        Some(Event::Error(e)) => out.push(Err(e)),
                        Some(Event::Truncated(_)) => out.push(Err(Error::Truncated)),
                        None if rest.is_empty() => return out,
                        None => {}
                    }
                }
            }
        }
    };
}

events!(CommandDecoder, Command);
events!(MessageDecoder, Message);

/// Every event of feeding `byte` alone (`feed` with a one-byte slice).
pub fn feed_byte<D: Events>(d: &mut D, byte: u8) -> Vec<Result<D::Item, Error>> {
    d.feed_vec(core::slice::from_ref(&byte))
}

/// Every event of `finish` (the line went quiet).
pub fn finish_all<D: Events>(d: &mut D) -> Vec<Result<D::Item, Error>> {
    d.finish_vec()
}

/// Every event of feeding each byte of `bytes` alone, in turn.
pub fn feed_bytes<D: Events>(d: &mut D, bytes: &[u8]) -> Vec<Result<D::Item, Error>> {
    bytes.iter().flat_map(|&b| feed_byte(d, b)).collect()
}

/// Every event of the pull form over `bytes` (`decode` until it finds nothing).
pub fn decode_all<D: Events>(d: &mut D, bytes: &[u8]) -> Vec<Result<D::Item, Error>> {
    d.decode_vec(bytes)
}
