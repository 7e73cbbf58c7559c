//! Running the documented `protolink` examples (the `--help` pages' and the READMEs') as a
//! newcomer would, and judging what each one did, not only its exit status: a `decode` must
//! decode frames, a `watch` or `web` must receive bytes, a `record` must write a capture with
//! frames in it, a `get` must print the value. Used by `tests/all/protolink_help.rs` and
//! `tests/all/readme_examples.rs`.

use std::path::{Path, PathBuf};
use std::process::Output;

/// Where one test's box and tools listen, instead of the demo's fixed ports.
#[derive(Debug, Clone)]
pub struct Env {
    /// The QEMU UART ports (the demo's 7000, 7001, 7002).
    pub uart: [u16; 3],
    /// The box's telemetry UDP port (5001) and command port (5002).
    pub box_out: u16,
    /// The box's command port (5002).
    pub box_in: u16,
    /// The EFB app's GDL90 port (4000).
    pub efb: u16,
    /// The page's port (`web`, 8080 and 8081).
    pub page: u16,
    /// A directory for the files examples write (captures).
    pub tmp: PathBuf,
    /// The workspace root (for `testdata/`).
    pub root: PathBuf,
}

/// Splits an example at spaces, honouring double quotes, and drops a trailing comment
/// (`# ...`, or `(in a second terminal ...)` after two spaces).
///
/// ```
/// use protolink_tests::examples::words;
/// assert_eq!(
///     words(r#"protolink aeolus command "a pause"   # pause it"#),
///     ["protolink", "aeolus", "command", "a pause"]
/// );
/// ```
pub fn words(line: &str) -> Vec<String> {
    let line = line.split("  (").next().unwrap_or(line);
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    let mut started = false;
    for c in line.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                started = true;
            }
            '#' if !quoted && !started => break,
            ' ' if !quoted => {
                if started {
                    words.push(std::mem::take(&mut word));
                    started = false;
                }
            }
            c => {
                word.push(c);
                started = true;
            }
        }
    }
    if started {
        words.push(word);
    }
    words
}

/// The subcommand (first word) of an example's arguments.
pub fn subcommand(args: &[String]) -> &str {
    args.first().map_or("", String::as_str)
}

/// The value after `flag`, if any.
pub fn flag<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    let i = args.iter().position(|a| a == flag)?;
    args.get(i + 1).map(String::as_str)
}

/// Moves an example's arguments (without the leading `protolink`) onto `env`: the demo's
/// ports become the test's, `file:capture.bin` the matching sample capture in `testdata/`,
/// a `.pcapng` file a file in `env.tmp`, `web --listen` the test's page port, and a long run
/// gets `--seconds` (`seconds`) so that it ends by itself.
pub fn adapt(args: &[String], env: &Env, seconds: &str) -> Vec<String> {
    let proto = flag(args, "--proto").unwrap_or("aeolus").to_owned();
    let mut w: Vec<String> = args
        .iter()
        .map(|a| {
            let a = a
                .replace("127.0.0.1:7000", &format!("127.0.0.1:{}", env.uart[0]))
                .replace("127.0.0.1:7001", &format!("127.0.0.1:{}", env.uart[1]))
                .replace("127.0.0.1:7002", &format!("127.0.0.1:{}", env.uart[2]))
                .replace("5001", &env.box_out.to_string())
                .replace("5002", &env.box_in.to_string())
                .replace("127.0.0.1:4000", &format!("127.0.0.1:{}", env.efb))
                .replace("udp:4000", &format!("udp:{}", env.efb));
            if a == "file:capture.bin" {
                let name = match proto.as_str() {
                    "aydp" => "qemu-uart1-aydp.bin",
                    "aok" => "qemu-uart2-aok.bin",
                    _ => "qemu-uart0-aeolus.bin",
                };
                return format!("file:{}", env.root.join("testdata").join(name).display());
            }
            if a.ends_with(".pcapng") && !a.contains('/') {
                return env.tmp.join(&a).display().to_string();
            }
            a
        })
        .collect();
    let sub = subcommand(&w).to_owned();
    if sub == "export" {
        // Its tables go to the temporary directory; a byte file is the protocol's sample.
        let mut out_next = false;
        for a in w.iter_mut() {
            if out_next {
                *a = env.tmp.join(a.as_str()).display().to_string();
            } else if a.ends_with(".bin") && !a.contains('/') {
                let name = match proto.as_str() {
                    "aydp" => "qemu-uart1-aydp.bin",
                    "aok" => "qemu-uart2-aok.bin",
                    _ => "qemu-uart0-aeolus.bin",
                };
                *a = env.root.join("testdata").join(name).display().to_string();
            }
            out_next = a == "--out";
        }
    }
    let runs_on = matches!(
        sub.as_str(),
        "decode" | "watch" | "web" | "bridge" | "sim" | "gdl90" | "nmea" | "record" | "replay"
    );
    match w.iter().position(|a| a == "--seconds") {
        Some(i) if i + 1 < w.len() => w[i + 1] = seconds.to_owned(),
        _ if runs_on && !w.iter().any(|a| a.starts_with("file:")) => {
            w.extend(["--seconds".into(), seconds.to_owned()]);
        }
        _ => {}
    }
    if sub == "nmea" {
        // The app's UDP port (10110) is the test's EFB port; a server listens on the page port.
        for a in w.iter_mut() {
            *a = a.replace("127.0.0.1:10110", &format!("127.0.0.1:{}", env.efb));
        }
        if let Some(i) = w.iter().position(|a| a == "--listen") {
            if i + 1 < w.len() {
                w[i + 1] = format!("127.0.0.1:{}", env.page);
            }
        } else if !w.iter().any(|a| a == "--to") {
            w.extend(["--listen".into(), format!("127.0.0.1:{}", env.page)]);
        }
    }
    if sub == "web" {
        let listen = format!("127.0.0.1:{}", env.page);
        match w.iter().position(|a| a == "--listen") {
            Some(i) if i + 1 < w.len() => w[i + 1] = listen,
            _ => w.extend(["--listen".into(), listen]),
        }
    }
    if sub == "sim" {
        for (f, value) in [
            ("--udp-out", format!("127.0.0.1:{}", env.box_out)),
            ("--udp-in", env.box_in.to_string()),
        ] {
            if !w.iter().any(|a| a == f) {
                w.extend([f.to_owned(), value]);
            }
        }
    }
    w
}

