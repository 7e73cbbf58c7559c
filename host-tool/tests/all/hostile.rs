//! The tool held to the libraries' standard: hostile arguments, exact offsets after garbage and
//! rescans, safe text, truthful AEOLUS command outcomes, and a box that still answers after a
//! flood.

use std::net::UdpSocket;
use std::time::{Duration, Instant};

use crate::common::*;
use aeolus_proto::CrcMode;
use aeolus_proto::message::{Message, Text};
use serde_json::Value;

/// Every subcommand with every kind of hostile number: one sentence, exit status 2.
#[test]
fn hostile_numbers_are_one_sentence_and_exit_two() {
    let hostile = ["inf", "nan", "-5", "1e20", "", "-inf", "5x"];
    let cases: &[&[&str]] = &[
        &[
            "decode",
            "--proto",
            "aeolus",
            "--from",
            "udp:0",
            "--seconds",
            "@",
        ],
        &["watch", "--from", "udp:0", "--seconds", "@"],
        &["bridge", "--uart", "file:/dev/null", "--seconds", "@"],
        &["sim", "--seconds", "@"],
        &["sim", "--airspeed", "@"],
        &["sim", "--bank", "@"],
        &["sim", "--altitude", "@"],
        &[
            "aydp",
            "--to",
            "tcp:127.0.0.1:1",
            "--timeout-ms",
            "@",
            "store",
        ],
        &[
            "aok",
            "--to",
            "tcp:127.0.0.1:1",
            "--timeout-ms",
            "@",
            "get",
            "1",
        ],
        &[
            "aok",
            "--to",
            "tcp:127.0.0.1:1",
            "--quiet-ms",
            "@",
            "get",
            "1",
        ],
        &[
            "aok",
            "--to",
            "tcp:127.0.0.1:1",
            "motor",
            "1",
            "1",
            "--hold-ms",
            "@",
        ],
        &["aydp", "--to", "tcp:127.0.0.1:1", "output", "1:2=@"],
        &[
            "aeolus",
            "--to",
            "udp:127.0.0.1:9",
            "--timeout",
            "@",
            "settime",
        ],
    ];
    for case in cases {
        for value in hostile {
            // A negative bank or altitude is a real flight.
            let negative_ok = case.contains(&"--bank") || case.contains(&"--altitude");
            let value = if value == "-5" && negative_ok {
                "-1e6"
            } else {
                value
            };
            let args: Vec<&str> = case
                .iter()
                .map(|a| if *a == "@" { value } else { a })
                .collect();
            let out = run(&args);
            let err = usage_failed(&out);
            assert!(!err.contains("panicked"), "{args:?}: {err}");
        }
    }
    // The range is named in the sentence.
    let err = usage_failed(&run(&["sim", "--seconds", "1e20"]));
    assert!(err.contains("0 s to 31536000 s"), "{err}");
    let err = usage_failed(&run(&["sim", "--bank", "nan"]));
    assert!(err.contains("-60 to 60 degrees"), "{err}");
}

fn aeolus_frame(m: &Message<'_>) -> Vec<u8> {
    let mut buf = vec![0u8; 600];
    let n = m.encode(&mut buf, CrcMode::Compute).unwrap();
    buf.truncate(n);
    buf
}

fn decode_lines(args: &[&str], bytes: &[u8]) -> Vec<Value> {
    let file = TempFile::new("hostile", bytes);
    let mut full = vec!["decode", "--json"];
    full.extend_from_slice(args);
    let from = file.endpoint();
    full.extend(["--from", &from]);
    ok(&run(&full))
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .filter(|v: &Value| v["kind"] != "summary")
        .collect()
}

/// `offset` is where the test put each frame, after garbage and behind false starts.
#[test]
fn offsets_point_at_the_frames_the_test_placed() {
    // AEOLUS: noise, then a TOAST, a broken frame, a COMMAND.
    let toast = aeolus_frame(&Message::Toast(Text::new("one").unwrap()));
    let command = aeolus_frame(&Message::Command(Text::new("a pause").unwrap()));
    let mut s = vec![1, 2, 3];
    let at_toast = s.len();
    s.extend(&toast);
    s.extend([0x7E, 0x52, 0x41, 0x42, 0x7E]);
    let at_command = s.len();
    s.extend(&command);
    let lines = decode_lines(&["--proto", "aeolus"], &s);
    let msgs: Vec<_> = lines.iter().filter(|l| l["kind"] == "message").collect();
    assert_eq!(msgs[0]["offset"], at_toast);
    assert_eq!(msgs[0]["len"], toast.len());
    assert_eq!(msgs[1]["offset"], at_command);
    assert_eq!(msgs[1]["len"], command.len());

    // AYDP: a false start whose claimed length swallows a heartbeat; the rescan finds the
    // heartbeat, which must be reported at its own bytes.
    let heartbeat = [0xFF, 0x80, 0x07, 0, 0, 0, 0x78];
    let mut s = vec![0x00, 0x11];
    let at_false = s.len();
    s.extend([0xFF, 0x00, 0x28, 0, 0, 0]);
    let at_heartbeat = s.len();
    s.extend(heartbeat);
    s.extend([0x22; 40]);
    let at_second = s.len();
    s.extend(heartbeat);
    let lines = decode_lines(&["--proto", "aydp"], &s);
    let msgs: Vec<_> = lines.iter().filter(|l| l["kind"] == "message").collect();
    assert_eq!(msgs.len(), 2, "{lines:?}");
    assert_eq!(msgs[0]["offset"], at_heartbeat, "{lines:?}");
    assert_eq!(msgs[1]["offset"], at_second, "{lines:?}");
    let errors: Vec<_> = lines.iter().filter(|l| l["kind"] == "error").collect();
    assert_eq!(errors[0]["offset"], at_false, "{lines:?}");

    // AOK (device side): noise and a debug frame with a bad checksum before a good one.
    let good = [0x1C, 86, 0, 0, 0, 2, 86 ^ 2];
    let mut s = vec![0x00];
    s.extend([0x1C, 86, 0, 0, 0, 2, 0x55]);
    let at_good = s.len();
    s.extend(good);
    let lines = decode_lines(&["--proto", "aok"], &s);
    let msgs: Vec<_> = lines.iter().filter(|l| l["kind"] == "message").collect();
    assert_eq!(msgs.len(), 1, "{lines:?}");
    assert_eq!(msgs[0]["offset"], at_good, "{lines:?}");
}

