//! The links' per-frame entry points (`handle_frame`, `poll_tx`, `App::service_requests`), used
//! by boards whose own readers deframe (`firmware-embassy`), do exactly what `poll` does: the
//! same stream, fed byte by byte to `poll` or deframed by the caller and handed over frame by
//! frame, gives the same bytes on the wire, the same counters and the same shared state.

use aeolus_proto::message::{Message, SetTime, Text};
use aeolus_proto::{CrcMode, Decode};
use aydp_proto::{
    Decoder, Encoder, Payload, Profile, SystemControl, SystemValueUpdate, Timestamp, UpdateMode,
};
use sensor_box::aeolus_link::{AeolusLink, RX_FRAME};
use sensor_box::aydp_link::{AydpLink, DECODER_CAPACITY, addr};
use sensor_box::serial::Ring;
use sensor_box::serial::{PortStats, QueuedSerial, SerialIsr};
use sensor_box::storage::MemFlash;
use sensor_box::{App, Control, Persisted, Shared};

fn port() -> (
    QueuedSerial<'static, 4096, 16384>,
    SerialIsr<'static, 4096, 16384>,
) {
    let rx: &'static mut Ring<4096> = Box::leak(Box::new(Ring::new()));
    let tx: &'static mut Ring<16384> = Box::leak(Box::new(Ring::new()));
    let stats: &'static PortStats = Box::leak(Box::new(PortStats::new()));
    QueuedSerial::split(rx, tx, stats, || {})
}

fn sent<const RX: usize, const TX: usize>(isr: &mut SerialIsr<'_, RX, TX>) -> Vec<u8> {
    std::iter::from_fn(|| isr.next_to_send()).collect()
}

fn aeolus(msg: &Message<'_>, crc: CrcMode) -> Vec<u8> {
    let mut buf = [0u8; 600];
    let n = msg.encode(&mut buf, crc).expect("encodes");
    buf[..n].to_vec()
}

/// COMMANDs (known, unknown, padded), a SETTIME in range and one out of range, a frame with a
/// bad CRC, noise, a TOAST (ignored) and a frame without CRC.
fn aeolus_stream() -> Vec<u8> {
    let time = SetTime {
        year_since_1900: 124,
        month0: 2,
        day: 1,
        hour: 12,
        minute: 0,
        second: 0,
    };
    let mut s = Vec::new();
    s.extend(aeolus(
        &Message::Command(Text::new("a pause").unwrap()),
        CrcMode::Compute,
    ));
    s.extend([0x00, 0x13, 0x7D]);
    let mut bad = aeolus(
        &Message::Command(Text::new("a resume").unwrap()),
        CrcMode::Compute,
    );
    let at = bad.len() - 2;
    bad[at] ^= 0x01;
    s.extend(bad);
    s.extend(aeolus(&Message::SetTime(time), CrcMode::Compute));
    s.extend(aeolus(
        &Message::SetTime(SetTime { month0: 12, ..time }),
        CrcMode::Compute,
    ));
    s.extend(aeolus(
        &Message::Command(Text::new("  what now ").unwrap()),
        CrcMode::Omit,
    ));
    s.extend(aeolus(
        &Message::Toast(Text::new("hello").unwrap()),
        CrcMode::Compute,
    ));
    s.extend(aeolus(
        &Message::Command(Text::new("a resume").unwrap()),
        CrcMode::Compute,
    ));
    // Landed again, so that the reboot is obeyed (it is refused in flight).
    s.extend(aeolus(
        &Message::Command(Text::new("a pause").unwrap()),
        CrcMode::Compute,
    ));
    s.extend(aeolus(
        &Message::Command(Text::new("a reboot").unwrap()),
        CrcMode::Compute,
    ));
    s
}

#[test]
fn aeolus_frame_by_frame_equals_poll() {
    let stream = aeolus_stream();
    let mut flash_mem = [0xFFu8; 8192];
    let mut flash = MemFlash::new(&mut flash_mem);

    // Byte by byte through poll.
    let (mut a_port, mut a_isr) = port();
    let mut a_shared = Shared::new(Persisted::default(), 0);
    let mut a = AeolusLink::new(0);
    for &b in &stream {
        a_isr.received(b);
    }
    a.poll(3, &mut a_port, &mut a_shared);
    a.poll(10, &mut a_port, &mut a_shared);

    // Decoded by the caller, frame by frame, then the TX half.
    let (mut b_port, mut b_isr) = port();
    let mut b_shared = Shared::new(Persisted::default(), 0);
    let mut b = AeolusLink::new(0);
    let mut decoder = aeolus_proto::Decoder::<RX_FRAME>::new();
    for byte in &stream {
        decoder.feed(core::slice::from_ref(byte), |frame| {
            b.handle_frame(frame.as_ref().map_err(|e| *e), 3, &mut b_shared);
        });
    }
    b.poll_tx(3, &mut b_port, &b_shared);
    b.poll_tx(10, &mut b_port, &b_shared);

    assert_eq!(sent(&mut a_isr), sent(&mut b_isr));
    assert_eq!(a.counters(), b.counters());
    assert_eq!(a.rx_stats(), decoder.stats());
    assert_eq!(a_shared.paused, b_shared.paused);
    assert_eq!(a_shared.wall_clock, b_shared.wall_clock);
    assert!(a_shared.wall_clock.is_some());
    assert!(a.counters().rx_errors >= 1); // the bad CRC (and the noise)
    assert_eq!(a.counters().unknown_commands, 1);
    assert_eq!(a.counters().settime_rejected, 1);
    assert_eq!(a_shared.requests.reboot, b_shared.requests.reboot);
    assert!(a_shared.requests.reboot);

    // The reboot request is served the same way by both paths' App.
    let mut app = App::new(&mut flash, 0);
    app.shared.requests.reboot = b_shared.requests.reboot;
    assert_eq!(app.service_requests(&mut flash), Control::Reboot);
}

