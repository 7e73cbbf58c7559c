//! # panic-never
//!
//! Feeds bytes the optimiser cannot see (read with `read_volatile`) through every decoder,
//! typed parse and encoder of the protocol crates (AEOLUS, AOK, AYDP and GDL90). The panic
//! handler calls a function that is defined nowhere, so this binary only links if the
//! optimiser removed every panic path: if a change makes a panic reachable from any of these
//! entry points, the link fails with
//! `undefined symbol: PANIC_PATH_REACHABLE_see_checks_panic_never`.
//!
//! The `embedded-io` readers and writers of the three crates (the readers and write loops are
//! `frame-io`'s, over each crate's decoders), the `embedded-io-async` readers and the AOK async
//! writer are driven too, through a transport whose chunk sizes, errors and
//! end of stream are opaque. Not here: the AEOLUS and AYDP async writers and the AOK
//! `AsyncClient`. Every `async fn` state machine carries a compiler-inserted panic for being
//! polled after it completed; LLVM removes it only where it can see the whole state machine,
//! and it cannot across those three's loops. With a plain `loop {}` panic handler that guard
//! (`panic_const_async_fn_resumed`) is the only panic call they add; their logic is that of
//! the blocking writers and `Client`, which are checked here.
//!
//! Built for thumbv7m (the default) and for thumbv6m (`--target thumbv6m-none-eabi`).
#![no_std]
#![no_main]

use core::ptr::{addr_of, read_volatile};

unsafe extern "C" {
    /// Deliberately never defined.
    fn PANIC_PATH_REACHABLE_see_checks_panic_never() -> !;
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    unsafe { PANIC_PATH_REACHABLE_see_checks_panic_never() }
}

/// Opaque input: the optimiser must assume any contents.
static mut INPUT: [u8; 512] = [0; 512];
/// Opaque sink for results, so nothing is optimised away.
static mut SINK: u32 = 0;

fn input_byte(i: usize) -> u8 {
    unsafe { read_volatile(addr_of!(INPUT).cast::<u8>().add(i % 512)) }
}

fn input<const N: usize>() -> [u8; N] {
    let mut buf = [0u8; N];
    for (i, b) in buf.iter_mut().enumerate() {
        *b = input_byte(i);
    }
    buf
}

fn len() -> usize {
    input_byte(0) as usize | (input_byte(1) as usize) << 8
}

fn sink(v: u32) {
    unsafe { core::ptr::write_volatile(core::ptr::addr_of_mut!(SINK), v) }
}

/// Runs `step` (a decoder's `next_event`, its event handed to `sink`; the bytes consumed and
/// whether it found an event) on what each call left, until it finds nothing in what is left.
fn until_each(bytes: &[u8], mut step: impl FnMut(&[u8]) -> (usize, bool)) {
    let mut rest = bytes;
    loop {
        let (n, found) = step(rest);
        rest = rest.get(n..).unwrap_or(&[]);
        if !found && rest.is_empty() {
            break;
        }
    }
}

mod aeolus {
    use super::*;
    use aeolus_proto::{message::*, *};