/// Control bytes never reach the terminal raw, and different bytes never look the same.
#[test]
fn text_is_escaped_and_raw_bytes_are_kept() {
    let data = b"\x1b[2Jhi\xff\0";
    let toast = aeolus_frame(&Message::Toast(Text::from_bytes(data).unwrap()));
    let file = TempFile::new("escape", &toast);
    let text = ok(&run(&[
        "decode",
        "--proto",
        "aeolus",
        "--from",
        &file.endpoint(),
    ]));
    assert!(!text.contains('\x1b'), "{text:?}");
    assert!(text.contains(r"text=\x1b[2Jhi\xff"), "{text}");
    let lines = decode_lines(&["--proto", "aeolus"], &toast);
    assert_eq!(lines[0]["fields"]["text"], r"\x1b[2Jhi\xff");
    assert_eq!(lines[0]["fields"]["hex"], "1b5b324a6869ff");
}

fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// `protolink aeolus` against `sim`: confirmed, refused, unconfirmed; and after a flood of
/// the sim's command port, a command is still obeyed.
#[test]
fn aeolus_commands_report_the_box_answer_even_after_a_flood() {
    let (out_port, in_port) = (free_udp_port(), free_udp_port());
    let sim = spawn(&[
        "sim",
        "--udp-out",
        &format!("127.0.0.1:{out_port}"),
        "--udp-in",
        &in_port.to_string(),
        "--seconds",
        "20",
    ]);
    std::thread::sleep(Duration::from_millis(300));
    let to = format!("udp:127.0.0.1:{in_port}");
    let from = format!("udp:{out_port}");
    let command = |text: &str| run(&["aeolus", "--to", &to, "--from", &from, "command", text]);

    assert_eq!(
        ok(&command("a pause")),
        "COMMAND \"a pause\": confirmed (TOAST \"AEOLUS paused\")\n"
    );
    let err = failed(&command("fly"));
    assert!(
        err.contains("the box refused COMMAND \"fly\": TOAST \"unknown command: fly\""),
        "{err}"
    );
    assert_eq!(
        ok(&run(&["aeolus", "--to", &to, "command", "a resume"])),
        "COMMAND \"a resume\": unconfirmed (no --from to hear the box's answer on)\n"
    );

    // 2 s of datagrams as fast as one socket sends them, then a command at once.
    let flood = UdpSocket::bind("127.0.0.1:0").unwrap();
    let junk = [0x55u8; 1400];
    let started = Instant::now();
    let mut sent = 0u64;
    while started.elapsed() < Duration::from_secs(2) {
        if flood.send_to(&junk, ("127.0.0.1", in_port)).is_ok() {
            sent += 1;
        }
    }
    assert!(sent > 1000, "the flood sent only {sent} datagrams");
    assert_eq!(
        ok(&command("a pause")),
        "COMMAND \"a pause\": confirmed (TOAST \"AEOLUS paused\")\n"
    );
    let _ = sim_kill(sim);
}

fn sim_kill(mut child: std::process::Child) -> std::io::Result<()> {
    child.kill()?;
    child.wait().map(|_| ())
}

/// `watch` says when nothing arrives, with the likely causes.
#[test]
fn watch_says_when_no_data_arrives() {
    let port = free_udp_port();
    let text = ok(&run(&[
        "watch",
        "--from",
        &format!("udp:{port}"),
        "--seconds",
        "2500ms",
        "--plain",
    ]));
    assert!(
        text.contains("NO DATA    nothing from udp:127.0.0.1:"),
        "{text}"
    );
    assert!(
        text.contains("another client hold the QEMU socket"),
        "{text}"
    );
}

/// Every example in every `--help` parses (its subcommand and options exist and take the
/// values shown).
#[test]
fn every_help_example_parses() {
    use clap::Parser;
    let top = ok(&run(&["--help"]));
    let subcommands: Vec<String> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_owned))
        .filter(|c| c != "help")
        .collect();
    assert!(subcommands.len() >= 7, "{subcommands:?}");
    let mut examples = 0;
    for sub in &subcommands {
        let help = ok(&run(&[sub, "--help"]));
        for line in help
            .lines()
            .map(str::trim)
            .filter(|l| l.starts_with("protolink "))
        {
            let words = shell_words(line.split("  (").next().unwrap_or(line));
            protolink::cli::Cli::try_parse_from(&words)
                .unwrap_or_else(|e| panic!("example `{line}` does not parse: {e}"));
            examples += 1;
        }
    }
    assert!(examples >= 14, "{examples} examples");
}

/// Splits a command line at spaces, honouring double quotes.
fn shell_words(line: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ' ' if !quoted => {
                if !word.is_empty() {
                    words.push(std::mem::take(&mut word));
                }
            }
            c => word.push(c),
        }
    }
    if !word.is_empty() {
        words.push(word);
    }
    words
}
