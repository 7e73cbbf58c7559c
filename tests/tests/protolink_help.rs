//! Every example that `protolink --help` and its subcommands' `--help` show, run against the
//! release firmware in QEMU (lm3s6965evb) or `protolink sim`, as a newcomer would paste it.
//!
//! The examples' addresses are the demo's (UARTs on 7000..7002, the box's UDP on 5001/5002,
//! EFB apps on 4000) and are moved to this test's own ports; `file:capture.bin` becomes the
//! matching capture in `testdata/`; a long-running example gets `--seconds 1`, and `web` its own
//! `--listen` port. Examples on a
//! `serial:` port cannot run here (there is no serial device) and are listed as skipped.
//! Run on one board: the other board's end-to-end tests cover the firmware; this one is about
//! the help text.

mod harness;

use harness::*;
use std::net::Shutdown;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

fn run(args: &[String]) -> Output {
    finish(spawn_protolink(args))
}

fn help(path: &[&str]) -> String {
    let mut args: Vec<String> = path.iter().map(|s| s.to_string()).collect();
    args.push("--help".into());
    let out = run(&args);
    assert!(out.status.success(), "{args:?}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The subcommands a help page lists under `Commands:`.
fn subcommands(page: &str) -> Vec<String> {
    page.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_owned))
        .filter(|c| c != "help")
        .collect()
}

/// Every example line of every help page, each once, in the order the pages list them.
fn examples() -> Vec<String> {
    let mut pages = vec![Vec::<String>::new()];
    let mut found: Vec<String> = Vec::new();
    while let Some(path) = pages.pop() {
        let refs: Vec<&str> = path.iter().map(String::as_str).collect();
        let page = help(&refs);
        for line in page.lines().map(str::trim) {
            if line.starts_with("protolink ") && !found.iter().any(|f| f == line) {
                found.push(line.to_owned());
            }
        }
        for sub in subcommands(&page).into_iter().rev() {
            let mut p = path.clone();
            p.push(sub);
            pages.push(p);
        }
    }
    found
}

/// Splits at spaces, honouring double quotes, and drops a trailing `(in a second terminal...)`.
fn words(line: &str) -> Vec<String> {
    let line = line.split("  (").next().unwrap_or(line);
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

#[test]
fn every_help_example_runs_against_the_firmware() {
    let board = Board::Lm3s6965evb;
    let ports = Ports::CLI_HELP.on(board);
    let Some(mut q) = boot(board, ports) else {
        return;
    };
    // protolink takes the three UARTs.
    q.uart0.disconnect();
    let _ = q.uart1.shutdown(Shutdown::Both);
    let _ = q.uart2.shutdown(Shutdown::Both);
    std::thread::sleep(Duration::from_millis(200));
    let root = workspace_root();
    let capture = |proto: &str| {
        let name = match proto {
            "aydp" => "qemu-uart1-aydp.bin",
            "aok" => "qemu-uart2-aok.bin",
            _ => "qemu-uart0-aeolus.bin",
        };
        format!("file:{}", root.join("testdata").join(name).display())
    };
    let (box_out, box_in, efb) = (ports.uart(0) + 5, ports.uart(0) + 6, ports.uart(0) + 7);
    let mut all = examples();
    // The reset reboots the box: last.
    all.sort_by_key(|l| l.ends_with(" reset"));
    let (mut ran, mut skipped) = (0, Vec::new());
    for line in &all {
        if line.contains("serial:") {
            skipped.push(format!("{line}  (no serial port on this machine)"));
            continue;
        }
        let mut w: Vec<String> = words(line).into_iter().skip(1).collect();
        let proto = w
            .iter()
            .position(|a| a == "--proto")
            .and_then(|i| w.get(i + 1).cloned())
            .unwrap_or_default();
        for a in w.iter_mut() {
            *a = a
                .replace("127.0.0.1:7000", &format!("127.0.0.1:{}", ports.uart(0)))
                .replace("127.0.0.1:7001", &format!("127.0.0.1:{}", ports.uart(1)))
                .replace("127.0.0.1:7002", &format!("127.0.0.1:{}", ports.uart(2)))
                .replace("5001", &box_out.to_string())
                .replace("5002", &box_in.to_string())
                .replace("127.0.0.1:4000", &format!("127.0.0.1:{efb}"));
            if a == "file:capture.bin" {
                *a = capture(&proto);
            }
        }
        // The capture examples' files live in the temp directory; a replay gets one recorded
        // from the sample UART capture first.
        for a in w.iter_mut() {
            if a.ends_with(".pcapng") {
                *a = std::env::temp_dir()
                    .join(format!("protolink-help-{}-{a}", std::process::id()))
                    .display()
                    .to_string();
            }
        }
        if w.first().is_some_and(|s| s == "replay") && !std::path::Path::new(&w[1]).exists() {
            let rec = run(&[
                "record".into(),
                "--from".into(),
                capture("aeolus"),
                "--out".into(),
                w[1].clone(),
            ]);
            assert!(rec.status.success(), "recording {} for `{line}`", w[1]);
        }
        let sub = w.first().cloned().unwrap_or_default();
        let runs_on = matches!(
            sub.as_str(),
            "decode" | "watch" | "web" | "bridge" | "sim" | "gdl90" | "record" | "replay"
        );
        match w.iter().position(|a| a == "--seconds") {
            Some(i) => w[i + 1] = "1".into(),
            None if runs_on && !w.iter().any(|a| a.starts_with("file:")) => {
                w.extend(["--seconds".into(), "1".into()]);
            }
            None => {}
        }
        // The page of `web` on this test's own port (TCP UART0 + 8), never the demo's 8080.
        if sub == "web" {
            let listen = format!("127.0.0.1:{}", ports.uart(0) + 8);
            match w.iter().position(|a| a == "--listen") {
                Some(i) if i + 1 < w.len() => w[i + 1] = listen,
                _ => w.extend(["--listen".into(), listen]),
            }
        }
        if sub == "sim" {
            for (flag, value) in [
                ("--udp-out", format!("127.0.0.1:{box_out}")),
                ("--udp-in", box_in.to_string()),
            ] {
                if !w.iter().any(|a| a == flag) {
                    w.extend([flag.to_string(), value]);
                }
            }
        }
        // The AEOLUS-over-UDP examples talk to a box on UDP: `protolink sim`.
        let sim = line.contains("udp:127.0.0.1:5002").then(|| {
            let child = Command::new(protolink())
                .args([
                    "sim",
                    "--udp-out",
                    &format!("127.0.0.1:{box_out}"),
                    "--udp-in",
                ])
                .arg(box_in.to_string())
                .args(["--seconds", "10"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("start sim");
            std::thread::sleep(Duration::from_millis(300));
            child
        });
        let out = run(&w);
        if let Some(mut s) = sim {
            let _ = s.kill();
            let _ = s.wait();
        }
        let stderr = String::from_utf8_lossy(&out.stderr);
        let refused_in_flight = stderr.contains("in flight ('I')");
        // The simulated box is flying: it refuses set changes in flight, as a real one does.
        if line.contains("save-set") || line.contains("load-set") {
            assert!(refused_in_flight, "`{line}` (ran as {w:?}): {stderr}");
        } else {
            assert!(
                out.status.success(),
                "`{line}` (ran as {w:?}) failed: {stderr}\n{}",
                String::from_utf8_lossy(&out.stdout)
            );
        }
        ran += 1;
    }
    for s in &skipped {
        println!("skipped: {s}");
    }
    println!("{ran} help examples ran, {} skipped", skipped.len());
    assert!(ran >= 25, "only {ran} examples ran");
}
