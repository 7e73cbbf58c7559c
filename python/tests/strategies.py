"""The fields of every message type of AEOLUS, AYDP and AOK as hypothesis strategies, each
type's range (f32 fields as f32), and streams that hold one message of every type a decoder
reads: what test_roundtrip.py, test_frames_agree.py and test_field_names.py draw from."""

import struct

from hypothesis import strategies as st

from protolink import aeolus, aok, aydp

u8 = st.integers(0, 255)
u16 = st.integers(0, 0xFFFF)
u32 = st.integers(0, 0xFFFF_FFFF)
i16 = st.integers(-0x8000, 0x7FFF)
i32 = st.integers(-0x8000_0000, 0x7FFF_FFFF)
f32 = st.floats(width=32, allow_nan=False, allow_infinity=False)
flag = st.booleans()


def json_f64(x):
    """The value `protolink decode --json` (and so the package) gives an f64 field holding x:
    the host tool writes every float that is exactly an f32 as the f32's shortest decimal
    (protolink::render::to_json), so 2**-24, exact in f32, reads 5.9604645e-08."""
    try:
        exact = struct.unpack("<f", struct.pack("<f", x))[0] == x
    except OverflowError:
        return x
    if not exact:
        return x
    for digits in range(1, 18):
        short = float(f"{x:.{digits}g}")
        if struct.pack("<f", short) == struct.pack("<f", x):
            return short
    return x


# f64 fields: the values the JSON rendering keeps as they are (see test_f64_exactly_f32).
f64 = st.floats(allow_nan=False, allow_infinity=False).filter(lambda x: json_f64(x) == x)


def uflt16():
    """A finite, non-negative IEEE binary16 value (AYDP's uflt16)."""
    return st.integers(0, 0x7BFF).map(lambda b: struct.unpack("<e", struct.pack("<H", b))[0])



# ---------------------------------------------------------------- AEOLUS

def motion(*names):
    return st.fixed_dictionaries({"valid": flag, "timestamp_ms": f64, **{n: f32 for n in names}})


CALIBRATION = st.one_of(
    st.sampled_from(["NoCalibration", "JustFinished", "Ok", "Calibrating", "TooFewData",
                     "FieldWeak", "FieldDistorted", "ErrorVeryHigh"]),
    st.integers(-128, 127).filter(lambda v: v not in (1, 2, 3, 4, -1, -2, -3, -4)).map(lambda v: {"Other": v}),
)

AEOLUS = {
    "AEOLUSINFO": st.fixed_dictionaries({
        "model": u8, "firmware": st.lists(u8, min_size=3, max_size=3), "mac": st.lists(u8, min_size=6, max_size=6)}),
    "PRESSURE": motion("static_mbar", "pitot_mbar", "airspeed_mps"),
    "GYRO": motion("x", "y", "z"),
    "ACCEL": motion("x", "y", "z"),
    "MAGNET": motion("x", "y", "z"),
    "TEMP": motion("celsius"),
    "GPS": st.fixed_dictionaries({
        "valid": flag, "has_fix": flag, "satellites": u8, "timestamp_ms": f64, "latitude_deg": f32,
        "longitude_deg": f32, "altitude_m": f32, "ground_speed_mps": f32}),
    "ATTITUDE": motion("roll_rad", "pitch_rad", "yaw_rad", "slip_ball", "turn_coordinator", "qx", "qy", "qz", "qw"),
    "COMPASS": st.fixed_dictionaries({
        "valid": flag, "calibration": CALIBRATION, "has_value": flag, "calibration_percent": u8,
        "calibration_remaining": u8, "timestamp_ms": f64, "heading_deg": f32,
        "soft_iron": st.lists(f32, min_size=3, max_size=3), "hard_iron": st.lists(f32, min_size=9, max_size=9)}),
    "WIND": motion("speed_mps", "direction_deg"),
    "SETTIME": st.fixed_dictionaries({
        k: u8 for k in ("year_since_1900", "month0", "day", "hour", "minute", "second")}),
    "CALIBINFO": st.binary(min_size=32, max_size=32).map(lambda b: {"len": 32, "data": b.hex()}),
    "DEBUGINFO": st.binary(min_size=208, max_size=208).map(lambda b: {"len": 208, "data": b.hex()}),
    "LOG": st.binary(max_size=400).map(lambda b: {"len": len(b), "data": b.hex()}),
    "TOAST": st.text(max_size=40).filter(lambda t: "\0" not in t and len(t.encode()) <= 120).map(lambda t: {"text": t}),
    "COMMAND": st.binary(max_size=120).filter(lambda b: 0 not in b).map(lambda b: {"hex": b.hex()}),
}
KNOWN_IDS = {51, 61, 62, 63, 64, 65, 66, 71, 72, 73, 75, 76, 81, 82, 11, 12}


