//! Every example that `protolink --help` and its subcommands' `--help` show, run against the
//! release firmware in QEMU (lm3s6965evb) or `protolink sim`, as a newcomer would paste it, and
//! judged by what it did (`protolink_tests::examples::check_outcome`: frames decoded, bytes
//! watched, a capture with frames in it, the value read), not by its exit status alone.
//!
//! The examples' addresses are the demo's (UARTs on 7000..7002, the box's UDP on 5001/5002,
//! EFB apps on 4000) and are moved to this test's own ports; `file:capture.bin` becomes the
//! matching capture in `testdata/`; a long-running example gets `--seconds 1`, and `web` its own
//! `--listen` port. Examples on a
//! `serial:` port cannot run here (there is no serial device) and are listed as skipped.
//! Run on one board: the other board's end-to-end tests cover the firmware; this one is about
//! the help text.

use crate::harness::*;
use protolink_tests::examples::{
    Env, adapt, check_outcome, flag, needs_udp_box, prepare_export, record_sample, subcommand,
    words,
};
use std::net::Shutdown;
use std::process::{Output, Stdio};
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
    let tmp = std::env::temp_dir().join(format!("protolink-help-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("a temporary directory");
    let env = Env {
        uart: [ports.uart(0), ports.uart(1), ports.uart(2)],
        box_out: ports.uart(0) + 5,
        box_in: ports.uart(0) + 6,
        efb: ports.uart(0) + 7,
        page: ports.uart(0) + 8,
        tmp: tmp.clone(),
        root: workspace_root(),
    };
    let mut all = examples();
    // The reset reboots the box: last.
    all.sort_by_key(|l| l.ends_with(" reset"));
    let (mut ran, mut skipped) = (0, Vec::new());
    for line in &all {
        if line.contains("serial:") {
            skipped.push(format!("{line}  (no serial port on this machine)"));
            continue;
        }
        let given: Vec<String> = words(line).into_iter().skip(1).collect();
        let w = adapt(&given, &env, "1");
        // A replay gets a capture recorded from the sample UART capture first.
        if subcommand(&w) == "replay" && !std::path::Path::new(&w[1]).exists() {
            let rec = run(&record_sample(&env, std::path::Path::new(&w[1])));
            assert!(rec.status.success(), "recording {} for `{line}`", w[1]);
        }
        // An export reads captures recorded from the sample UART capture, into a fresh directory.
        if subcommand(&w) == "export" {
            prepare_export(&w, |capture| {
                let rec = run(&record_sample(&env, capture));
                assert!(rec.status.success(), "recording {capture:?} for `{line}`");
            });
        }
        // The examples that talk to a box on UDP get `protolink sim` as that box.
        let sim = needs_udp_box(&w, &env).then(|| start_sim(&env));
        // A replay is checked by a listener on its destination.
        let discovery = discovery_port_turn(&w);
        let out = run(&w);
        drop(discovery);
        if let Some(mut s) = sim {
            let _ = s.kill();
            let _ = s.wait();
        }
        if let Err(why) = check_outcome(&w, &out, |file| decode_summary(file, &w)) {
            panic!(
                "`{line}` (ran as {w:?}): {why}\nstdout:\n{}\nstderr:\n{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        ran += 1;
    }
    let _ = std::fs::remove_dir_all(&tmp);
    for s in &skipped {
        println!("skipped: {s}");
    }
    println!(
        "{ran} help examples ran and did what they are for, {} skipped",
        skipped.len()
    );
    assert!(ran >= 25, "only {ran} examples ran");
}

/// `protolink sim` playing the box on `env`'s UDP ports for 10 s.
fn start_sim(env: &Env) -> std::process::Child {
    let child = protolink_command()
        .args(["sim", "--udp-out", &format!("127.0.0.1:{}", env.box_out)])
        .args(["--udp-in", &env.box_in.to_string(), "--seconds", "10"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start sim");
    std::thread::sleep(Duration::from_millis(300));
    child
}

/// `protolink decode --from FILE`'s output for a capture `record` made: with the recording's
/// `--proto` (and `--side`), since this test's moved UDP ports do not name the protocol.
fn decode_summary(file: &std::path::Path, record: &[String]) -> String {
    let mut args = vec![
        "decode".to_owned(),
        "--from".into(),
        file.display().to_string(),
    ];
    args.extend([
        "--proto".into(),
        flag(record, "--proto").unwrap_or("aeolus").into(),
    ]);
    if let Some(side) = flag(record, "--side") {
        args.extend(["--side".into(), side.into()]);
    }
    let out = run(&args);
    String::from_utf8_lossy(&out.stdout).into_owned()
}