    pub fn run() {
        // Decoder, byte by byte, both modes.
        let mut d = Decoder::<{ MAX_FIXED_FRAME }>::new();
        let mut s = Decoder::<16>::strict();
        for i in 0..len() {
            let b = input_byte(i);
            d.feed(&[b], |ev| {
                if let Ok(frame) = ev {
                    sink(frame.id() as u32 ^ frame.data().len() as u32 ^ frame.crc() as u32);
                    if let Ok(msg) = frame.message() {
                        sink(msg.buffer_len() as u32);
                    }
                }
            });
            s.feed(&[b], |ev| { sink(ev.is_ok() as u32); });
        }
        sink(d.stats().bytes_discarded ^ s.stats().frames_ok);

        // The bulk path, in opaque chunks, and the CRC over an opaque slice.
        let bulk: [u8; 512] = input();
        let total = len() % 513;
        let mut b = Decoder::<{ MAX_FIXED_FRAME }>::new();
        let mut at = 0;
        while at < total {
            let step = 1 + input_byte(at) as usize % 67;
            let end = if at + step < total { at + step } else { total };
            b.feed(bulk.get(at..end).unwrap_or(&[]), |ev| {
                if let Ok(frame) = ev {
                    if let Ok(msg) = frame.message() {
                        sink(msg.buffer_len() as u32);
                    }
                }
            });
            at = end;
        }
        sink(b.stats().frames_ok);
        sink(crc::update_slice(input_byte(3) as u16, bulk.get(..total).unwrap_or(&[])) as u32);

        // Event by event (`next_event`) over the same bytes.
        let mut u = Decoder::<{ MAX_FIXED_FRAME }>::new();
        until_each(bulk.get(..total).unwrap_or(&[]), |rest| {
            let (n, ev) = u.next_event(rest);
            let found = ev.is_some();
            if let Some(Ok(frame)) = ev {
                sink(frame.id() as u32 ^ frame.data().len() as u32);
            }
            (n, found)
        });
        sink(u.stats().frames_ok);

        // Datagram decoding in place.
        let mut dg: [u8; 300] = input();
        let n = len() % 301;
        for f in decode_datagram(&mut dg[..n], input_byte(2) & 1 == 1).flatten() {
            sink(f.raw().len() as u32);
        }

        // Every typed parse, then emit and encode what parsed.
        let data: [u8; 256] = input();
        let id = input_byte(3);
        let dl = len() % 257;
        if let Ok(msg) = Message::parse(id, &data[..dl]) {
            let mut out = [0u8; max_encoded_len(256)];
            let k = (input_byte(4) as usize) % out.len();
            if let Ok(n) = msg.encode(&mut out[..k], CrcMode::Compute) {
                sink(n as u32);
            }
            let mut raw = [0u8; 256];
            if let Ok(n) = msg.emit(&mut raw[..k.min(256)]) {
                sink(n as u32);
            }
        }
        // Encoders with arbitrary data and output sizes.
        let mut out = [0u8; 128];
        let k = (input_byte(5) as usize) % 129;
        if let Ok(n) = encode_frame(
            id,
            &data[..dl],
            &data[..dl % 7],
            CrcMode::Omit,
            &mut out[..k],
        ) {
            sink(n as u32);
        }
        for b in FrameBytes::new(id, &data[..dl], CrcMode::Compute) {
            sink(b as u32);
        }
        if let Ok(t) = Text::from_bytes(&data[..dl]) {
            sink(t.buffer_len() as u32);
        }
        sink(crc::checksum(&data[..dl]) as u32);
    }
}

mod aok {
    use super::*;
    use aok_proto::{
        Expect, MessageDecoder,
        *,
    };