/// An `export` example (as [`adapt`] made it) made ready to run: its output directory
/// emptied, and each capture it reads that does not exist yet recorded by `record` (which
/// writes the sample UART capture of `testdata/` as that capture).
pub fn prepare_export(args: &[String], record: impl Fn(&Path)) {
    if let Some(out) = flag(args, "--out") {
        let _ = std::fs::remove_dir_all(out);
    }
    for a in args.iter().skip(1) {
        if a.ends_with(".pcapng") && !Path::new(a).exists() {
            record(Path::new(a));
        }
    }
}

/// The arguments of `protolink record` that write the sample UART capture of `testdata/`
/// (AEOLUS) as the pcapng `capture`: what a `replay` or `export` example reads.
pub fn record_sample(env: &Env, capture: &Path) -> Vec<String> {
    vec![
        "record".into(),
        "--from".into(),
        format!(
            "file:{}",
            env.root.join("testdata/qemu-uart0-aeolus.bin").display()
        ),
        "--out".into(),
        capture.display().to_string(),
    ]
}

/// Whether an example talks to a box on UDP (reads its telemetry port or sends to its
/// command port), which `protolink sim` then plays.
pub fn needs_udp_box(args: &[String], env: &Env) -> bool {
    let out = format!("udp:{}", env.box_out);
    let out_full = format!("udp:127.0.0.1:{}", env.box_out);
    let cmd = format!("udp:127.0.0.1:{}", env.box_in);
    subcommand(args) != "sim"
        && subcommand(args) != "replay"
        && args
            .iter()
            .any(|a| *a == out || *a == out_full || *a == cmd)
}

/// The first number after `key=` or `"key":` in `text`.
///
/// ```
/// use protolink_tests::examples::counter;
/// assert_eq!(counter("summary: bytes=405 frames_ok=15", "frames_ok"), Some(15));
/// assert_eq!(counter(r#"{"frames_ok":3}"#, "frames_ok"), Some(3));
/// assert_eq!(counter("frames_ok=x", "frames_ok"), None);
/// ```
pub fn counter(text: &str, key: &str) -> Option<u64> {
    for pattern in [format!("{key}="), format!("\"{key}\":")] {
        if let Some(at) = text.find(&pattern) {
            let digits: String = text[at + pattern.len()..]
                .chars()
                .take_while(char::is_ascii_digit)
                .collect();
            if let Ok(n) = digits.parse() {
                return Some(n);
            }
        }
    }
    None
}