fn aydp(payload: &(impl Payload + ?Sized), ts: Option<Timestamp>) -> Vec<u8> {
    Encoder::new(Profile::Spec)
        .iter(payload, ts)
        .expect("encodes")
        .collect()
}

/// Requests (expedited and normal), updates accepted and rejected, a store configuration, a
/// request for an unknown address and a bad checksum. No request for 0x0300: the decoder
/// counters it reports are taken at different instants on the two paths (documented).
fn aydp_stream() -> Vec<u8> {
    let ts = Some(Timestamp::new(100, 5));
    let airspeed = 62.5f32.to_le_bytes();
    let mut s = Vec::new();
    s.extend(aydp(
        &SystemControl::RequestData {
            address: addr::SYSTEM_NAME,
        },
        None,
    ));
    s.extend(aydp(
        &SystemValueUpdate {
            address: addr::AIRSPEED,
            mode: UpdateMode::Single,
            data: &airspeed,
        },
        ts,
    ));
    s.extend(aydp(
        &SystemControl::RequestData {
            address: addr::AIRSPEED,
        },
        ts,
    ));
    s.extend(aydp(
        &SystemValueUpdate {
            address: addr::SYSTEM_NAME,
            mode: UpdateMode::Single,
            data: &[1],
        },
        None,
    ));
    s.extend(aydp(&SystemControl::RequestData { address: 0x7777 }, None));
    let mut bad = aydp(&SystemControl::StoreConfiguration, None);
    let last = bad.len() - 1;
    bad[last] ^= 0x55;
    s.extend(bad);
    s.extend(aydp(&SystemControl::StoreConfiguration, None));
    s
}

#[test]
fn aydp_frame_by_frame_equals_poll() {
    let stream = aydp_stream();

    let (mut a_port, mut a_isr) = port();
    let mut a_shared = Shared::new(Persisted::default(), 0);
    let mut a = AydpLink::new(0);
    for &b in &stream {
        a_isr.received(b);
    }
    a.poll(2, &mut a_port, &mut a_shared);
    a.poll(1500, &mut a_port, &mut a_shared);

    let (mut b_port, mut b_isr) = port();
    let mut b_shared = Shared::new(Persisted::default(), 0);
    let mut b = AydpLink::new(0);
    let mut decoder = Decoder::<DECODER_CAPACITY>::new(Profile::Spec);
    for &byte in &stream {
        let stats = decoder.stats();
        decoder.feed(&[byte], |ev| {
            b.handle_frame(
                ev.as_ref().map_err(|e| *e),
                &stats,
                2,
                &mut b_port,
                &mut b_shared,
            );
        });
    }
    b.poll_tx(2, &mut b_port, &b_shared);
    b.poll_tx(1500, &mut b_port, &b_shared);

    let a_wire = sent(&mut a_isr);
    assert_eq!(a_wire, sent(&mut b_isr));
    // Two answers, then heartbeat, position and fix quality at boot and a second later.
    assert_eq!(messages(&a_wire), 2 + 3 + 3);
    assert_eq!(a.counters(), b.counters());
    assert_eq!(a.decoder_stats(), decoder.stats());
    assert_eq!(a_shared.settings(), b_shared.settings());
    assert_eq!(a_shared.settings().airspeed_mps, 62.5);
    // Flying: the store configuration was refused by both, and counted.
    assert!(!a_shared.requests.store && !b_shared.requests.store);
    assert_eq!(a_shared.counters, b_shared.counters);
    assert_eq!(a_shared.counters.stores_refused_in_flight, 1);
    assert_eq!(a.counters().requests_answered, 2);
    assert_eq!(a.counters().rejected, 2);
}

/// How many messages a wire holds (all must be good).
fn messages(wire: &[u8]) -> usize {
    let mut d = Decoder::<256>::new(Profile::Spec);
    let mut n = 0;
    d.feed(wire, |ev| {
        assert!(ev.is_ok(), "the box sends good messages");
        n += 1;
    });
    n
}
