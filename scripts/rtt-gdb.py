#!/usr/bin/env python3
"""Reads a firmware's defmt RTT up-channel 0 through QEMU's GDB stub, as a debug probe would.

    scripts/rtt-gdb.py ELF PORT [QEMU_PID]

The STM32 board logs with `defmt-rtt`: the log is a ring buffer in the target's RAM, found
through the `_SEGGER_RTT` control block. A probe reads it over SWD; in QEMU the GDB stub
(`-gdb tcp:127.0.0.1:PORT`) is the only way in. Every POLL_S seconds this stops the VM
(^C), reads the new bytes, advances the read offset, and continues the VM, so the firmware's
non-blocking RTT channel never fills up. The bytes go to stdout unchanged (pipe them into
`defmt-print -e ELF`).

Stopping the VM also stops QEMU's virtual clock, so the box's millisecond clock does not see
the pauses; a poll takes well under a millisecond of host time.

Exits when the stub closes the connection (QEMU exited), or, with QEMU_PID, when that
process is gone before the stub came up. Only 127.0.0.1 is ever contacted.
"""

import os
import socket
import struct
import sys
import time

# 1 KiB of RTT buffer (defmt-rtt's default) holds seconds of this firmware's log; each poll
# stops the VM for a few ms of host time, so polls are few.
POLL_S = 0.2
# The RTT control block: "SEGGER RTT\0..." (16 bytes), max up, max down, then the up
# channels, 24 bytes each: name, buffer, size, write offset, read offset, flags.
RTT_ID = b"SEGGER RTT"
UP0 = 24
CHANNEL_LEN = 24


def symbol(elf_path, name):
    """The address of `name` in a 32-bit little-endian ELF's .symtab, or None."""
    with open(elf_path, "rb") as f:
        elf = f.read()
    if elf[:4] != b"\x7fELF" or elf[4] != 1 or elf[5] != 1:
        raise SystemExit(f"{elf_path}: not a 32-bit little-endian ELF")
    shoff, = struct.unpack_from("<I", elf, 0x20)
    shentsize, shnum = struct.unpack_from("<HH", elf, 0x2E)
    sections = [struct.unpack_from("<IIIIIIIIII", elf, shoff + i * shentsize) for i in range(shnum)]
    want = name.encode()
    for sh in sections:
        if sh[1] != 2:  # SHT_SYMTAB
            continue
        strtab = sections[sh[6]]  # sh_link
        str_off = strtab[4]
        for off in range(sh[4], sh[4] + sh[5], 16):
            st_name, st_value = struct.unpack_from("<II", elf, off)
            end = elf.index(b"\0", str_off + st_name)
            if elf[str_off + st_name:end] == want:
                return st_value
    return None


class StubError(Exception):
    """The stub refused a read or a write."""


class Stub:
    """A GDB remote-protocol client, just enough for memory reads and writes."""

    def __init__(self, sock):
        self.sock = sock
        self.buf = b""

    def _recv(self):
        data = self.sock.recv(65536)
        if not data:
            raise EOFError
        self.buf += data

    def packet(self, timeout=5.0):
        """The next packet's payload (acks and stray bytes skipped)."""
        deadline = time.monotonic() + timeout
        while True:
            start = self.buf.find(b"$")
            if start >= 0:
                hash_at = self.buf.find(b"#", start)
                if hash_at >= 0 and len(self.buf) >= hash_at + 3:
                    payload = self.buf[start + 1:hash_at]
                    self.buf = self.buf[hash_at + 3:]
                    self.sock.sendall(b"+")
                    return payload
            if time.monotonic() > deadline:
                raise TimeoutError("no answer from the GDB stub")
            self.sock.settimeout(max(0.01, deadline - time.monotonic()))
            try:
                self._recv()
            except socket.timeout:
                pass

    def send(self, payload):
        checksum = sum(payload) & 0xFF
        self.sock.sendall(b"$" + payload + b"#%02x" % checksum)

    def command(self, payload):
        self.send(payload)
        return self.packet()

    def stop(self):
        """Stops the VM; returns once the stop reply arrived."""
        self.sock.sendall(b"\x03")
        while True:
            reply = self.packet()
            if reply[:1] in (b"T", b"S"):
                return

    def read(self, addr, length):
        reply = self.command(b"m%x,%x" % (addr, length))
        if reply[:1] == b"E" or len(reply) != 2 * length:
            raise StubError(f"read {length} bytes at {addr:#x}: {reply!r}")
        return bytes.fromhex(reply.decode())

    def write(self, addr, data):
        reply = self.command(b"M%x,%x:" % (addr, len(data)) + data.hex().encode())
        if reply != b"OK":
            raise StubError(f"write at {addr:#x}: {reply!r}")

    def cont(self):
        self.send(b"c")


def connect(port, qemu_pid):
    while True:
        try:
            sock = socket.create_connection(("127.0.0.1", port), timeout=1.0)
            # Every exchange is a few small packets: without this, Nagle and the stub's
            # delayed ACKs hold each one for tens of ms, with the VM stopped meanwhile.
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            return sock
        except OSError:
            if qemu_pid and not os.path.exists(f"/proc/{qemu_pid}"):
                raise SystemExit(0)
            time.sleep(0.05)


def drain(stub, cb, out):
    """Moves whatever up-channel 0 holds to `out` (the VM is stopped)."""
    head = stub.read(cb, UP0 + 20)
    if head[: len(RTT_ID)] != RTT_ID:
        return  # not initialised yet (before the firmware's first log)
    _name, buf, size, write, read = struct.unpack_from("<IIIII", head, UP0)
    if size == 0 or write >= size or read >= size or write == read:
        return
    if write > read:
        data = stub.read(buf + read, write - read)
    else:
        data = stub.read(buf + read, size - read) + (stub.read(buf, write) if write else b"")
    stub.write(cb + UP0 + 16, struct.pack("<I", write))
    out.write(data)
    out.flush()


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    elf, port = sys.argv[1], int(sys.argv[2])
    qemu_pid = sys.argv[3] if len(sys.argv) > 3 else None
    cb = symbol(elf, "_SEGGER_RTT")
    if cb is None:
        raise SystemExit(f"{elf} has no _SEGGER_RTT: not a defmt-rtt firmware")
    out = sys.stdout.buffer
    stub = Stub(connect(port, qemu_pid))
    try:
        stub.stop()
        while True:
            try:
                drain(stub, cb, out)
            except (StubError, TimeoutError) as e:
                # A bad read (or a firmware that broke its control block): say so, leave the
                # VM running, and stop reading rather than halt the firmware.
                print(f"rtt-gdb: {e}; the RTT log stops here", file=sys.stderr)
                stub.cont()
                return
            stub.cont()
            time.sleep(POLL_S)
            stub.stop()
    except (EOFError, ConnectionError, BrokenPipeError):
        pass


if __name__ == "__main__":
    main()
