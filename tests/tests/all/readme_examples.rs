//! Every shell example in the READMEs, run as written against the release firmware in QEMU
//! (lm3s6965evb) or `protolink sim`, and judged by what it did
//! (`protolink_tests::examples::check_outcome`): so a README cannot drift from the tool again.
//!
//! * A `protolink ...` line (or `cargo run -q -p protolink -- ...`) runs on this test's own
//!   ports (`examples::adapt`); one that talks to a box on UDP gets `protolink sim` as the box.
//! * A `$ ` line followed by output lines must print those lines: each shown line appears in
//!   what it printed (the counters of a `summary:`, `gdl90:` or `nmea:` line may differ, so digits are
//!   compared as "a number" there). `...` stands for lines left out.
//! * `curl` of the page runs against a `protolink web` on this test's page port, `tshark` on
//!   the capture the block recorded, `protolink wireshark > FILE` into a temporary file, a
//!   `duckdb -c "QUERY"` through DuckDB's Python package (`scripts/setup.sh python`) in the
//!   directory the block's `protolink export` wrote its tables to.
//! * Anything else (building and flashing firmware, the demo, `cd`) is listed with the reason
//!   it is not run here: a line of a form the test does not know fails it.

use crate::harness::*;
use protolink_tests::examples::{
    Env, adapt, check_outcome, needs_udp_box, prepare_export, record_sample, subcommand, words,
};
use std::net::Shutdown;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

/// The READMEs whose shell examples run here.
const READMES: [&str; 5] = [
    "README.md",
    "host-tool/README.md",
    "sensor-box/README.md",
    "firmware-example/README.md",
    "firmware-embassy/README.md",
];

/// Lines that are not run here, by how they start, and why.
const NOT_RUN: [(&str, &str); 17] = [
    (
        "scripts/demo.sh",
        "the demo runs until Ctrl-C (scripts/test.sh runs its parts)",
    ),
    ("scripts/test.sh", "this test is part of it"),
    (
        "scripts/setup.sh",
        "installs packages (scripts/test.sh runs it first)",
    ),
    (
        "cargo qemu-build",
        "a build (scripts/test.sh builds it; this test boots it)",
    ),
    (
        "cargo qemu",
        "boots the firmware until Ctrl-C (this test boots it itself)",
    ),
    ("cargo stm32", "flashes a board, or boots it until Ctrl-C"),
    ("cargo install", "installs a tool"),
    ("cargo test", "a test run (scripts/test.sh runs it)"),
    ("cargo build", "a build (scripts/test.sh builds it)"),
    ("cd ", "changes the directory"),
    ("$(rustc", "prints section sizes of a build"),
    ("\"$(rustc", "prints section sizes of a build"),
    ("mkdir -p ~/", "creates a folder in your home"),
    (
        "printf ",
        "needs nc (netcat), which the README says how to install",
    ),
    (
        "nc ",
        "needs nc (netcat), which the README says how to install",
    ),
    (
        "cargo run --release",
        "flashes the embassy firmware onto a board",
    ),
    (
        "arm-none-eabi-gcc",
        "builds your own app.c with the archive (c-api/tests/firmware.sh builds and boots a C \
         program against it the same way)",
    ),
];

/// One example: the command line and the output the README shows for it.
#[derive(Debug)]
struct Example {
    readme: &'static str,
    line: String,
    shown: Vec<String>,
}

