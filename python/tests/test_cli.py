"""`python -m protolink decode FILE` prints what `protolink decode` prints, byte for byte
(stdout, stderr and exit status)."""

import subprocess

import pytest

from conftest import PROTOLINK, PYTHON, ROOT, TESTDATA


def run(cmd):
    # From the repository root, the cwd of the scripts: the package comes from the install.
    p = subprocess.run(cmd, capture_output=True, cwd=ROOT.parent, timeout=120)
    return p.returncode, p.stdout, p.stderr


@pytest.fixture(scope="module")
def capture(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli") / "uart.pcapng"
    subprocess.run([PROTOLINK, "record", "--from", f"file:{TESTDATA / 'qemu-uart0-aeolus.bin'}",
                    "--proto", "aeolus", "--out", str(path)], check=True, capture_output=True)
    return path


CASES = [
    (["qemu-uart0-aeolus.bin", "--proto", "aeolus"], 1615),
    (["qemu-uart0-aeolus.bin", "--proto", "aeolus", "--json"], 1615),
    (["qemu-uart1-aydp.bin", "--proto", "aydp", "--profile", "spec"], 16),
    (["qemu-uart2-aok.bin", "--proto", "aok", "--side", "device", "--json"], 235),
    (["qemu-uart2-aok.bin", "--proto", "aok", "--side", "pc"], None),
]


@pytest.mark.parametrize("args,lines", CASES)
def test_decode_file_same_bytes(args, lines):
    name, *rest = args
    path = str(TESTDATA / name)
    want = run([PROTOLINK, "decode", "--from", path, *rest])
    got = run([PYTHON, "-m", "protolink", "decode", path, *rest])
    assert got == want
    assert want[0] == 0 and want[1]
    if lines is not None:
        assert len(want[1].splitlines()) == lines
    # --from works as well as a bare FILE.
    assert run([PYTHON, "-m", "protolink", "decode", "--from", path, *rest]) == want


@pytest.mark.parametrize("extra", [[], ["--json"]])
def test_decode_capture_same_bytes(capture, extra):
    want = run([PROTOLINK, "decode", "--from", str(capture), *extra])
    got = run([PYTHON, "-m", "protolink", "decode", str(capture), *extra])
    assert got == want and want[0] == 0
    assert want[1].splitlines()[-1].startswith(b'{"kind":"capture"' if extra else b"capture: frames=2 ")


def test_decode_errors_same_bytes():
    raw = str(TESTDATA / "qemu-uart0-aeolus.bin")
    for args in ([raw], [raw, "--proto", "mavlink"], ["/nonexistent.bin", "--proto", "aeolus"]):
        want = run([PROTOLINK, "decode", "--from", *args])
        got = run([PYTHON, "-m", "protolink", "decode", *args])
        assert got == want and want[0] != 0 and want[2].startswith(b"error: ")


def test_only_decode():
    code, out, err = run([PYTHON, "-m", "protolink", "sim"])
    assert code == 2 and out == b"" and err.startswith(b"usage: python -m protolink decode")
