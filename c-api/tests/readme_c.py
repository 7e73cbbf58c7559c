#!/usr/bin/env python3
"""Compiles and runs the root README's C examples ("Use it from C"), as printed.

    readme_c.py OUT_DIR ARCHIVE PROTOLINK

Takes the section's ```c blocks (the receive loop, then the encode) into OUT_DIR, builds them
inside c-api/tests/c/readme_harness.c against c-api/include/protolink.h and the host ARCHIVE
(libprotolink_c.a) with gcc, C11, -Wall -Wextra -Werror -pedantic, AddressSanitizer and
UndefinedBehaviorSanitizer, and runs the receive loop over testdata/qemu-uart0-aeolus.bin.
Every GYRO's rates must equal `PROTOLINK decode --json`'s, in order and as f32; no error may
be counted; the encode example's frame must decode back to its command. Exit status 1 with
what differed.
"""
import json
import pathlib
import re
import struct
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
CAPTURE = ROOT / "testdata" / "qemu-uart0-aeolus.bin"


def blocks():
    """The ```c blocks of the README's "Use it from C" section."""
    text = (ROOT / "README.md").read_text()
    start = text.find("\n## Use it from C\n")
    if start < 0:
        sys.exit("readme_c: README.md has no section 'Use it from C'")
    end = text.find("\n## ", start + 1)
    section = text[start:end if end > 0 else len(text)]
    return re.findall(r"```c\n(.*?)```", section, re.S)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    out, archive, protolink = pathlib.Path(argv[0]), argv[1], argv[2]
    found = blocks()
    if len(found) != 2:
        sys.exit(f"readme_c: 'Use it from C' has {len(found)} C blocks; this test knows two "
                 "(the receive loop, the encode)")
    out.mkdir(parents=True, exist_ok=True)
    (out / "readme_receive.c").write_text(found[0])
    (out / "readme_encode.c").write_text(found[1])
    exe = out / "readme"
    build = subprocess.run(
        ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic",
         "-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer",
         "-g", "-O1", f"-I{out}", f"-I{ROOT / 'c-api' / 'include'}",
         str(ROOT / "c-api" / "tests" / "c" / "readme_harness.c"), archive,
         "-lpthread", "-ldl", "-lm", "-o", str(exe)])
    if build.returncode != 0:
        sys.exit("readme_c: the README's C examples do not compile against the header "
                 "(gcc's errors above)")
    run = subprocess.run([str(exe), str(CAPTURE)], capture_output=True, text=True)
    lines = run.stdout.splitlines()
    got = [tuple(float(v) for v in l.split()[1:]) for l in lines if l.startswith("gyro ")]
    errors = [l for l in lines if l.startswith("error ")]
    end = [l for l in lines if l.startswith("end ")]

    decoded = subprocess.run(
        [protolink, "decode", "--proto", "aeolus", "--from", str(CAPTURE), "--json"],
        capture_output=True, text=True, check=True).stdout.splitlines()
    want = []
    for line in decoded:
        event = json.loads(line)
        if event.get("kind") == "message" and event.get("name") == "GYRO":
            fields = event["fields"]
            want.append((f32(fields["x"]), f32(fields["y"]), f32(fields["z"])))

    problems = []
    if run.returncode != 0:
        problems.append(f"the README's examples exited with {run.returncode}: {run.stderr[-2000:]}")
    if not end or "encode ok" not in end[0]:
        problems.append(f"the encode example's frame did not decode back to its command: {end}")
    if errors:
        problems.append(f"{len(errors)} errors counted, none expected: {errors[:5]}")
    if len(got) != len(want):
        problems.append(f"{len(got)} GYRO rates from the receive loop, {len(want)} from protolink")
    for i, (g, w) in enumerate(zip(got, want)):
        if tuple(f32(v) for v in g) != w:
            problems.append(f"GYRO {i}: the receive loop gave {g}, protolink {w}")
            break
    if problems:
        print("\n".join(f"readme_c: {p}" for p in problems))
        sys.exit(1)
    print(f"readme_c: the README's C examples compile (C11, -Wall -Wextra -Werror -pedantic) and "
          f"run: {len(got)} GYRO rates equal protolink's over {end[0].split('reads ')[1].split()[0]} "
          "reads of 1-64 bytes, no error, the encoded command decodes back")


if __name__ == "__main__":
    main(sys.argv[1:])