/// The shell examples of one README, with their shown outputs.
fn examples(readme: &'static str) -> Vec<Example> {
    let text = std::fs::read_to_string(workspace_root().join(readme)).expect("read the README");
    let mut out: Vec<Example> = Vec::new();
    let mut in_block = false;
    let mut prompted = false;
    for raw in text.lines() {
        if raw.starts_with("```") {
            in_block = !in_block && ["```sh", "```bash", "```console"].contains(&raw.trim());
            prompted = false;
            continue;
        }
        if !in_block {
            continue;
        }
        let line = raw.trim_end();
        if let Some(cmd) = line.strip_prefix("$ ") {
            prompted = true;
            out.push(Example {
                readme,
                line: cmd.to_owned(),
                shown: Vec::new(),
            });
        } else if prompted {
            // The output of the last `$ ` command (a blank line ends it).
            if line.is_empty() {
                prompted = false;
            } else if let Some(last) = out.last_mut() {
                last.shown.push(line.to_owned());
            }
        } else if !line.trim().is_empty() && !line.trim_start().starts_with('#') {
            // A continued line (`\` at the end) joins the next.
            match out.last_mut() {
                Some(last) if last.line.ends_with('\\') => {
                    last.line.pop();
                    last.line.push_str(line.trim());
                }
                _ => out.push(Example {
                    readme,
                    line: line.to_owned(),
                    shown: Vec::new(),
                }),
            }
        }
    }
    out
}

/// Kills a started process when dropped.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Runs `protolink` in the workspace root, where the READMEs' relative paths start.
fn run(args: &[String]) -> Output {
    let child = protolink_command()
        .args(args)
        .current_dir(workspace_root())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start protolink");
    finish(child)
}

