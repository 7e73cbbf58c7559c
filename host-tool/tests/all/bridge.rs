//! `protolink bridge` end to end: a fake UART (a loopback TCP server in the test) sends AEOLUS
//! frames among noise and a corrupted frame; a plain UDP socket receives the datagrams; a UDP
//! datagram sent to the in-port must come out of the UART.

use std::io::{Read, Write};
use std::net::UdpSocket;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::common::*;
use aeolus_proto::decode_datagram;

/// The good frames of the vector file, in order, and a stream that carries them among noise and
/// a corrupted frame.
fn uart_stream() -> (Vec<Vec<u8>>, Vec<u8>) {
    let mut good = Vec::new();
    let mut stream = vec![0x00, 0x55];
    for v in vectors("aeolus") {
        let bytes = vector_bytes(&v);
        stream.extend(&bytes);
        match v["name"].as_str().unwrap() {
            "bad-crc" => {}
            "datagram-two-messages" => {
                // Two frames: split at the flag pair.
                let split = bytes.windows(2).position(|w| w == [0x7e, 0x7e]).unwrap() + 1;
                good.push(bytes[..split].to_vec());
                good.push(bytes[split..].to_vec());
            }
            _ => good.push(bytes),
        }
        stream.extend([0x13, 0x37]);
    }
    (good, stream)
}

struct Run {
    datagrams: Vec<Vec<u8>>,
    to_uart: Vec<u8>,
    stdout: String,
}

/// Runs the bridge for `seconds` against a fake UART that sends `stream` once, while the test
/// sends `inbound` to the in-port until it comes out of the UART.
fn bridge(extra: &[&str], stream: Vec<u8>, inbound: &[u8]) -> Run {
    let (uart, uart_ep) = listener();
    let receiver = UdpSocket::bind("127.0.0.1:0").unwrap();
    receiver
        .set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    let out_port = receiver.local_addr().unwrap().port();
    let in_port = free_udp_port();
    let (got_tx, got_rx) = mpsc::channel::<Vec<u8>>();
    let uart_thread = std::thread::spawn(move || {
        let Some(mut s) = accept(&uart) else {
            return Vec::new();
        };
        s.write_all(&stream).unwrap();
        s.set_read_timeout(Some(Duration::from_millis(50))).unwrap();
        let mut received = Vec::new();
        let mut buf = [0u8; 256];
        loop {
            match s.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    received.extend(&buf[..n]);
                    let _ = got_tx.send(buf[..n].to_vec());
                }
                Err(e)
                    if e.kind() == std::io::ErrorKind::WouldBlock
                        || e.kind() == std::io::ErrorKind::TimedOut => {}
                Err(_) => break,
            }
        }
        received
    });
    let out = format!("127.0.0.1:{out_port}");
    let inp = in_port.to_string();
    let mut args = vec![
        "bridge",
        "--uart",
        uart_ep.as_str(),
        "--udp-out",
        out.as_str(),
        "--udp-in",
        inp.as_str(),
    ];
    args.extend_from_slice(extra);
    let child = spawn(&args);
    let mut datagrams = Vec::new();
    let sender = UdpSocket::bind("127.0.0.1:0").unwrap();
    let mut delivered = inbound.is_empty();
    let started = Instant::now();
    let mut buf = vec![0u8; 65_536];
    // Until the bridge stops by itself (--seconds): collect datagrams, and knock on the in-port
    // until the inbound datagram has reached the UART.
    while started.elapsed() < Duration::from_secs(30) {
        if !delivered {
            sender.send_to(inbound, ("127.0.0.1", in_port)).unwrap();
            if got_rx.recv_timeout(Duration::from_millis(50)).is_ok() {
                delivered = true;
            }
        }
        match receiver.recv_from(&mut buf) {
            Ok((n, _)) => datagrams.push(buf[..n].to_vec()),
            Err(_) if delivered && !datagrams.is_empty() => break,
            Err(_) => {}
        }
    }
    let output = finish(child);
    while let Ok((n, _)) = receiver.recv_from(&mut buf) {
        datagrams.push(buf[..n].to_vec());
    }
    let to_uart = uart_thread.join().unwrap();
    Run {
        datagrams,
        to_uart,
        stdout: ok(&output),
    }
}

