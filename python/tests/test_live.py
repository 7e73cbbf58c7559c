"""`protolink.open` on live links, all on 127.0.0.1: `udp:PORT` (datagram boundaries kept),
`tcp:HOST:PORT`, and a serial port (a pseudo-terminal)."""

import os
import socket
import threading
import time

import pytest

import protolink
from conftest import TESTDATA, free_port

GYRO = protolink.aeolus.encode("GYRO", valid=True, timestamp_ms=7.0, x=0.5, y=-1.25, z=0.0078125)
TOAST = protolink.aeolus.encode("TOAST", text="hello")


def later(seconds, action):
    t = threading.Timer(seconds, action)
    t.start()
    return t


def test_udp():
    port = free_port()
    with protolink.open(f"udp:{port}", proto="aeolus") as link:
        assert link.source == f"udp:127.0.0.1:{port}"
        sender = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)

        def send():
            sender.sendto(TOAST + GYRO, ("127.0.0.1", port))
            sender.sendto(GYRO[:9], ("127.0.0.1", port))   # half a frame: the datagram ends it
            sender.sendto(GYRO, ("127.0.0.1", port))

        later(0.2, send)
        started = time.time()
        first = link.recv_match(type="GYRO", timeout=10)
        assert first is not None and first.x == 0.5 and first.offset == len(TOAST)
        assert started - 1 < first.capture_time < time.time() + 1 and first.flow is None
        error = next(link)
        assert error.is_error and error.kind == "truncated"
        again = next(link)
        assert again.name == "GYRO"
        # Nothing more arrives: recv_match gives up at its timeout.
        t = time.perf_counter()
        assert link.recv_match(timeout=0.3) is None
        assert 0.25 < time.perf_counter() - t < 5
        assert link.stats["frames_ok"] == 3 and link.stats["truncated"] == 1
        sender.close()


def test_tcp():
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    port = server.getsockname()[1]
    data = (TESTDATA / "qemu-uart1-aydp.bin").read_bytes()

    def serve():
        conn, _ = server.accept()
        for i in range(0, len(data), 50):   # in pieces: frames span reads
            conn.sendall(data[i:i + 50])
            time.sleep(0.01)
        conn.close()

    t = threading.Thread(target=serve)
    t.start()
    with protolink.open(f"tcp:127.0.0.1:{port}", proto="aydp", profile="spec") as link:
        names = [m.name for m in link]   # ends when the server closes
    t.join()
    server.close()
    assert names == ["HEARTBEAT", "POSITION", "FIX_QUALITY"] * 5


def test_tcp_refused():
    port = free_port(socket.SOCK_STREAM)
    with pytest.raises(ConnectionRefusedError, match=f"cannot open tcp:127.0.0.1:{port}"):
        protolink.open(f"tcp:127.0.0.1:{port}", proto="aeolus")


def test_serial_pty():
    master, slave = os.openpty()
    name = os.ttyname(slave)
    data = (TESTDATA / "qemu-uart2-aok.bin").read_bytes()[:700]
    with protolink.open(f"serial:{name}@38400", proto="aok", side="device") as link:
        later(0.1, lambda: os.write(master, data))
        got = [link.recv_match(timeout=10) for _ in range(100)]
    os.close(master)
    os.close(slave)
    assert all(m is not None and m.name == "DEBUG" for m in got)
    assert [m.offset for m in got[:3]] == [0, 7, 14]


def test_closed_reader():
    r = protolink.open(TESTDATA / "qemu-uart2-aok.bin", proto="aok")
    r.close()
    with pytest.raises(ValueError, match="is closed"):
        next(r)
