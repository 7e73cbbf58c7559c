#!/usr/bin/env python3
"""Compares what the C API decodes with what `protolink decode --json` decodes.

compare.py HOST_TEST PROTOLINK PROTO:FILE...

For each file, `HOST_TEST dump PROTO FILE` (the C API) and `protolink decode --json` (the Rust
crates through the host tool) must give the same sequence of messages and errors, every
message with the same name, the same place in the input (offset and wire length) and the same
value in every field, every error at the same offset, and the same decoder counters.
protolink's renderings (enum names, slot and action names, texts) are turned back into the
raw values the C structs carry before comparing. f64 fields must be equal exactly; f32 fields
equal as f32. Exit status 1 with one line per difference.
"""
import json
import struct
import subprocess
import sys

F64_FIELDS = {"timestamp_ms", "latitude", "longitude", "lat_deg", "lon_deg"}
CALIBRATION = {"NoCalibration": 1, "JustFinished": 2, "Ok": 3, "Calibrating": 4,
               "TooFewData": -1, "FieldWeak": -2, "FieldDistorted": -3, "ErrorVeryHigh": -4}
ACTIONS = ["none", "pause", "hold-and-climb", "hold-and-sink", "fly-and-climb", "fly-and-sink",
           "set-fly-speed"]
ADDRESS_TYPES = ["AdsbIcao", "AdsbSelfAssigned", "TisbIcao", "TisbTrackFile", "SurfaceVehicle",
                 "GroundStationBeacon"]
EMERGENCIES = ["None", "General", "Medical", "MinimumFuel", "NoCommunication",
               "UnlawfulInterference", "Downed"]
TRACKS = {"TrueTrack": 1, "MagneticHeading": 2, "TrueHeading": 3}
HEADINGS = {"True": 1, "Magnetic": 2}
PROTOLINK_ARGS = {
    "aeolus": ["--proto", "aeolus"],
    "aydp-spec": ["--proto", "aydp", "--profile", "spec"],
    "aydp-reference": ["--proto", "aydp", "--profile", "reference"],
    "aok-pc": ["--proto", "aok", "--side", "pc"],
    "aok-device": ["--proto", "aok", "--side", "device"],
    "gdl90": ["--proto", "gdl90"],
}


def enum_value(v, names):
    """An enum as serde writes it ("Name" or {"Reserved": n} / {"Other": n}) as its number."""
    if isinstance(v, str):
        return names[v] if isinstance(names, dict) else names.index(v)
    (_, n), = v.items()
    return n


def slot_wire(name):
    return {"poi": 31, "ram-poi": 254, "fbc": 255}.get(name) or int(name) - 1


def action_raw(text):
    kind, value = text.split(":")
    if kind == "raw":
        return int(value, 16)
    return (ACTIONS.index(kind) << 16) | ((int(value) + 32768) & 0xFFFF)


def padded_hex(text, size, pad):
    return text.encode().ljust(size, pad).hex()


def normalise(proto, name, f):
    """protolink's fields of one message, in the shape host_test prints."""
    f = dict(f)
    if proto == "aeolus":
        if name in ("TOAST", "COMMAND"):
            text_hex = f.get("hex") or f["text"].encode().hex()
            f = {"text_hex": text_hex}
        if name == "COMPASS":
            f["calibration"] = enum_value(f["calibration"], CALIBRATION)
    elif proto.startswith("aydp"):
        if name == "SYSTEM_VALUE_UPDATE":
            mode = f.pop("mode")
            if mode == "Single":
                f["mode_code"], f["mode_field"] = 1, 0
            else:
                (kind, inner), = mode.items()
                f["mode_code"] = {"Array": 2, "Element": 3}[kind]
                (f["mode_field"],) = inner.values()
        if name in ("TBD", "USER_DEFINED", "UNKNOWN") and "value" in f:
            f = f["value"]
    elif proto.startswith("aok"):
        if "slot" in f:
            f["slot_wire"] = slot_wire(f.pop("slot"))
        for a in ("action1", "action2"):
            if a in f:
                f[a + "_raw"] = action_raw(f.pop(a))
    elif proto == "gdl90":
        if name in ("OWNSHIP", "TRAFFIC"):
            f["address_type"] = enum_value(f["address_type"], ADDRESS_TYPES)
            f["emergency"] = enum_value(f["emergency"], EMERGENCIES)
            track = f.pop("track")
            f["track_kind"], f["track_deg"] = (0, None) if track is None else (
                TRACKS[next(iter(track))], next(iter(track.values())))
            f["call_sign_hex"] = padded_hex(f.pop("call_sign"), 8, b" ")
        if name == "FOREFLIGHT_ID":
            f["name_hex"] = padded_hex(f.pop("name"), 8, b"\0")
            f["long_name_hex"] = padded_hex(f.pop("long_name"), 16, b"\0")
            f["altitude_datum"] = enum_value(f["altitude_datum"], ["Wgs84Ellipsoid", "Msl"])
        if name == "FOREFLIGHT_AHRS":
            heading = f.pop("heading")
            f["heading_kind"], f["heading_deg"] = (0, None) if heading is None else (
                HEADINGS[next(iter(heading))], next(iter(heading.values())))
        if name == "UNKNOWN":
            f = {"data": f["data"] if isinstance(f["data"], str) else bytes(f["data"]).hex()}
    return f