/// The number right before `word` in `text` (`recorded 12 packets`: 12 before "packets").
fn number_before(text: &str, word: &str) -> Option<u64> {
    let mut last = None;
    for pair in text.split_whitespace().collect::<Vec<_>>().windows(2) {
        if pair[1].trim_end_matches(',') == word
            && let Ok(n) = pair[0].parse()
        {
            last = Some(n);
        }
    }
    last
}

fn positive(what: &str, n: Option<u64>) -> Result<(), String> {
    match n {
        Some(n) if n > 0 => Ok(()),
        Some(_) => Err(format!("{what} is 0")),
        None => Err(format!("no {what} in the output")),
    }
}

/// Judges what an example did from its output: `Ok` when it did what it is for.
/// `decode_capture` decodes a capture file (for `record`): its summary.
pub fn check_outcome(
    args: &[String],
    out: &Output,
    decode_capture: impl Fn(&Path) -> String,
) -> Result<(), String> {
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let all = format!("{stdout}\n{stderr}");
    let sub = subcommand(args);
    let second = args.get(1).map_or("", String::as_str);
    // The box flies, so it refuses set changes in flight (AOK 'I'; an AYDP store, which
    // `aydp store --verify` reports from the box's counters), as a real one does.
    let refused_in_flight = stderr.contains("in flight ('I')")
        || stderr.contains("refused to store its configuration: it is flying");
    let refused_as_a_real_box_would = matches!(sub, "aok" | "aydp") && refused_in_flight;
    if !(out.status.success() || refused_as_a_real_box_would) {
        return Err(format!("exit status {}: {stderr}", out.status));
    }
    match sub {
        "decode" => positive("frames_ok", counter(&all, "frames_ok")),
        "watch" => {
            let last = stdout.rsplit("protolink watch").next().unwrap_or("");
            let header = last.lines().next().unwrap_or("");
            positive("bytes watched", number_before(header, "bytes"))?;
            if last.contains(" live") {
                Ok(())
            } else {
                Err("no message type live".into())
            }
        }
        "web" => positive("bytes", counter(&stdout, "bytes")),
        "bridge" => positive("frames_forwarded", counter(&stdout, "frames_forwarded")),
        "sim" => positive("telemetry", counter(&stdout, "telemetry")),
        "gdl90" => {
            positive("telemetry_in", counter(&stdout, "telemetry_in"))?;
            if args.iter().any(|a| a == "--discover") {
                Ok(())
            } else {
                positive("ahrs", counter(&stdout, "ahrs"))
            }
        }
        "nmea" => {
            positive("telemetry_in", counter(&stdout, "telemetry_in"))?;
            positive("rmc", counter(&stdout, "rmc"))
        }
        "record" => {
            positive("packets recorded", number_before(&stderr, "packets"))?;
            let file = flag(args, "--out").ok_or("record without --out")?;
            let summary = decode_capture(Path::new(file));
            positive("frames_ok in the capture", counter(&summary, "frames_ok"))
        }
        "replay" => positive("payloads replayed", number_before(&stderr, "payloads")),
        "export" => {
            let last = stdout.lines().last().unwrap_or("");
            if !last.starts_with("export: ") {
                return Err(format!("no export summary: {stdout}"));
            }
            positive("rows exported", number_before(last, "rows"))
        }
        "aeolus" if second == "command" || args.iter().any(|a| a == "command") => {
            if stdout.contains(": confirmed") {
                Ok(())
            } else {
                Err(format!("not confirmed: {stdout}"))
            }
        }
        "aeolus" => {
            if stdout.contains("SETTIME ") {
                Ok(())
            } else {
                Err(format!("no SETTIME report: {stdout}"))
            }
        }
        "aydp" | "aok" => {
            let verb = args
                .iter()
                .skip(1)
                .find(|a| !a.starts_with('-') && !a.contains(':') && !a.contains('.'))
                .map_or("", String::as_str);
            let want: &[&str] = match verb {
                "get" => &[" = "],
                "set" | "output" if !refused_in_flight => &[": confirmed"],
                "waypoint" if args.iter().any(|a| a == "get") => &["waypoint "],
                "bulk" => &["parameter "],
                _ => &[],
            };
            match want.iter().find(|w| !stdout.contains(**w)) {
                Some(w) => Err(format!("{w:?} not in the output: {stdout}")),
                None => Ok(()),
            }
        }
        _ => Ok(()),
    }
}
