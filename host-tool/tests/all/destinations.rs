//! Where the commands that send datagrams send them: a run that had datagrams to send and got
//! not one out fails (status 1, one sentence), and an IPv6 destination works as an IPv4 one.
//! Every run here sends to loopback only.

use std::borrow::Cow;
use std::net::UdpSocket;
use std::process::Output;
use std::time::{Duration, Instant};

use crate::common::*;
use pcap_file::DataLink;
use pcap_file::pcap::{PcapHeader, PcapPacket, PcapWriter};
use protolink::capture::ethernet_udp;

/// TOAST "hi" with a good CRC: one frame for `bridge` to forward and `replay` to send.
const TOAST: [u8; 8] = [0x7E, 0x52, b'h', b'i', 0, 0x73, 0xEC, 0x7E];

/// A classic pcap holding [`TOAST`] as one UDP payload, for `replay`.
fn capture() -> TempFile {
    let mut bytes = Vec::new();
    let mut w = PcapWriter::with_header(
        &mut bytes,
        PcapHeader {
            datalink: DataLink::ETHERNET,
            ..Default::default()
        },
    )
    .expect("pcap header");
    let frame = ethernet_udp(
        "127.0.0.1:40000".parse().expect("addr"),
        "127.0.0.1:5001".parse().expect("addr"),
        &TOAST,
    );
    w.write_packet(&PcapPacket {
        timestamp: Duration::from_secs(1_700_000_000),
        orig_len: frame.len() as u32,
        data: Cow::Borrowed(&frame),
    })
    .expect("pcap packet");
    let _ = w.into_writer();
    TempFile::new("destinations.pcap", &bytes)
}

/// The commands that send, each sending to `to` (`ADDR:PORT`) for about half a second; the
/// files they read live as long as the returned list.
fn senders(to: &str) -> (Vec<(&'static str, Vec<String>)>, [TempFile; 2]) {
    let uart = TempFile::new("destinations.uart", &TOAST);
    let pcap = capture();
    let args = |a: &[&str]| a.iter().map(|s| (*s).to_owned()).collect::<Vec<_>>();
    let udp = format!("udp:{to}");
    let list = vec![
        (
            "sim",
            args(&["sim", "--udp-out", to, "--udp-in", "0", "--seconds", "0.5"]),
        ),
        (
            "gdl90",
            args(&["gdl90", "--from", "udp:0", "--to", to, "--seconds", "0.5"]),
        ),
        (
            "nmea",
            args(&["nmea", "--from", "udp:0", "--to", to, "--seconds", "1.1"]),
        ),
        (
            "bridge",
            args(&[
                "bridge",
                "--uart",
                &uart.endpoint(),
                "--udp-out",
                to,
                "--udp-in",
                "0",
                "--seconds",
                "5",
            ]),
        ),
        (
            "replay",
            args(&["replay", &pcap.0.display().to_string(), "--to", &udp]),
        ),
        (
            "aeolus",
            args(&["aeolus", "--to", &udp, "command", "a pause"]),
        ),
    ];
    (list, [uart, pcap])
}

fn run_owned(args: &[String]) -> Output {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    run(&args)
}

/// Port 0 on 127.0.0.1 takes no datagram: every send fails, and every command says so with
/// status 1 and one sentence naming the destination and the reason, never status 0 with a
/// count of errors. (`nmea --to` refuses port 0 on the command line: status 2, with the
/// reason.) `aok` and `aydp` answer on a UDP endpoint's last sender: with none, they fail too.
#[test]
fn every_command_that_sends_fails_when_not_one_datagram_went_out() {
    let (list, _files) = senders("127.0.0.1:0");
    for (name, args) in &list {
        let out = run_owned(args);
        if *name == "nmea" {
            let err = usage_failed(&out);
            assert!(err.contains("port 0"), "{name}: {err}");
            continue;
        }
        let err = failed(&out);
        assert!(err.contains("127.0.0.1:0"), "{name}: {err}");
        assert_eq!(
            err.lines().filter(|l| l.starts_with("error: ")).count(),
            1,
            "{name}: {err}"
        );
    }
    // nmea's own rule: datagrams to a broadcast address are refused by the system unless
    // asked for, so every send fails (nothing leaves the machine).
    let err = failed(&run(&[
        "nmea",
        "--from",
        "udp:0",
        "--to",
        "255.255.255.255:4353",
        "--seconds",
        "1.1",
    ]));
    assert!(err.contains("sending every one of"), "{err}");
    for cmd in [
        &["aok", "--to", "udp:127.0.0.1:0", "get", "1"][..],
        &["aydp", "--to", "udp:127.0.0.1:0", "get", "0x0110"],
    ] {
        let err = failed(&run(cmd));
        assert!(
            err.contains("no datagram has arrived yet"),
            "{cmd:?}: {err}"
        );
    }
}

/// Datagrams that arrive at `socket` until `child` ends, then for 200 ms more.
fn received_while(socket: &UdpSocket, child: std::process::Child) -> (Output, usize) {
    socket
        .set_read_timeout(Some(Duration::from_millis(20)))
        .expect("timeout");
    let mut buf = vec![0u8; 65_536];
    let mut n = 0;
    let mut child = Some(child);
    let mut out = None;
    let mut ended = None::<Instant>;
    loop {
        if socket.recv(&mut buf).is_ok() {
            n += 1;
            continue;
        }
        if let Some(c) = child.as_mut()
            && c.try_wait().expect("wait").is_some()
        {
            out = Some(finish(child.take().expect("child")));
            ended = Some(Instant::now());
        }
        if ended.is_some_and(|t| t.elapsed() > Duration::from_millis(200)) {
            break;
        }
    }
    (out.expect("the run ended"), n)
}

/// An IPv6 destination (`[::1]:PORT`) works wherever an IPv4 one does: the sender's socket is
/// of the destination's family. Skipped, and said so, where the system has no IPv6 loopback
/// (a failure under `CI`).
#[test]
fn every_command_that_sends_reaches_an_ipv6_destination() {
    let Ok(socket) = UdpSocket::bind("[::1]:0") else {
        // CI has one: there, a missing loopback is a failure, not a skip.
        assert!(
            std::env::var_os("CI").is_none(),
            "CI=true and no IPv6 loopback ([::1] cannot be bound)"
        );
        eprintln!("no IPv6 loopback here ([::1] cannot be bound): IPv6 destinations not tested");
        return;
    };
    let to = socket.local_addr().expect("addr").to_string();
    let (list, _files) = senders(&to);
    for (name, args) in &list {
        let (out, n) = received_while(
            &socket,
            spawn(&args.iter().map(String::as_str).collect::<Vec<_>>()),
        );
        ok(&out);
        assert!(
            n > 0,
            "{name}: no datagram reached {to}; stderr:\n{}",
            stderr(&out)
        );
    }
}