# ---------------------------------------------------------------- AYDP

SATELLITE = st.fixed_dictionaries({"id": u8, "azimuth": uflt16(), "elevation": uflt16(), "snr": uflt16()})
ENTRY = st.fixed_dictionaries({"device": u8, "channel": u8, "value": f32})
MODE = st.one_of(st.just("Single"), u32.map(lambda n: {"Array": {"count": n}}),
                 u32.map(lambda n: {"Element": {"index": n}}))

BOTH = {
    "POSITION": st.fixed_dictionaries({"latitude": f64, "longitude": f64, "altitude": f32}),
    "FIX_QUALITY": st.fixed_dictionaries({
        "fix_type": u8, "mean_dop": uflt16(), "hdop": uflt16(), "vdop": uflt16(), "satellites": u8}),
    "FIX_DETAIL": st.lists(SATELLITE, max_size=8).map(lambda s: {"satellites": s}),
    "DIRECT_OUTPUT": st.lists(ENTRY, max_size=8).map(lambda e: {"entries": e}),
    "SYSTEM_VALUE_UPDATE": st.fixed_dictionaries({
        "address": u16, "mode": MODE, "data": st.binary(max_size=40).map(bytes.hex)}),
    "SYSTEM_CONTROL": st.one_of(
        st.just({"command": "StoreConfiguration"}),
        u16.map(lambda a: {"command": "RequestData", "address": a})),
    "USER_DEFINED": st.fixed_dictionaries({
        "msg_type": st.integers(100, 126), "data": st.binary(max_size=40).map(bytes.hex)}),
}
SPEC = {
    **BOTH,
    "TIME_SYNC": st.just({}),
    "HEARTBEAT": st.just({}),
    "TBD": st.fixed_dictionaries({"msg_type": st.sampled_from([1, 2, 6]), "data": st.binary(max_size=40).map(bytes.hex)}),
    "UNKNOWN": st.fixed_dictionaries({
        "msg_type": st.sampled_from([10, 11, 17, 50, 99]), "data": st.binary(max_size=40).map(bytes.hex)}),
}
REFERENCE = {
    **BOTH,
    "NO_OP": st.just({}),
    "WIND_SPEED": f32.map(lambda v: {"value": v}),
    "WIND_DIRECTION": f32.map(lambda v: {"value": v}),
    "VESSEL_DATA": st.fixed_dictionaries({
        "roll": f32, "pitch": f32, "heading": f32, "roll_rate": f32, "pitch_rate": f32, "heading_rate": f32,
        "latitude": f64, "longitude": f64, "track": f32, "speed_over_ground": f32, "fix_type": i32,
        "satellites": i32, "mean_dop": f32, "hdop": f32, "vdop": f32}),
    "UNKNOWN": st.fixed_dictionaries({
        "msg_type": st.sampled_from([6, 10, 16, 18, 99]), "data": st.binary(max_size=40).map(bytes.hex)}),
}
SUBSEC = {"spec": 999, "reference": 999_999}


# ---------------------------------------------------------------- AOK

