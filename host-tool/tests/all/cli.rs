//! The command line's contract: an example in every `--help`, one-sentence errors with a
//! non-zero exit, the endpoint syntax, and no field broadcast address anywhere by default.

use crate::common::*;
use protolink::endpoint::{Endpoint, parse_local_addr};

const SUBCOMMANDS: &[&[&str]] = &[
    &["decode"],
    &["bridge"],
    &["aydp"],
    &["aydp", "get"],
    &["aydp", "set"],
    &["aydp", "store"],
    &["aydp", "output"],
    &["aok"],
    &["aok", "debug"],
    &["aok", "get"],
    &["aok", "set"],
    &["aok", "bulk"],
    &["aok", "waypoint", "get"],
    &["aok", "waypoint", "set"],
    &["aok", "motor"],
    &["aok", "extern"],
    &["aok", "save-set"],
    &["aok", "load-set"],
    &["aok", "reset"],
    &["watch"],
    &["sim"],
];

#[test]
fn every_subcommand_help_has_an_example() {
    for sub in SUBCOMMANDS {
        let mut args = sub.to_vec();
        args.push("--help");
        let text = ok(&run(&args));
        assert!(
            text.contains("Example"),
            "{sub:?} --help has no example:\n{text}"
        );
        assert!(text.contains("protolink "), "{sub:?}");
    }
    let top = ok(&run(&["--help"]));
    for word in [
        "decode",
        "bridge",
        "aydp",
        "aok",
        "watch",
        "sim",
        "serial:/dev/ttyUSB0@921600",
        "udp:5001",
    ] {
        assert!(top.contains(word), "{word} missing from the top-level help");
    }
}