    pub fn run() {
        // Device side: every command the PC sends, one byte a `feed`, then `finish`.
        let mut dev = CommandDecoder::new();
        let fw = FirmwareVersion::new(input_byte(6), input_byte(7));
        let mut host = MessageDecoder::new(fw);
        let slot = WaypointSlot::from_wire(input_byte(8)).unwrap_or(WaypointSlot::FbcTarget);
        for i in 0..len() {
            let b = input_byte(i);
            dev.feed(&[b], |item| {
                let Ok(cmd) = item else { return };
                let mut out = [0u8; 32];
                let k = input_byte(9) as usize % 33;
                if let Ok(n) = cmd.emit(&mut out[..k]) {
                    sink(n as u32);
                }
                if let Ok(n) = cmd.emit(&mut out[..k]) {
                    sink(n as u32);
                }
                sink(cmd.buffer_len() as u32);
            });
            if b == 0x55 {
                host.expect(match input_byte(i + 1) & 3 {
                    0 => Expect::Ack,
                    1 => Expect::Parameter(input_byte(i + 2)),
                    2 => Expect::Bulk(input_byte(i + 2)),
                    _ => Expect::Waypoint(slot),
                });
            }
            let form = host.reply_form();
            host.feed(&[b], |item| {
                let Ok(msg) = item else { return };
                let mut out = [0u8; 32];
                let k = input_byte(10) as usize % 33;
                if let Ok(n) = msg.emit(&mut out[..k], form) {
                    sink(n as u32);
                }
            });
        }
        dev.finish(|c| {
            if let Ok(cmd) = c {
                sink(cmd.buffer_len() as u32);
            }
        });
        host.finish(|m| {
            if let Ok(msg) = m {
                sink(msg.buffer_len(ReplyForm::Headed) as u32);
            }
        });
        sink(dev.stats().bytes_discarded ^ host.stats().frames_ok);

        // The bulk paths, in opaque chunks, with the pending request switched between them.
        let bulk: [u8; 512] = input();
        let total = len() % 513;
        let mut bdev = CommandDecoder::new();
        let mut bhost = MessageDecoder::new(fw);
        let mut at = 0;
        while at < total {
            let step = 1 + input_byte(at) as usize % 41;
            let end = if at + step < total { at + step } else { total };
            let chunk = bulk.get(at..end).unwrap_or(&[]);
            bdev.feed(chunk, |c| {
                if let Ok(cmd) = c {
                    sink(cmd.buffer_len() as u32);
                }
            });
            if input_byte(end) & 7 == 0 {
                bhost.expect(match input_byte(end + 1) & 3 {
                    0 => Expect::Ack,
                    1 => Expect::Parameter(input_byte(end + 2)),
                    2 => Expect::Bulk(input_byte(end + 2)),
                    _ => Expect::Waypoint(slot),
                });
            }
            bhost.feed(chunk, |m| {
                if let Ok(m) = m {
                    sink(m.buffer_len(ReplyForm::Headerless) as u32);
                }
            });
            at = end;
        }
        sink(bdev.stats().bytes_discarded ^ bhost.stats().frames_ok);

        // Event by event (`next_event`) over the same bytes, on both sides.
        let mut udev = CommandDecoder::new();
        until_each(bulk.get(..total).unwrap_or(&[]), |rest| {
            let (n, ev) = udev.next_event(rest);
            let found = ev.is_some();
            if let Some(Ok(cmd)) = ev {
                sink(cmd.buffer_len() as u32);
            }
            (n, found)
        });
        let mut uhost = MessageDecoder::new(fw);
        uhost.expect(Expect::Parameter(input_byte(5)));
        until_each(bulk.get(..total).unwrap_or(&[]), |rest| {
            let (n, ev) = uhost.next_event(rest);
            let found = ev.is_some();
            if let Some(Ok(m)) = ev {
                sink(m.buffer_len(ReplyForm::Headed) as u32);
            }
            (n, found)
        });
        sink(udev.stats().frames_ok ^ uhost.stats().bytes_discarded);

        // Typed parses on opaque bytes.
        let bytes: [u8; 32] = input();
        let n = len() % 33;
        if let Ok((c, used)) = Command::parse(&bytes[..n]) {
            let mut wire = [0u8; command::MAX_COMMAND_LEN];
            sink(c.emit(&mut wire).unwrap_or(0) as u32 ^ used as u32);
        }
        if let Ok((m, used)) = Message::parse(&bytes[..n]) {
            sink(m.buffer_len(ReplyForm::Headerless) as u32 ^ used as u32);
        }
        if let Ok(m) = ParameterValue::parse_headerless(&bytes[..n], input_byte(11)) {
            sink(m.value as u32);
        }
        // Encoders with opaque values and buffer sizes.
        let mut out = [0u8; 400];
        let k = len() % 401;
        let v = i32::from_le_bytes([
            input_byte(12),
            input_byte(13),
            input_byte(14),
            input_byte(15),
        ]);
        let _ = Message::Debug(DebugValue {
            number: input_byte(16),
            value: v,
        })
        .emit(&mut out[..k], ReplyForm::Headed);
        let _ = Message::Ack(Ack::Ok).emit(&mut out[..k], ReplyForm::Headed);
        let _ = BulkReply { first: input_byte(17), values: [v; 16] }.emit(&mut out[..k]);
        sink(out[0] as u32);
    }
}

