//! `protolink.aydp`: the AYDP `Decoder` in either profile, and `encode` for every message
//! type (requests and commands to a device included: `SYSTEM_CONTROL`, `SYSTEM_VALUE_UPDATE`,
//! `DIRECT_OUTPUT`).

use aydp_proto::{
    DirectOutputBuilder, EncodeError, Encoder, FixDetailBuilder, FixQuality, Message, OutputEntry,
    Position, Profile, Raw, Satellite, SystemControl, SystemValueUpdate, Timestamp, UpdateMode,
    VesselData, WindDirection, WindSpeed,
};
use protolink::decoders::{AydpDecoder, Decoder as Core};
use protolink::proto::{ProfileArg, Proto, Side};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use serde::de::DeserializeOwned;
use serde_json::{Map, Value, json};

use crate::decoder::{PROFILES, choose, protocol_decoder};
use crate::encode::{self, check_decodes, check_names, data_bytes, invalid, needed, read};
use crate::value;

protocol_decoder!(
    /// The AYDP stream decoder in one profile, as `protolink decode --proto aydp --profile ...`
    /// runs it: resynchronising, every typed message, errors as events. `finish()`: a message
    /// still open is given up (`truncated`) and what followed its start is rescanned.
    AydpPyDecoder,
    "protolink.aydp",
    Proto::Aydp,
    /// `profile`: `"spec"` (the 2016 document: the length counts the whole message,
    /// sub-seconds in ms) or `"reference"` (the released software: data length, µs).
    profile in PROFILES => |p| (p, Side::Device),
    /// The profile: `"spec"` or `"reference"`.
);

/// The message names `encode` takes.
const NAMES: &str = "TIME_SYNC, HEARTBEAT, NO_OP, POSITION, FIX_QUALITY, FIX_DETAIL, \
                     DIRECT_OUTPUT, SYSTEM_VALUE_UPDATE, SYSTEM_CONTROL, WIND_SPEED, \
                     WIND_DIRECTION, VESSEL_DATA, TBD, USER_DEFINED or UNKNOWN";

/// The header time from `time`: `{"seconds": s, "subsec": n}` (the form `meta["time"]` has)
/// or a pair `(s, n)`; none is zero.
fn timestamp(name: &str, time: Option<&Bound<'_, PyAny>>) -> PyResult<Timestamp> {
    let Some(t) = time.filter(|t| !t.is_none()) else {
        return Ok(Timestamp::new(0, 0));
    };
    if let Ok((seconds, subsec)) = t.extract::<(i64, i64)>() {
        return Ok(Timestamp::new(seconds, subsec));
    }
    let Ok(d) = t.cast::<PyDict>() else {
        return Err(PyTypeError::new_err(format!(
            "cannot encode {name}: `time` is a dict {{\"seconds\": ..., \"subsec\": ...}} or a pair (seconds, subsec)"
        )));
    };
    read(name, Value::Object(value::map_from_py(d, "time")?))
}