#[test]
fn every_good_frame_becomes_one_datagram_byte_for_byte() {
    let (good, stream) = uart_stream();
    let run = bridge(&["--seconds", "2"], stream, &[]);
    assert_eq!(run.datagrams, good);
    for d in &run.datagrams {
        let mut d = d.clone();
        let frames: Vec<_> = decode_datagram(&mut d, false).collect();
        assert_eq!(frames.len(), 1);
        assert!(frames[0].is_ok());
    }
    assert!(
        run.stdout.contains(&format!(
            "frames_forwarded={} datagrams_sent={}",
            good.len(),
            good.len()
        )),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("checksum_errors=1"), "{}", run.stdout);
}

#[test]
fn pack_puts_up_to_n_frames_in_a_datagram() {
    let (good, stream) = uart_stream();
    let run = bridge(&["--pack", "3", "--seconds", "2"], stream, &[]);
    let mut frames = Vec::new();
    for d in &run.datagrams {
        let mut d = d.clone();
        let ids: Vec<_> = decode_datagram(&mut d, false)
            .map(|f| f.map(|f| f.id()))
            .collect();
        assert!(!ids.is_empty() && ids.len() <= 3, "{ids:?}");
        frames.extend(ids.into_iter().map(Result::unwrap));
    }
    let want: Vec<u8> = good
        .iter()
        .map(|f| if f[1] == 0x7d { f[2] ^ 0x20 } else { f[1] })
        .collect();
    assert_eq!(frames, want);
    // The whole stream arrived at once, so the frames were packed three by three.
    assert!(
        run.datagrams.len() < good.len(),
        "{} datagrams",
        run.datagrams.len()
    );
    // A datagram is the frames one after the other (7E 7E between them).
    assert_eq!(run.datagrams.concat(), good.concat());
}

#[test]
fn datagrams_from_the_in_port_reach_the_uart() {
    // "a pause" as a COMMAND (ID 11), as an app would send it.
    let mut command = vec![0u8; 32];
    let n = aeolus_proto::message::Message::Command(
        aeolus_proto::message::Text::new("a pause").unwrap(),
    )
    .encode(&mut command, aeolus_proto::CrcMode::Compute)
    .unwrap();
    command.truncate(n);
    let (_, stream) = uart_stream();
    let run = bridge(&["--seconds", "3"], stream, &command);
    assert!(!run.to_uart.is_empty());
    // Whole datagrams, unchanged (it may have been knocked in more than once).
    assert_eq!(run.to_uart.len() % command.len(), 0);
    assert!(run.to_uart.chunks(command.len()).all(|c| c == command));
    let received = run.to_uart.len() / command.len();
    assert!(
        run.stdout.contains(&format!(
            "datagrams_received={received} bytes_to_uart={}",
            run.to_uart.len()
        )),
        "{}",
        run.stdout
    );
}

#[test]
fn a_file_uart_ends_the_bridge_by_itself() {
    let (good, stream) = uart_stream();
    let file = TempFile::new("uart", &stream);
    let receiver = UdpSocket::bind("127.0.0.1:0").unwrap();
    let port = receiver.local_addr().unwrap().port().to_string();
    let in_port = free_udp_port().to_string();
    let out = run(&[
        "bridge",
        "--uart",
        &file.endpoint(),
        "--udp-out",
        &port,
        "--udp-in",
        &in_port,
    ]);
    let text = ok(&out);
    assert!(
        text.contains(&format!("uart_bytes={}", stream.len())),
        "{text}"
    );
    assert!(
        text.contains(&format!("frames_forwarded={}", good.len())),
        "{text}"
    );
}
