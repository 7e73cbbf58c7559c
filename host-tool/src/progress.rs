//! Progress on stderr for anything that takes longer than a second.

use std::io::{IsTerminal, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long a wait must last before progress shows.
pub(crate) const SHOW_AFTER: Duration = Duration::from_secs(1);

/// A spinner on stderr that appears once a wait has lasted [`SHOW_AFTER`], and disappears when
/// dropped. On a terminal it spins in place; otherwise it prints one line, then a dot a second.
#[derive(Debug)]
pub(crate) struct Spinner {
    done: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Spinner {
    /// Starts waiting on `what`.
    pub(crate) fn start(what: &str) -> Self {
        let done = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&done);
        let what = what.to_owned();
        let thread = std::thread::spawn(move || spin(&what, &flag));
        Spinner {
            done,
            thread: Some(thread),
        }
    }
}

fn spin(what: &str, done: &AtomicBool) {
    const FRAMES: [char; 4] = ['|', '/', '-', '\\'];
    let started = Instant::now();
    let tty = std::io::stderr().is_terminal();
    let mut shown = false;
    let mut tick = 0usize;
    let mut last_dot = started;
    while !done.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(100));
        if started.elapsed() < SHOW_AFTER || done.load(Ordering::SeqCst) {
            continue;
        }
        let mut err = std::io::stderr().lock();
        if tty {
            tick += 1;
            let _ = write!(
                err,
                "\r{} {what} ({:.1} s)",
                FRAMES[tick % FRAMES.len()],
                started.elapsed().as_secs_f64()
            );
        } else if !shown {
            let _ = write!(err, "{what}...");
            last_dot = Instant::now();
        } else if last_dot.elapsed() >= Duration::from_secs(1) {
            let _ = write!(err, ".");
            last_dot = Instant::now();
        }
        shown = true;
        let _ = err.flush();
    }
    if shown {
        let mut err = std::io::stderr().lock();
        let _ = if tty {
            write!(err, "\r\x1b[2K")
        } else {
            writeln!(err)
        };
        let _ = err.flush();
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        self.done.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