mod aydp {
    use super::*;
    use aydp_proto::{
        registry::{Cell, Registry, Slot},
        *,
    };

    pub fn run() {
        let profile = if input_byte(20) & 1 == 0 {
            Profile::Spec
        } else {
            Profile::Reference
        };
        // The decoder, byte by byte, draining every event; then a flush.
        let mut d = Decoder::<128>::new(profile);
        let mut enable = 0u8;
        let mut name = [0u8; 40];
        let mut gains = [0f32; 3];
        let mut rate = 0u16;
        let mut slots = [
            Slot::value(0, Cell::u8(&mut enable)).with_range(0.0, 1.0),
            Slot::value(1, Cell::Chars(&mut name)).read_only(),
            Slot::array(0x100, Cell::F32(&mut gains)),
            Slot::value(0x101, Cell::u16(&mut rate)),
        ];
        let mut reg = Registry::new(&mut slots);
        let enc = Encoder::new(profile);
        for i in 0..len() {
            d.feed(&[input_byte(i)], |e| {
                if let Ok(frame) = e {
                    sink(frame.base_type() as u32 ^ frame.data().len() as u32);
                    if let Ok(msg) = frame.message() {
                        if let Message::SystemValueUpdate(u) = &msg {
                            sink(reg.apply(u).is_ok() as u32);
                        }
                        let mut out = [0u8; 200];
                        let k = input_byte(21) as usize % 201;
                        if let Ok(n) = enc.encode(&msg, None, &mut out[..k]) {
                            sink(n as u32);
                        }
                    }
                }
            });
        }
        d.finish(|e| sink(e.is_ok() as u32));
        sink(d.stats().bytes_discarded);

        // The bulk path, in opaque chunks, then a flush.
        let bulk: [u8; 512] = input();
        let total = len() % 513;
        let mut b = Decoder::<128>::new(profile);
        let mut at = 0;
        while at < total {
            let step = 1 + input_byte(at) as usize % 97;
            let end = if at + step < total { at + step } else { total };
            b.feed(bulk.get(at..end).unwrap_or(&[]), |e| {
                if let Ok(frame) = e {
                    sink(frame.base_type() as u32 ^ frame.data().len() as u32);
                    if let Ok(msg) = frame.message() {
                        sink(matches!(msg, Message::Heartbeat) as u32);
                    }
                }
            });
            at = end;
        }
        // Event by event (`next_event`) over the same bytes.
        let mut u = Decoder::<128>::new(profile);
        until_each(bulk.get(..total).unwrap_or(&[]), |rest| {
            let (n, ev) = u.next_event(rest);
            let found = ev.is_some();
            if let Some(Ok(frame)) = ev {
                sink(frame.base_type() as u32 ^ frame.data().len() as u32);
            }
            (n, found)
        });
        sink(u.stats().frames_ok);
        let mut small = Decoder::<4>::new(profile);
        small.feed(bulk.get(..total).unwrap_or(&[]), |e| sink(e.is_ok() as u32));
        b.finish(|e| sink(e.is_ok() as u32));
        sink(b.stats().bytes_discarded ^ small.stats().length_errors);

        // Typed parse of opaque data, every type, both forms.
        let data: [u8; 128] = input();
        let n = len() % 129;
        if let Ok(msg) = Message::parse(
            input_byte(22) & 0x7F,
            input_byte(23) & 1 == 1,
            &data[..n],
            profile,
        ) {
            let ts = Timestamp {
                seconds: input_byte(24) as i64,
                subsec: input_byte(25) as i64,
            };
            let mut out = [0u8; 200];
            let k = input_byte(26) as usize % 201;
            if let Ok(n) = enc.encode(&msg, Some(ts), &mut out[..k]) {
                sink(n as u32);
            }
            if let Ok(bytes) = enc.iter(&msg, Some(ts)) {
                for b in bytes {
                    sink(b as u32);
                }
            }
        }
        if let Ok(f) = Frame::new_checked(&data[..n], profile) {
            sink(f.checksum() as u32);
        }
        // Registry reply to request-data for an opaque address.
        let mut out = [0u8; 64];
        let k = input_byte(27) as usize % 65;
        let addr = u16::from_le_bytes([input_byte(28), input_byte(29)]);
        if let Ok(reply) = reg.read(addr, &mut out[..k]) {
            sink(reply.address as u32);
        }
        sink(uflt16::encode(f32::from_bits(len() as u32)) as u32);
    }
}

