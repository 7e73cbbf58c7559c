//! Shared helpers: running the real binary, the vectors, and a deterministic byte source.
#![allow(dead_code)]

use std::io::Read;
use std::net::{TcpListener, UdpSocket};
use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// The longest any one run of the binary may take before the test fails (never a hang).
pub const RUN_LIMIT: Duration = Duration::from_secs(60);

/// Where the runs keep their state (`gdl90`'s ownship file): never the user's home.
pub fn state_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("test-state")
}

/// Starts `protolink ARGS` with piped stdout and stderr.
pub fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_protolink"))
        .args(args)
        .env("XDG_STATE_HOME", state_dir())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the protolink binary starts")
}

/// Waits for a started run, killing it if it outlives [`RUN_LIMIT`]. Stdout and stderr are read
/// while it runs, so a full pipe never stalls it.
pub fn finish(mut child: Child) -> Output {
    let mut out_pipe = child.stdout.take().expect("stdout");
    let mut err_pipe = child.stderr.take().expect("stderr");
    let out_reader = std::thread::spawn(move || read_all(&mut out_pipe));
    let err_reader = std::thread::spawn(move || read_all(&mut err_pipe));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > RUN_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "protolink ran longer than {RUN_LIMIT:?}; stderr:\n{}",
                String::from_utf8_lossy(&err_reader.join().unwrap_or_default())
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    Output {
        status,
        stdout: out_reader.join().expect("stdout reader"),
        stderr: err_reader.join().expect("stderr reader"),
    }
}

/// Runs `protolink ARGS` to its end.
pub fn run(args: &[&str]) -> Output {
    finish(spawn(args))
}

/// Runs `protolink ARGS` with `input` on stdin.
pub fn run_with_stdin(args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_protolink"))
        .args(args)
        .env("XDG_STATE_HOME", state_dir())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the protolink binary starts");
    let mut stdin = child.stdin.take().expect("stdin");
    let input = input.to_vec();
    let writer = std::thread::spawn(move || {
        use std::io::Write;
        let _ = stdin.write_all(&input);
    });
    let out = finish(child);
    writer.join().expect("stdin writer");
    out
}

/// Stdout as text.
pub fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Stderr as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts a zero exit and returns stdout.
pub fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "protolink failed ({:?}); stderr:\n{}\nstdout:\n{}",
        out.status,
        stderr(out),
        stdout(out)
    );
    stdout(out)
}

/// Asserts a command-line mistake: exit status 2, one `error: ...` line, no panic.
pub fn usage_failed(out: &Output) -> String {
    let err = stderr(out);
    assert_eq!(
        out.status.code(),
        Some(2),
        "stderr:\n{err}\nstdout:\n{}",
        stdout(out)
    );
    assert!(err.starts_with("error: "), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// Asserts the tool's error contract: exit status 1, one `error: ...` line, no panic.
pub fn failed(out: &Output) -> String {
    let err = stderr(out);
    assert_eq!(
        out.status.code(),
        Some(1),
        "stderr:\n{err}\nstdout:\n{}",
        stdout(out)
    );
    assert!(err.contains("error: "), "no error sentence in:\n{err}");
    assert!(!err.contains("panicked"), "a panic in:\n{err}");
    assert_eq!(
        err.matches("error: ").count(),
        1,
        "more than one error in:\n{err}"
    );
    err
}

/// The parsed lines of `--json` output.
pub fn json_lines(text: &str) -> Vec<Value> {
    text.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

/// A vector file from `testdata/`.
pub fn vectors(name: &str) -> Vec<Value> {
    let text = match name {
        "aeolus" => include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../testdata/aeolus-frames.json"
        )),
        "aydp" => include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../testdata/aydp-messages.json"
        )),
        "aok" => include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../testdata/aok-frames.json"
        )),
        other => panic!("no vector file {other}"),
    };
    let v: Value = serde_json::from_str(text).expect("vector JSON");
    v["vectors"].as_array().expect("vectors").clone()
}

/// Decodes a hex string.
pub fn unhex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex"))
        .collect()
}

/// The wire bytes of a vector (`frame` or `bytes`).
pub fn vector_bytes(v: &Value) -> Vec<u8> {
    unhex(v["frame"].as_str().or(v["bytes"].as_str()).expect("bytes"))
}

/// A temporary file holding `bytes`, removed on drop.
pub struct TempFile(pub PathBuf);

impl TempFile {
    pub fn new(tag: &str, bytes: &[u8]) -> Self {
        let path = std::env::temp_dir().join(format!(
            "protolink-test-{}-{tag}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        std::fs::write(&path, bytes).expect("temp file");
        TempFile(path)
    }

    pub fn endpoint(&self) -> String {
        format!("file:{}", self.0.display())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// xorshift64*: a fixed-seed byte source, so random-input tests repeat exactly.
pub fn random_bytes(seed: u64, n: usize) -> Vec<u8> {
    let mut x = seed | 1;
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        out.extend_from_slice(&x.wrapping_mul(0x2545_F491_4F6C_DD1D).to_le_bytes());
    }
    out.truncate(n);
    out
}

/// A TCP listener on a free loopback port, and its `tcp:` endpoint.
pub fn listener() -> (TcpListener, String) {
    let l = TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = l.local_addr().expect("addr").port();
    (l, format!("tcp:127.0.0.1:{port}"))
}

/// A free TCP port on 127.0.0.1 (bound, then released).
pub fn free_tcp_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .expect("bind")
        .local_addr()
        .expect("addr")
        .port()
}

/// A free UDP port on 127.0.0.1 (bound, then released).
pub fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .expect("bind")
        .local_addr()
        .expect("addr")
        .port()
}

/// Reads everything a stream sends until it closes.
pub fn read_all(mut r: impl Read) -> Vec<u8> {
    let mut v = Vec::new();
    let _ = r.read_to_end(&mut v);
    v
}

/// Accepts one connection, giving up after [`RUN_LIMIT`] (the tool may fail before connecting).
pub fn accept(listener: &TcpListener) -> Option<std::net::TcpStream> {
    listener.set_nonblocking(true).expect("nonblocking");
    let started = Instant::now();
    while started.elapsed() < RUN_LIMIT {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false).expect("blocking");
                return Some(s);
            }
            Err(_) => std::thread::sleep(Duration::from_millis(5)),
        }
    }
    None
}