def same(key, a, b):
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(k, a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(key, x, y) for x, y in zip(a, b))
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if a == b:
            return True
        return key not in F64_FIELDS and struct.pack("<f", a) == struct.pack("<f", b)
    return a == b


def events(lines):
    out, summary = [], None
    for line in lines:
        e = json.loads(line)
        if e["kind"] == "summary":
            summary = e["counters"]
        else:
            out.append(e)
    return out, summary


def compare(host_test, protolink, proto, path):
    c_out = subprocess.run([host_test, "dump", proto, path], capture_output=True, text=True)
    if c_out.returncode != 0:
        return [f"{path}: host_test dump {proto} failed: {c_out.stderr.strip()}"]
    r_out = subprocess.run([protolink, "decode", *PROTOLINK_ARGS[proto], "--from", f"file:{path}",
                            "--json"], capture_output=True, text=True, check=True)
    c_events, c_counters = events(c_out.stdout.splitlines())
    r_events, r_counters = events(r_out.stdout.splitlines())
    problems = []
    if len(c_events) != len(r_events):
        problems.append(f"{path} ({proto}): {len(c_events)} events from C, {len(r_events)} from protolink")
    for i, (c, r) in enumerate(zip(c_events, r_events)):
        where = f"{path} ({proto}) event {i}"
        if c["kind"] != r["kind"]:
            problems.append(f"{where}: C {c['kind']}, protolink {r['kind']} ({r.get('error', '')})")
            continue
        if c["kind"] != "message":
            # An error's place: the first byte of what it condemns and their wire length.
            for meta in ("offset", "len"):
                if c.get(meta) != r.get(meta):
                    problems.append(f"{where}: error {meta} C {c.get(meta)}, protolink {r.get(meta)}")
            continue
        if c["name"] != r["name"]:
            problems.append(f"{where}: C {c['name']}, protolink {r['name']}")
            continue
        # "offset" and "len": the message's first byte and wire length (the C struct's offset
        # and wire_len).
        for meta in ("id", "type", "expedited", "crc", "time", "offset", "len"):
            if meta in r and not same(meta, c.get(meta), r[meta]):
                problems.append(f"{where} {c['name']}: {meta} C {c.get(meta)}, protolink {r[meta]}")
        want = normalise(proto, r["name"], r["fields"])
        if not same("", c["fields"], want):
            problems.append(f"{where} {c['name']}: fields differ\n  C:         {c['fields']}\n  protolink: {want}")
    for key, value in (c_counters or {}).items():
        if r_counters is None or key not in r_counters:
            problems.append(f"{path} ({proto}): counter {key} missing from protolink")
        elif r_counters[key] != value:
            problems.append(f"{path} ({proto}): counter {key} C {value}, protolink {r_counters[key]}")
    messages = sum(e["kind"] == "message" for e in c_events)
    print(f"{proto:15} {path}: {messages} messages, {len(c_events) - messages} errors, "
          f"{len(c_counters or {})} counters: {'same' if not problems else 'DIFFERENT'}")
    return problems


def main():
    host_test, protolink, *pairs = sys.argv[1:]
    problems = []
    for pair in pairs:
        proto, path = pair.split(":", 1)
        problems += compare(host_test, protolink, proto, path)
    for p in problems:
        print(p, file=sys.stderr)
    sys.exit(1 if problems else 0)


main()