SLOT = st.one_of(st.integers(1, 31).map(str), st.sampled_from(["poi", "ram-poi", "fbc"]))
ACTION = st.one_of(
    st.tuples(st.sampled_from(["none", "pause", "hold-and-climb", "hold-and-sink", "fly-and-climb",
                               "fly-and-sink", "set-fly-speed"]), i16).map(lambda t: f"{t[0]}:{t[1]}"),
    st.integers(7, 0xFFFF).flatmap(lambda a: u16.map(lambda v: f"raw:{(a << 16) | v:#010x}")),
)
WAYPOINT = st.fixed_dictionaries({
    "slot": SLOT, "longitude": i32, "latitude": i32, "action1": ACTION, "action2": ACTION})
STICK = st.integers(-200, 200)

COMMANDS = {
    "DEBUG_OFF": st.just({}),
    "DEBUG_ON": st.just({}),
    "RESET": st.just({}),
    "SAVE_WAYPOINTS": st.just({}),
    "LOAD_WAYPOINTS": st.just({}),
    "LOAD_SET": u8.map(lambda n: {"set": n}),
    "SAVE_SET": u8.map(lambda n: {"set": n}),
    "START_SET": u8.map(lambda n: {"set": n}),
    "SET_PARAMETER": st.fixed_dictionaries({"number": u8, "value": i32}),
    "READ_PARAMETER": u8.map(lambda n: {"number": n}),
    "BULK_READ": u8.map(lambda n: {"first": n}),
    "MOTOR_TEST": st.fixed_dictionaries({"motor": st.integers(1, 12), "value": u8}),
    "SET_WAYPOINT": WAYPOINT,
    "READ_WAYPOINT": SLOT.map(lambda s: {"slot": s}),
    "EXTERNAL_CONTROL": st.fixed_dictionaries({
        "roll": STICK, "nick": STICK, "yaw": STICK, "pitch": i16, "expiry_ms": u16}),
}
MESSAGES = {
    "DEBUG": st.fixed_dictionaries({"number": u8, "value": i32}),
    "PARAMETER": st.fixed_dictionaries({"number": u8, "value": i32}),
    "WAYPOINT": WAYPOINT,
}


# ---------------------------------------------------------------- streams

KINDS = ["aeolus", "aydp-spec", "aydp-reference", "aok-pc", "aok-device"]


@st.composite
def aydp_header(draw, profile, name):
    """`expedited` and `time` of an AYDP message: HEARTBEAT expedited, the reference profile
    never; otherwise either, with a drawn time when the header is a normal one."""
    expedited = name == "HEARTBEAT" or (profile == "spec" and name != "TIME_SYNC" and draw(flag))
    if expedited:
        return True, None
    return False, {"seconds": draw(st.integers(0, 0x7FFF_FFFF)), "subsec": draw(st.integers(0, SUBSEC[profile]))}


@st.composite
def every_type(draw, kind):
    """One frame of every message type that `kind`'s decoder reads (`aeolus`, `aydp-spec`,
    `aydp-reference`, `aok-pc`, `aok-device`; AEOLUS's UNKNOWN too), in a drawn order, with
    drawn fields: a list of (name, frame)."""
    if kind == "aeolus":
        table = {**AEOLUS, "UNKNOWN": st.fixed_dictionaries({
            "id": st.integers(0, 255).filter(lambda i: i not in KNOWN_IDS), "data": st.binary(max_size=40)})}
    elif kind.startswith("aydp"):
        table = SPEC if kind == "aydp-spec" else REFERENCE
    else:
        table = COMMANDS if kind == "aok-pc" else MESSAGES
    out = []
    for name in draw(st.permutations(sorted(table))):
        fields = draw(table[name])
        if kind == "aeolus":
            out.append((name, aeolus.encode(name, **fields)))
        elif kind.startswith("aydp"):
            profile = kind.split("-")[1]
            expedited, time = draw(aydp_header(profile, name))
            out.append((name, aydp.encode(name, profile=profile, expedited=expedited, time=time, **fields)))
        else:
            out.append((name, aok.encode(name, **fields)))
    return out