#[test]
fn bad_endpoints_are_refused_with_the_syntax() {
    let out = run(&["decode", "--proto", "aeolus", "--from", "http://box"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("invalid endpoint 'http://box': unknown kind 'http'"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
    let out = run(&["decode", "--proto", "aeolus", "--from", "tcp:127.0.0.1"]);
    assert!(
        stderr(&out).contains("invalid endpoint 'tcp:127.0.0.1': expected tcp:HOST:PORT"),
        "{}",
        stderr(&out)
    );
    let out = run(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        "tcp:127.0.0.1:http",
    ]);
    assert!(
        stderr(&out).contains("'http' is not a port"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn runtime_errors_are_one_sentence_and_exit_one() {
    let out = run(&[
        "decode",
        "--proto",
        "aok",
        "--from",
        "file:/nonexistent/x.bin",
    ]);
    let err = failed(&out);
    assert!(
        err.starts_with("error: cannot open file:/nonexistent/x.bin: No such file or directory"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
    let out = run(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        "serial:/dev/protolink-missing@9600",
    ]);
    assert!(failed(&out).starts_with("error: cannot open serial:/dev/protolink-missing@9600: "));
    // A write to a read-only endpoint.
    let file = TempFile::new("ro", b"");
    let out = run(&["aydp", "--to", &file.endpoint(), "get", "1"]);
    assert!(failed(&out).contains("is read-only: a file endpoint cannot receive bytes"));
}

#[test]
fn endpoint_syntax() {
    let parse = |s: &str| s.parse::<Endpoint>();
    assert_eq!(parse("-").unwrap(), Endpoint::Stdio);
    assert_eq!(
        parse("serial:/dev/ttyUSB0@921600").unwrap(),
        Endpoint::Serial {
            path: "/dev/ttyUSB0".into(),
            baud: 921_600
        }
    );
    assert_eq!(
        parse("serial:/dev/ttyACM0").unwrap(),
        Endpoint::Serial {
            path: "/dev/ttyACM0".into(),
            baud: 115_200
        }
    );
    assert_eq!(
        parse("tcp:127.0.0.1:7000").unwrap(),
        Endpoint::Tcp("127.0.0.1:7000".into())
    );
    assert_eq!(
        parse("tcp:localhost:7000").unwrap(),
        Endpoint::Tcp("localhost:7000".into())
    );
    assert_eq!(
        parse("udp:5001").unwrap(),
        Endpoint::Udp("127.0.0.1:5001".parse().unwrap())
    );
    assert_eq!(
        parse("udp:0.0.0.0:5001").unwrap(),
        Endpoint::Udp("0.0.0.0:5001".parse().unwrap())
    );
    assert_eq!(
        parse("file:a/b.bin").unwrap(),
        Endpoint::File("a/b.bin".into())
    );
    // A bare path is a file (a newcomer's `--from capture.bin`).
    assert_eq!(parse("x").unwrap(), Endpoint::File("x".into()));
    for bad in [
        "",
        "serial:",
        "serial:/dev/x@",
        "serial:/dev/x@0",
        "serial:/dev/x@fast",
        "tcp:",
        "tcp:host",
        "tcp::7000",
        "tcp:h:70000",
        "udp:",
        "udp:65536",
        "udp:host:1",
        "file:",
        "ftp:x",
    ] {
        assert!(parse(bad).is_err(), "'{bad}' was accepted");
    }
    // Display gives back a parseable endpoint.
    for good in [
        "-",
        "serial:/dev/ttyUSB0@921600",
        "tcp:127.0.0.1:7000",
        "udp:127.0.0.1:5001",
        "file:x.bin",
    ] {
        let e = parse(good).unwrap();
        assert_eq!(e.to_string(), good);
        assert_eq!(parse(&e.to_string()).unwrap(), e);
    }
    assert_eq!(
        parse_local_addr("5002").unwrap().to_string(),
        "127.0.0.1:5002"
    );
}

#[test]
fn no_field_address_is_a_default_anywhere() {
    // DECISIONS.md A9: no code sends to a 192.168.x.x address by default.
    let mut dirs = vec![std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/src"
    ))];
    let mut files = 0;
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
                continue;
            }
            files += 1;
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(
                !text.contains("192.168"),
                "{} mentions a 192.168 address",
                path.display()
            );
        }
    }
    assert!(files > 10, "{files} source files read");
    let help = ok(&run(&["bridge", "--help"]));
    assert!(help.contains("[default: 127.0.0.1:5001]"), "{help}");
    let broadcast = help.lines().find(|l| l.contains("--broadcast")).unwrap();
    assert!(!broadcast.contains("[default"), "{broadcast}");
}

#[test]
fn a_closed_output_pipe_is_not_an_error() {
    use std::io::Read;
    let noise = random_bytes(7, 1 << 20);
    let file = TempFile::new("pipe", &noise);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_protolink"))
        .args(["decode", "--proto", "aeolus", "--from", &file.endpoint()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Read one line's worth, then hang up, like `| head -1`.
    let mut stdout = child.stdout.take().unwrap();
    let mut first = [0u8; 16];
    stdout.read_exact(&mut first).unwrap();
    drop(stdout);
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_udp_endpoint_answers_the_last_sender() {
    use protolink::endpoint::Input;
    use std::net::UdpSocket;
    use std::time::Duration;
    let port = free_udp_port();
    let mut link = format!("udp:{port}")
        .parse::<Endpoint>()
        .unwrap()
        .open()
        .unwrap();
    // Nobody has spoken yet: nowhere to send.
    let err = link.write_all(b"x").unwrap_err().to_string();
    assert!(err.contains("no datagram has arrived yet"), "{err}");
    let peer = UdpSocket::bind("127.0.0.1:0").unwrap();
    peer.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    peer.send_to(b"hello", ("127.0.0.1", port)).unwrap();
    let mut buf = [0u8; 64];
    assert_eq!(
        link.read(&mut buf, Duration::from_secs(5)).unwrap(),
        Input::Data(5)
    );
    assert_eq!(&buf[..5], b"hello");
    link.write_all(b"back").unwrap();
    let (n, _) = peer.recv_from(&mut buf).unwrap();
    assert_eq!(&buf[..n], b"back");
    // The binary reports the same as one sentence.
    let out = run(&[
        "aydp",
        "--to",
        &format!("udp:{}", free_udp_port()),
        "get",
        "1",
    ]);
    assert!(failed(&out).contains("it answers the last sender, and no datagram has arrived yet"));
}
