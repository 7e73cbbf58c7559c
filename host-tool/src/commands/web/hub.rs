//! The one-slot hub between the decoder and the live-update streams: the decoder publishes
//! each snapshot into it, replacing the last one (never a queue), and every stream waits for
//! one newer than the one it sent. So a slow client only misses snapshots.

use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::Duration;

/// The latest snapshot, shared by the decoder (which publishes) and the streams (which wait).
#[derive(Debug, Default)]
pub(crate) struct Hub {
    latest: Mutex<Latest>,
    changed: Condvar,
}

#[derive(Debug, Default)]
struct Latest {
    seq: u64,
    json: Arc<str>,
    closed: bool,
}

impl Hub {
    /// Replaces the latest snapshot and wakes every waiting stream.
    pub(crate) fn publish(&self, json: String) {
        let mut l = self.latest.lock().unwrap_or_else(PoisonError::into_inner);
        l.seq = l.seq.wrapping_add(1);
        l.json = json.into();
        drop(l);
        self.changed.notify_all();
    }

    /// Ends every stream (the command is stopping).
    pub(crate) fn close(&self) {
        self.latest
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .closed = true;
        self.changed.notify_all();
    }

    /// The latest snapshot and its number.
    pub(crate) fn latest(&self) -> (u64, Arc<str>) {
        let l = self.latest.lock().unwrap_or_else(PoisonError::into_inner);
        (l.seq, l.json.clone())
    }

    /// Waits up to `timeout` for a snapshot newer than `seen`: `Ok(Some(..))` a newer one,
    /// `Ok(None)` none yet, `Err(())` the hub was closed.
    #[allow(clippy::result_unit_err)]
    pub(crate) fn newer(
        &self,
        seen: u64,
        timeout: Duration,
    ) -> Result<Option<(u64, Arc<str>)>, ()> {
        let l = self.latest.lock().unwrap_or_else(PoisonError::into_inner);
        let (l, _) = self
            .changed
            .wait_timeout_while(l, timeout, |l| l.seq == seen && !l.closed)
            .unwrap_or_else(PoisonError::into_inner);
        if l.closed {
            Err(())
        } else if l.seq != seen {
            Ok(Some((l.seq, l.json.clone())))
        } else {
            Ok(None)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hub_keeps_only_the_latest_snapshot() {
        let hub = Hub::default();
        assert_eq!(hub.newer(0, Duration::ZERO), Ok(None));
        for i in 1..=1000 {
            hub.publish(format!("{{\"n\":{i}}}"));
        }
        // A reader that was away gets the newest, never a backlog.
        let (seq, json) = hub.newer(0, Duration::ZERO).unwrap().unwrap();
        assert_eq!((seq, &*json), (1000, "{\"n\":1000}"));
        assert_eq!(hub.newer(seq, Duration::from_millis(10)), Ok(None));
        hub.close();
        assert_eq!(hub.newer(seq, Duration::from_secs(60)), Err(()));
    }
}