mod io {
    use super::*;
    use core::future::Future;
    use core::pin::pin;
    use core::task::{Context, Poll, Waker};
    use embedded_io::ErrorKind;

    /// Reads opaque chunks (0 bytes: EOF) of opaque bytes, fails when told to; writes take an
    /// opaque number of bytes (0 included) or fail.
    pub struct Opaque {
        at: usize,
    }

    impl Opaque {
        fn read_now(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
            let ctl = input_byte(self.at);
            self.at = self.at.wrapping_add(1);
            if ctl == 0xEE {
                return Err(ErrorKind::Other);
            }
            let n = (ctl as usize % 70).min(buf.len());
            for b in buf.iter_mut().take(n) {
                *b = input_byte(self.at);
                self.at = self.at.wrapping_add(1);
            }
            Ok(n)
        }
        fn write_now(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
            let ctl = input_byte(self.at);
            self.at = self.at.wrapping_add(1);
            if ctl == 0xEE {
                return Err(ErrorKind::Other);
            }
            for &b in buf.iter().take(ctl as usize) {
                sink(b as u32);
            }
            Ok((ctl as usize).min(buf.len()))
        }
    }

    impl embedded_io::ErrorType for Opaque {
        type Error = ErrorKind;
    }
    impl embedded_io::Read for Opaque {
        fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
            self.read_now(buf)
        }
    }
    impl embedded_io::Write for Opaque {
        fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
            self.write_now(buf)
        }
        fn flush(&mut self) -> Result<(), ErrorKind> {
            Ok(())
        }
    }
    impl embedded_io_async::Read for Opaque {
        async fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
            self.read_now(buf)
        }
    }
    impl embedded_io_async::Write for Opaque {
        async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
            self.write_now(buf)
        }
        async fn flush(&mut self) -> Result<(), ErrorKind> {
            Ok(())
        }
    }

    /// Polls once: the opaque transport never suspends, so one poll runs every await of the
    /// readers and writers to the end. Polling only once keeps out the panic every
    /// `async fn` state machine carries for being polled after it completed (an executor's
    /// contract, not a path in these crates), which LLVM cannot rule out across a poll loop.
    fn block_on<F: Future>(f: F) -> Option<F::Output> {
        let mut f = pin!(f);
        let mut cx = Context::from_waker(Waker::noop());
        match f.as_mut().poll(&mut cx) {
            Poll::Ready(v) => Some(v),
            Poll::Pending => None,
        }
    }

    fn opaque(at: usize) -> Opaque {
        Opaque { at }
    }

    pub fn run() {
        use aeolus_proto::{
            CrcMode, Decoder, IoError as AeolusIo, MAX_FIXED_FRAME, message::Message,
        };
        let rounds = len() % 64;

        // AEOLUS readers and writers.
        let mut r = aeolus_proto::embedded_io::FrameReader::<_, MAX_FIXED_FRAME, 48>::new(
            opaque(0),
            Decoder::new(),
        );
        let mut a = aeolus_proto::embedded_io_async::FrameReader::<_, 64, 7>::new(
            opaque(9),
            Decoder::new(),
        );
        let mut w = aeolus_proto::embedded_io::FrameWriter::new(opaque(17));
        for _ in 0..rounds {
            match r.read() {
                Ok(f) => {
                    if let Ok(m) = f.message() {
                        sink(w.write_message(&m, CrcMode::Compute).is_ok() as u32);
                    }
                }
                Err(AeolusIo::Eof) => break,
                Err(e) => sink(e.is_protocol() as u32),
            }
            if let Some(Ok(f)) = block_on(a.read()) {
                if let Ok(m) = Message::parse(f.id(), f.data()) {
                    sink(m.buffer_len() as u32);
                }
            }
        }
        sink(r.decoder().stats().frames_ok ^ a.decoder().stats().frames_ok);

        // AYDP readers and writers.
        use aydp_proto::{Profile, Raw, Timestamp};
        let profile = if input_byte(30) & 1 == 0 {
            Profile::Spec
        } else {
            Profile::Reference
        };
        let mut r = aydp_proto::embedded_io::FrameReader::<_, 128, 32>::new(
            opaque(31),
            aydp_proto::Decoder::new(profile),
        );
        let mut a = aydp_proto::embedded_io_async::FrameReader::<_, 40, 5>::new(
            opaque(37),
            aydp_proto::Decoder::new(profile),
        );
        let mut w = aydp_proto::embedded_io::FrameWriter::new(opaque(41), profile);
        for _ in 0..rounds {
            if let Ok(f) = r.read() {
                let raw = Raw {
                    msg_type: f.base_type(),
                    data: f.data(),
                };
                sink(w.write_expedited(&raw).is_ok() as u32);
                if let Ok(m) = f.message() {
                    let ts = Timestamp::new(len() as i64, 3);
                    sink(w.write_normal(&m, ts).is_ok() as u32);
                }
            }
            if let Some(Ok(f)) = block_on(a.read()) {
                sink(f.message().is_ok() as u32);
            }
        }
        sink(r.decoder().stats().frames_ok ^ a.decoder().stats().frames_ok);

        // AOK readers and writers.
        use aok_proto::{FirmwareVersion, ReplyForm, Expect};
        let fw = FirmwareVersion::new(input_byte(44), input_byte(45));
        let mut m = aok_proto::embedded_io::MessageReader::<_, 16>::new(
            opaque(47),
            aok_proto::MessageDecoder::new(fw),
        );
        let mut c = aok_proto::embedded_io_async::CommandReader::<_, 3>::new(
            opaque(53),
            aok_proto::CommandDecoder::new(),
        );
        let mut w = aok_proto::embedded_io::Writer::new(opaque(59));
        let mut aw = aok_proto::embedded_io_async::Writer::new(opaque(61));
        for i in 0..rounds {
            if input_byte(i) == 0x55 {
                m.decoder_mut().expect(Expect::Parameter(input_byte(i + 1)));
            }
            if let Ok(msg) = m.read() {
                sink(w.write_message(&msg, ReplyForm::Headerless).is_ok() as u32);
            }
            if let Some(Ok(cmd)) = block_on(c.read()) {
                sink(matches!(block_on(aw.write_command(&cmd)), Some(Ok(_))) as u32);
                sink(w.write_command(&cmd).is_ok() as u32);
            }
        }
    }
}

