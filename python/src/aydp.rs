//! `protolink.aydp`: the AYDP `Decoder` in either profile, and `encode` for every message
//! type (requests and commands to a device included: `SYSTEM_CONTROL`, `SYSTEM_VALUE_UPDATE`,
//! `DIRECT_OUTPUT`).

use aydp_proto::{
    DirectOutputBuilder, Encoder, FixDetailBuilder, FixQuality, Message, OutputEntry, Position,
    Profile, Raw, Satellite, SystemControl, SystemValueUpdate, Timestamp, UpdateMode, VesselData,
    WindDirection, WindSpeed,
};
use protolink::decoders::{AydpDecoder, Decoder as Core};
use protolink::proto::{ProfileArg, Proto, Side};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use serde_json::{Map, Value, json};

use crate::decoder::{Decoder, choice, choose};
use crate::encode::{self, check_decodes, check_names, data_bytes, invalid, needed, read};
use crate::stream::Stream;
use crate::value;

/// The profiles by name.
const PROFILES: [(&str, ProfileArg); 2] = [
    ("spec", ProfileArg::Spec),
    ("reference", ProfileArg::Reference),
];

/// The AYDP stream decoder in one profile, as `protolink decode --proto aydp --profile ...`
/// runs it: resynchronising, every typed message, errors as events. `finish()`: a message
/// still open is given up (`truncated`) and what followed its start is rescanned.
#[pyclass(extends = Decoder, module = "protolink.aydp", name = "Decoder")]
#[derive(Debug)]
pub(crate) struct AydpPyDecoder {
    profile: &'static str,
}

#[pymethods]
impl AydpPyDecoder {
    /// `profile`: `"spec"` (the 2016 document: the length counts the whole message,
    /// sub-seconds in ms) or `"reference"` (the released software: data length, µs).
    #[new]
    #[pyo3(signature = (profile = None))]
    fn new(profile: Option<&Bound<'_, PyAny>>) -> PyResult<PyClassInitializer<Self>> {
        let (profile, p) = match profile {
            Some(a) => choice("profile", a, &PROFILES)?,
            None => ("spec", ProfileArg::Spec),
        };
        let stream = Stream::new(Proto::Aydp, p, Side::Device);
        let base = Decoder::new("protolink.aydp.Decoder", stream, Some(("profile", profile)));
        Ok(base.add_subclass(AydpPyDecoder { profile }))
    }

    /// The profile: `"spec"` or `"reference"`.
    #[getter]
    fn profile(&self) -> &'static str {
        self.profile
    }
}

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

/// A list field (`satellites`, `entries`) of `T`s.
fn list<T: serde::de::DeserializeOwned>(
    name: &str,
    given: &Map<String, Value>,
    key: &str,
) -> PyResult<Vec<T>> {
    read(name, needed(name, given, key)?.clone())
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
    let mut scratch: Vec<u8>;
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
            fixed(&["satellites"])?;
            let sats: Vec<Satellite> = list(name, &given, "satellites")?;
            scratch = vec![0u8; 1 + sats.len() * Satellite::LEN];
            let mut b = FixDetailBuilder::new(&mut scratch);
            for s in sats {
                b.push(s).map_err(|e| invalid(name, e))?;
            }
            Message::FixDetail(b.finish())
        }
        "DIRECT_OUTPUT" => {
            fixed(&["entries"])?;
            let entries: Vec<OutputEntry> = list(name, &given, "entries")?;
            scratch = vec![0u8; 2 + entries.len() * OutputEntry::LEN];
            let mut b = DirectOutputBuilder::new(&mut scratch);
            for e in entries {
                b.push(e).map_err(|e| invalid(name, e))?;
            }
            Message::DirectOutput(b.finish())
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