/// `protolink gdl90` from the simulated box to the EFB port (for an example that reads it).
fn start_gdl90(env: &Env) -> Running {
    let child = protolink_command()
        .args(["gdl90", "--from", &format!("udp:{}", env.box_out)])
        .args(["--to", &format!("127.0.0.1:{}", env.efb), "--seconds", "15"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start gdl90");
    Running(child)
}

fn start_sim(env: &Env) -> Running {
    let child = protolink_command()
        .args(["sim", "--udp-out", &format!("127.0.0.1:{}", env.box_out)])
        .args(["--udp-in", &env.box_in.to_string(), "--seconds", "15"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start sim");
    std::thread::sleep(Duration::from_millis(300));
    Running(child)
}

fn decode_summary(file: &Path) -> String {
    let out = run(&["decode".into(), "--from".into(), file.display().to_string()]);
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Digits as one placeholder, for the counter lines whose values depend on timing.
fn digits_masked(line: &str) -> String {
    let mut out = String::new();
    let mut in_number = false;
    for c in line.chars() {
        if c.is_ascii_digit() {
            if !in_number {
                out.push('#');
            }
            in_number = true;
        } else {
            in_number = false;
            out.push(c);
        }
    }
    out
}

/// Each shown output line (but `...`) must be among the printed ones.
fn check_shown(ex: &Example, printed: &str, env: &Env) -> Result<(), String> {
    for want in &ex.shown {
        let want = want.trim_end();
        if want == "..." {
            continue;
        }
        let want = want
            .replace("127.0.0.1:7000", &format!("127.0.0.1:{}", env.uart[0]))
            .replace("127.0.0.1:7001", &format!("127.0.0.1:{}", env.uart[1]));
        let counters = [
            "summary:",
            "gdl90:",
            "nmea:",
            "bridge:",
            "sim:",
            "web:",
            "{\"kind\":\"summary\"",
        ]
        .iter()
        .any(|p| want.starts_with(p));
        let found = printed.lines().any(|got| {
            got.trim_end() == want
                || (counters && digits_masked(got.trim_end()) == digits_masked(&want))
        });
        if !found {
            return Err(format!(
                "the README shows {want:?}, but it printed:\n{printed}"
            ));
        }
    }
    Ok(())
}

#[test]
fn every_readme_example_runs_as_written() {
    let board = Board::Lm3s6965evb;
    let ports = Ports::README.on(board);
    let Some(mut q) = boot(board, ports) else {
        return;
    };
    // The box's own UDP ports (5001 out, 5002 in), not moved: a capture of them is named by
    // its ports (`decode --from flight.pcapng`, the Wireshark plugin), as the READMEs show.
    q.uart0.disconnect();
    let _ = q.uart1.shutdown(Shutdown::Both);
    let _ = q.uart2.shutdown(Shutdown::Both);
    std::thread::sleep(Duration::from_millis(200));
    let tmp = std::env::temp_dir().join(format!("protolink-readme-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("a temporary directory");
    let env = Env {
        uart: [ports.uart(0), ports.uart(1), ports.uart(2)],
        box_out: 5001,
        box_in: 5002,
        efb: ports.uart(0) + 7,
        page: ports.uart(0) + 8,
        tmp: tmp.clone(),
        root: workspace_root(),
    };
    let mut all: Vec<Example> = READMES.iter().flat_map(|r| examples(r)).collect();
    // A reset reboots the box, a save-set is refused in flight: the AOK reset goes last.
    all.sort_by_key(|e| e.line.contains(" reset"));
    let (mut ran, mut not_run) = (0, Vec::new());
    let mut failures = Vec::new();
    for ex in &all {
        let line = ex.line.trim();
        let line = line
            .strip_prefix("cargo run -q -p protolink -- ")
            .or_else(|| line.strip_prefix("cargo run -p protolink -- "))
            .map_or_else(|| line.to_owned(), |rest| format!("protolink {rest}"));
        if let Some((_, why)) = NOT_RUN.iter().find(|(start, _)| line.starts_with(start)) {
            not_run.push(format!("{}: {line}  ({why})", ex.readme));
            continue;
        }
        if line.contains("serial:") || line.contains("TABLET_IP") || line.contains("--broadcast") {
            not_run.push(format!(
                "{}: {line}  (a serial port or another machine)",
                ex.readme
            ));
            continue;
        }
        let result = if line.starts_with("protolink ") {
            run_protolink(ex, &line, &env)
        } else if line.starts_with("curl ") {
            run_curl(&line, &env)
        } else if line.starts_with("tshark ") {
            run_tshark(&line, &env)
        } else if line.starts_with("duckdb ") {
            run_duckdb(&line, &env)
        } else {
            Err(
                "a line this test does not know how to run (add it to NOT_RUN with a reason, \
                 or teach the test)"
                    .to_owned(),
            )
        };
        if let Err(why) = result {
            failures.push(format!("{}: `{}`: {why}", ex.readme, ex.line));
        }
        ran += 1;
    }
    let _ = std::fs::remove_dir_all(&tmp);
    let _ = q.stop();
    for n in &not_run {
        println!("not run: {n}");
    }
    println!("{ran} README examples ran, {} not run", not_run.len());
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    assert!(ran >= 40, "only {ran} README examples ran");
}

fn run_protolink(ex: &Example, line: &str, env: &Env) -> Result<(), String> {
    // `protolink wireshark > FILE`: the plugin into a temporary file.
    let (line, redirect) = match line.split_once(" > ") {
        Some((cmd, _)) => (cmd.trim(), true),
        None => (line, false),
    };
    // `&` (run in the background): here it runs for its `--seconds` like the others.
    let given: Vec<String> = words(line)
        .into_iter()
        .skip(1)
        .filter(|w| w != "&")
        .collect();
    if given.iter().any(|a| a == "--help") || given.is_empty() {
        let out = run(&given);
        let text = String::from_utf8_lossy(&out.stdout);
        return if out.status.success() && text.contains("Usage:") {
            Ok(())
        } else {
            Err(format!("no usage: {text}"))
        };
    }
    let w = adapt(&given, env, "2");
    if subcommand(&w) == "export" {
        prepare_export(&w, |capture| {
            let _ = run(&record_sample(env, capture));
        });
    }
    let _sim = needs_udp_box(&w, env).then(|| start_sim(env));
    let efb = format!("udp:{}", env.efb);
    let _sim_for_gdl90 = w.contains(&efb).then(|| start_sim(env));
    let _gdl90 = w.contains(&efb).then(|| start_gdl90(env));
    let _discovery = discovery_port_turn(&w);
    let out = run(&w);
    let printed = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    if redirect {
        let file = env.tmp.join("plugin.lua");
        std::fs::write(&file, &out.stdout).map_err(|e| e.to_string())?;
        let lua = String::from_utf8_lossy(&out.stdout);
        return if out.status.success() && lua.contains("Proto(") {
            Ok(())
        } else {
            Err(format!("no Wireshark plugin: {printed}"))
        };
    }
    // An example the README marks `# exit status 1` must fail, with the error it shows.
    if ex.line.contains("# exit status 1") {
        if out.status.code() != Some(1) {
            return Err(format!("exit status {}, not 1: {printed}", out.status));
        }
        return check_shown(ex, &printed, env);
    }
    check_outcome(&w, &out, decode_summary).map_err(|e| format!("{e}\n{printed}"))?;
    check_shown(ex, &printed, env)
}

/// `duckdb -c "QUERY"`: the query, through DuckDB's Python package, in the temporary directory
/// where the README's `protolink export` wrote its tables; it must print a row of a capture.
fn run_duckdb(line: &str, env: &Env) -> Result<(), String> {
    let w = words(line);
    let query = w
        .iter()
        .position(|a| a == "-c")
        .and_then(|i| w.get(i + 1))
        .ok_or("no -c QUERY")?;
    let out = Command::new("python3")
        .args([
            "-c",
            "import sys, duckdb; print(duckdb.sql(sys.argv[1]).fetchall())",
            query,
        ])
        .current_dir(&env.tmp)
        .output()
        .map_err(|e| format!("python3: {e}"))?;
    let printed = String::from_utf8_lossy(&out.stdout);
    if out.status.success() && printed.contains(".pcapng") {
        Ok(())
    } else {
        Err(format!("{printed}{}", String::from_utf8_lossy(&out.stderr)))
    }
}

/// `curl` of the page: a `protolink web` (fed by `protolink sim`) on this test's page port.
fn run_curl(line: &str, env: &Env) -> Result<(), String> {
    let url = words(line)
        .into_iter()
        .find(|w| w.starts_with("http://"))
        .ok_or("no URL")?;
    let url = url
        .replace("127.0.0.1:8080", &format!("127.0.0.1:{}", env.page))
        .replace("127.0.0.1:8081", &format!("127.0.0.1:{}", env.page));
    let _sim = start_sim(env);
    let _web = Running(spawn_protolink(&[
        "web".to_owned(),
        "--from".into(),
        format!("udp:{}", env.box_out),
        "--listen".into(),
        format!("127.0.0.1:{}", env.page),
        "--seconds".into(),
        "10".into(),
    ]));
    std::thread::sleep(Duration::from_secs(2));
    let out = Command::new("curl")
        .args(["-s", &url])
        .output()
        .map_err(|e| format!("curl: {e}"))?;
    let body = String::from_utf8_lossy(&out.stdout);
    if body.contains("\"source\"") && body.contains("\"attitude\":{") {
        Ok(())
    } else {
        Err(format!("no live state from {url}: {body:?}"))
    }
}

/// `tshark` on the capture an earlier example of the README recorded.
fn run_tshark(line: &str, env: &Env) -> Result<(), String> {
    let mut w: Vec<String> = words(line).into_iter().skip(1).collect();
    for a in &mut w {
        if a.ends_with(".pcapng") {
            *a = env.tmp.join(&*a).display().to_string();
        }
        if let Some(script) = a.strip_prefix("lua_script:") {
            *a = format!("lua_script:{}", env.root.join(script).display());
        }
    }
    let out = Command::new("tshark")
        .args(&w)
        .output()
        .map_err(|e| format!("tshark: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    if out.status.success() && text.contains("AEOLUS") {
        Ok(())
    } else {
        Err(format!(
            "no AEOLUS in tshark's dissection: {}",
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}