/// A list message's builder (`FIX_DETAIL`, `DIRECT_OUTPUT`) from the field `key`, its only
/// one: `start` makes it in `scratch`, sized for `head` bytes and the entries at `each` bytes
/// apiece, and `push` adds every entry.
fn built<'s, T, B, S, P>(
    name: &str,
    given: &Map<String, Value>,
    (key, head, each): (&str, usize, usize),
    scratch: &'s mut Vec<u8>,
    (start, push): (S, P),
) -> PyResult<B>
where
    T: DeserializeOwned,
    S: FnOnce(&'s mut [u8]) -> B,
    P: Fn(&mut B, T) -> Result<(), EncodeError>,
{
    check_names(name, given, [key])?;
    let entries: Vec<T> = read(name, needed(name, given, key)?.clone())?;
    *scratch = vec![0u8; head + entries.len() * each];
    let mut b = start(scratch);
    for e in entries {
        push(&mut b, e).map_err(|e| invalid(name, e))?;
    }
    Ok(b)
}

/// One AYDP message, header and checksum included, from its name and its fields as `to_dict()`
/// gives them. `profile` is `"spec"` or `"reference"`; `expedited` picks the short header (by
/// default only for `HEARTBEAT`); `time` is the normal header's time.
#[pyfunction(name = "aydp_encode")]
#[pyo3(signature = (name, /, profile = None, expedited = None, time = None, **fields))]
pub(crate) fn encode_aydp<'py>(
    py: Python<'py>,
    name: &str,
    profile: Option<&Bound<'py, PyAny>>,
    expedited: Option<bool>,
    time: Option<&Bound<'py, PyAny>>,
    fields: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let profile_arg = profile.map_or(Ok(ProfileArg::Spec), |a| choose("profile", a, &PROFILES))?;
    let given = encode::fields(fields)?;
    let fixed = |known: &[&str]| check_names(name, &given, known.iter().copied());
    let mut scratch = Vec::new();
    let message: Message<'_> = match name {
        "TIME_SYNC" | "HEARTBEAT" | "NO_OP" => {
            fixed(&[])?;
            match name {
                "TIME_SYNC" => Message::TimeSync,
                "HEARTBEAT" => Message::Heartbeat,
                _ => Message::NoOp,
            }
        }
        "POSITION" => {
            fixed(&["latitude", "longitude", "altitude"])?;
            Message::Position(read::<Position>(name, Value::Object(given.clone()))?)
        }
        "FIX_QUALITY" => {
            fixed(&["fix_type", "mean_dop", "hdop", "vdop", "satellites"])?;
            Message::FixQuality(read::<FixQuality>(name, Value::Object(given.clone()))?)
        }
        "VESSEL_DATA" => {
            let v = read::<VesselData>(name, Value::Object(given.clone()))?;
            check_names(name, &given, encode::keys(&protolink::render::to_json(&v)))?;
            Message::VesselData(v)
        }
        "WIND_SPEED" | "WIND_DIRECTION" => {
            fixed(&["value"])?;
            let v: f32 = read(name, needed(name, &given, "value")?.clone())?;
            if name == "WIND_SPEED" {
                Message::WindSpeed(WindSpeed(v))
            } else {
                Message::WindDirection(WindDirection(v))
            }
        }
        "FIX_DETAIL" => {
            let list = ("satellites", 1, Satellite::LEN);
            let how = (FixDetailBuilder::new, FixDetailBuilder::push);
            Message::FixDetail(built(name, &given, list, &mut scratch, how)?.finish())
        }
        "DIRECT_OUTPUT" => {
            let list = ("entries", 2, OutputEntry::LEN);
            let how = (DirectOutputBuilder::new, DirectOutputBuilder::push);
            Message::DirectOutput(built(name, &given, list, &mut scratch, how)?.finish())
        }
        "SYSTEM_VALUE_UPDATE" => {
            fixed(&["address", "mode", "data"])?;
            let address: u16 = read(name, needed(name, &given, "address")?.clone())?;
            let mode: UpdateMode = read(name, needed(name, &given, "mode")?.clone())?;
            scratch = data_bytes(name, "data", needed(name, &given, "data")?)?;
            Message::SystemValueUpdate(SystemValueUpdate {
                address,
                mode,
                data: &scratch,
            })
        }
        "SYSTEM_CONTROL" => {
            let command = needed(name, &given, "command")?;
            let control = match command.as_str() {
                Some("StoreConfiguration") => {
                    fixed(&["command"])?;
                    json!("StoreConfiguration")
                }
                Some("RequestData") => {
                    fixed(&["command", "address"])?;
                    json!({ "RequestData": { "address": needed(name, &given, "address")? } })
                }
                _ => {
                    return Err(invalid(
                        name,
                        format!(
                            "`command` is \"RequestData\" (with `address`) or \"StoreConfiguration\", not {command}"
                        ),
                    ));
                }
            };
            Message::SystemControl(read::<SystemControl>(name, control)?)
        }
        "TBD" | "USER_DEFINED" | "UNKNOWN" => {
            fixed(&["msg_type", "data"])?;
            let msg_type: u8 = read(name, needed(name, &given, "msg_type")?.clone())?;
            scratch = data_bytes(name, "data", needed(name, &given, "data")?)?;
            let raw = Raw {
                msg_type,
                data: &scratch,
            };
            match name {
                "TBD" => Message::Tbd(raw),
                "USER_DEFINED" => Message::UserDefined(raw),
                _ => Message::Unknown(raw),
            }
        }
        _ => {
            return Err(PyValueError::new_err(format!(
                "AYDP has no message '{name}': the names are {NAMES}"
            )));
        }
    };
    let profile: Profile = profile_arg.into();
    let expedited = expedited.unwrap_or(name == "HEARTBEAT");
    let header_time = if expedited {
        if time.is_some_and(|t| !t.is_none()) {
            return Err(invalid(
                name,
                "an expedited message has no header time (leave `time` out)",
            ));
        }
        None
    } else {
        Some(timestamp(name, time)?)
    };
    let encoder = Encoder::new(profile);
    let mut buf = vec![0u8; encoder.frame_len(&message, expedited)];
    let n = encoder
        .encode(&message, header_time, &mut buf)
        .map_err(|e| invalid(name, e))?;
    buf.truncate(n);
    // A reference type in the spec profile, a heartbeat sent normal, a list too long for a
    // decoder: refused.
    let decoder = Core::Aydp(AydpDecoder::new(profile));
    check_decodes(
        name,
        &buf,
        decoder,
        " in this profile and header form",
        false,
    )?;
    Ok(PyBytes::new(py, &buf))
}
