//! What a TCP client has been sent and not yet read, as far as its own system tells: the
//! receive window it advertises shrinks by what waits unread in its socket once its free space
//! is below the window, and opens again as its program reads. Linux hands the last advertised
//! window to the sender in `TCP_INFO` (`tcpi_snd_wnd`, since Linux 5.4); elsewhere, or on an
//! older kernel, nothing is known and [`Unread::update`] says so with `None`.
//!
//! The figure is a floor, and often 0 for a client that reads nothing:
//! * A client whose receive buffer is set (`SO_RCVBUF`, as many programs and small systems do)
//!   shows a little over half of what it leaves unread: on Linux's loopback, a 64 KiB buffer
//!   sent 80-byte lines every 10 ms offered 65,496 bytes at first, 54,112 after 20 KB and 0
//!   after about 111 KB, and the sender's writes were refused after 143,840 bytes.
//! * A Linux client with an automatically sized buffer widens that buffer with what it holds
//!   (up to `net.ipv4.tcp_rmem`'s last figure, 32 MiB here) and keeps offering the same window:
//!   80-byte lines every 10 ms left 440 KB unread and its window at 64 KiB, its buffer grown
//!   to 491 KiB. Such a client cannot be told from a reader by anything TCP shows the sender;
//!   at NMEA's few hundred bytes a second it would be found by a refused write after about a
//!   day. The shares per address (`super::fanout`) keep the user's place from it.

use std::net::TcpStream;

/// The widest window a client has advertised, and from it how much it holds unread.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Unread {
    widest: u32,
}

impl Unread {
    /// Asks the system for the window `stream`'s peer advertised last: the bytes it holds unread
    /// (its widest window so far less the last one), or `None` where the system does not tell.
    pub(crate) fn update(&mut self, stream: &TcpStream) -> Option<u32> {
        self.settle(peer_window(stream)?)
    }

    /// The same from a window already asked for.
    fn settle(&mut self, window: u32) -> Option<u32> {
        self.widest = self.widest.max(window);
        Some(self.widest - window)
    }
}

/// Where `tcpi_snd_wnd` lies in Linux's `struct tcp_info` (in its UAPI header tcp.h): after
/// 8 single bytes, 24 `u32`, 4 `u64`, 6 `u32`, 4 `u64`, 2 `u32`, 2 `u64`, 3 `u32`.
#[cfg(target_os = "linux")]
const SND_WND_AT: usize = 228;

/// The receive window `stream`'s peer advertised last, bytes after scaling.
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
fn peer_window(stream: &TcpStream) -> Option<u32> {
    use std::os::fd::AsRawFd as _;
    let mut info = [0u8; SND_WND_AT + 4];
    let mut len = libc::socklen_t::try_from(info.len()).ok()?;
    // SAFETY: `info` is a writable buffer of `len` bytes that lives across the call; the kernel
    // writes at most `len` bytes into it and stores in `len` how many it wrote.
    let rc = unsafe {
        libc::getsockopt(
            stream.as_raw_fd(),
            libc::IPPROTO_TCP,
            libc::TCP_INFO,
            info.as_mut_ptr().cast(),
            &mut len,
        )
    };
    if rc != 0 || usize::try_from(len).ok()? < info.len() {
        return None;
    }
    let field = info.get(SND_WND_AT..)?.first_chunk::<4>()?;
    Some(u32::from_ne_bytes(*field))
}

/// Not known beyond Linux.
#[cfg(not(target_os = "linux"))]
fn peer_window(_: &TcpStream) -> Option<u32> {
    None
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::io::{Read as _, Write as _};
    use std::net::TcpListener;
    use std::time::{Duration, Instant};

    #[test]
    fn unread_is_the_widest_window_less_the_last() {
        let mut u = Unread::default();
        assert_eq!(u.settle(65_000), Some(0));
        assert_eq!(u.settle(60_000), Some(5_000));
        assert_eq!(u.settle(65_536), Some(0));
        assert_eq!(u.settle(1_536), Some(64_000));
    }

    /// Polls `stream`'s window until `done` holds of the bytes unread, or `wait`; the last
    /// figure.
    fn unread_until(
        u: &mut Unread,
        stream: &TcpStream,
        wait: Duration,
        done: impl Fn(u32) -> bool,
    ) -> u32 {
        let started = Instant::now();
        loop {
            let unread = u.update(stream).expect("Linux tells the peer's window");
            if done(unread) || started.elapsed() > wait {
                return unread;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// A client from `from` (an address of 127/8) with a 64 KiB receive buffer, as a program
    /// sets it (`SO_RCVBUF`).
    pub(crate) fn connect_with_buffer(from: [u8; 4], to: std::net::SocketAddr) -> TcpStream {
        use socket2::{Domain, Socket, Type};
        let s = Socket::new(Domain::IPV4, Type::STREAM, None).unwrap();
        s.set_recv_buffer_size(64 * 1024).unwrap();
        s.bind(&std::net::SocketAddr::from((from, 0)).into())
            .unwrap();
        s.connect(&to.into()).unwrap();
        s.into()
    }

    /// On a loopback connection whose client set its receive buffer, the window read at
    /// `SND_WND_AT` shrinks by what the client leaves unread and opens again once it reads it
    /// all (a wrong offset reads another field).
    #[cfg(target_os = "linux")]
    #[test]
    fn the_window_shrinks_by_what_the_peer_leaves_unread_and_opens_when_it_reads() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let mut peer = connect_with_buffer([127, 0, 0, 1], listener.local_addr().unwrap());
        let (mut server, _) = listener.accept().unwrap();
        let mut u = Unread::default();
        let first = peer_window(&server).unwrap();
        assert!(first >= 8 * 1024, "a loopback window of {first} bytes");
        assert_eq!(
            unread_until(&mut u, &server, Duration::from_secs(2), |n| n == 0),
            0
        );

        // 1 KiB at a time until 8 KiB are seen unread (the peer's system widens its window
        // over the first few writes), never more than was sent.
        let mut sent = 0;
        let mut unread = 0;
        while unread < 8 * 1024 && sent < 48 * 1024 {
            server.write_all(&[b'x'; 1024]).unwrap();
            sent += 1024;
            unread = unread_until(&mut u, &server, Duration::from_millis(50), |n| {
                n >= 8 * 1024
            });
        }
        assert!(
            (8 * 1024..=sent).contains(&unread),
            "{unread} unread of {sent} bytes sent"
        );

        let mut got = vec![0u8; sent as usize];
        peer.read_exact(&mut got).unwrap();
        // The peer's system announces the opened window with its next acknowledgement.
        server.write_all(b"y").unwrap();
        let unread = unread_until(&mut u, &server, Duration::from_secs(2), |n| n <= 1024);
        assert!(
            unread <= 1024,
            "{unread} unread after the peer read everything"
        );
    }
}