mod gdl90 {
    use super::*;
    use gdl90_proto::{message::*, *};

    fn use_message(msg: &Message<'_>) {
        sink(msg.buffer_len() as u32 ^ msg.id() as u32);
        let mut out = [0u8; MAX_ENCODED_LEN];
        let k = input_byte(30) as usize % (out.len() + 1);
        if let Ok(n) = msg.encode(&mut out[..k]) {
            sink(n as u32);
        }
    }

    pub fn run() {
        // The decoder, byte by byte, at the typed capacity and a tiny one.
        let mut d = Decoder::<{ TYPED_FRAME }>::new();
        let mut small = Decoder::<4>::new();
        for i in 0..len() {
            let b = input_byte(i);
            d.feed(&[b], |ev| {
                if let Ok(msg) = ev {
                    use_message(&msg);
                }
            });
            small.feed(&[b], |ev| { sink(ev.is_ok() as u32); });
        }
        sink(d.stats().bytes_discarded ^ small.stats().overflows);

        // The slice path, in opaque chunks.
        let bulk: [u8; 512] = input();
        let total = len() % 513;
        let mut b = Decoder::<{ TYPED_FRAME }>::new();
        let mut at = 0;
        while at < total {
            let step = 1 + input_byte(at) as usize % 53;
            let end = if at + step < total { at + step } else { total };
            b.feed(bulk.get(at..end).unwrap_or(&[]), |ev| {
                if let Ok(msg) = ev {
                    use_message(&msg);
                }
            });
            at = end;
        }
        sink(b.stats().frames_ok ^ b.held_bytes() as u32);

        // Every typed parse on opaque data; emit and encode what parsed.
        let data: [u8; 64] = input();
        let dl = len() % 65;
        if let Ok(msg) = Message::parse(input_byte(31), &data[..dl]) {
            use_message(&msg);
            let mut raw = [0u8; 64];
            let k = input_byte(32) as usize % 65;
            if let Ok(n) = msg.emit(&mut raw[..k]) {
                sink(n as u32);
            }
        }

        // The encoders with opaque values and output sizes.
        let f = |i: usize| {
            f32::from_bits(u32::from_le_bytes([
                input_byte(i),
                input_byte(i + 1),
                input_byte(i + 2),
                input_byte(i + 3),
            ]))
        };
        let w = |i: usize| u16::from_le_bytes([input_byte(i), input_byte(i + 1)]);
        let mut out = [0u8; MAX_ENCODED_LEN];
        let k = input_byte(33) as usize % (MAX_ENCODED_LEN + 1);
        let hb = Heartbeat {
            utc_ok: input_byte(34) & 1 == 1,
            seconds_since_midnight: f(35).to_bits(),
            uplink_messages: input_byte(39),
            basic_long_messages: w(40),
            ..Heartbeat::default()
        };
        if let Ok(n) = Message::Heartbeat(hb).encode(&mut out[..k]) {
            sink(n as u32);
        }
        let report = Report {
            address: f(42).to_bits(),
            position: Some(LatLon {
                lat_deg: f(46) as f64 * 1e30,
                lon_deg: f(50) as f64,
            }),
            pressure_altitude_ft: Some(f(54).to_bits() as i32),
            track: Some(Track::MagneticHeading(f(58))),
            nic: input_byte(62),
            ground_speed_kt: Some(w(63)),
            vertical_rate_fpm: Some(f(65).to_bits() as i32),
            address_type: AddressType::from_nibble(input_byte(69)),
            emergency: Emergency::from_nibble(input_byte(70)),
            ..Report::default()
        };
        if let Ok(n) = Message::Ownship(report).encode(&mut out[..k]) {
            sink(n as u32);
        }
        if let Ok(n) = Message::Traffic(report).encode(&mut out[..k]) {
            sink(n as u32);
        }
        let alt = GeoAltitude {
            altitude_ft: f(71).to_bits() as i32,
            vertical_warning: true,
            vfom_m: Some(w(75)),
        };
        if let Ok(n) = Message::GeoAltitude(alt).encode(&mut out[..k]) {
            sink(n as u32);
        }
        let id = ForeFlightId {
            serial: Some(f(77).to_bits() as u64),
            ..ForeFlightId::default()
        };
        if let Ok(n) = Message::ForeFlightId(id).encode(&mut out[..k]) {
            sink(n as u32);
        }
        let ahrs = Ahrs {
            roll_deg: Some(f(81)),
            pitch_deg: Some(f(85)),
            heading: Some(Heading::Magnetic(f(89))),
            indicated_airspeed_kt: Some(w(93)),
            true_airspeed_kt: None,
        };
        if let Ok(n) = Message::Ahrs(ahrs).encode(&mut out[..k]) {
            sink(n as u32);
        }
        if let Ok(n) = encode_frame(input_byte(95), &data[..dl], &mut out[..k]) {
            sink(n as u32);
        }
        if let Some(cs) = CallSign::new(core::str::from_utf8(&data[..dl % 9]).unwrap_or("")) {
            sink(cs.as_str().map_or(0, str::len) as u32);
        }
    }
}

#[unsafe(no_mangle)]
pub extern "C" fn entry() -> ! {
    aydp::run();
    aeolus::run();
    aok::run();
    io::run();
    gdl90::run();
    loop {
        core::hint::spin_loop();
    }
}
