//! A typed message's fields into its table row, from its own types: each protocol's message
//! enum matched once, each variant's value written through serde at its own widths (`u8` as
//! UInt8, `f32` as Float32, ...), and the few fields that `decode` shows by name (AOK slots and
//! actions, AYDP system-control commands) or as hex (raw `data`) written as the texts it shows.
//! No JSON value on the way: a list (AYDP output entries and satellites) is a List column per
//! field of its items, declared from a sample item with the table.

use serde::Serialize;

use super::column::Scalar;
use super::row::{Ints, write_fields, write_list};
use super::table::Table;
use crate::decoders::{action_name, slot_name};
use crate::render::{escape_text, hex, is_clean_text};

/// A value's fields at their own widths.
fn own<T: Serialize + ?Sized>(table: &mut Table, value: &T) {
    write_fields(table, value, Ints::Own, None);
}

/// A text message's `text` (escaped) and, for one that is not clean UTF-8, `hex` (a column of
/// every row of its table, null where the text is clean).
fn text(table: &mut Table, bytes: &[u8]) {
    table.set_static("text", Scalar::Str(&escape_text(bytes)));
    let raw = (!is_clean_text(bytes)).then(|| hex(bytes));
    table.set_typed("hex", raw.as_deref().map(Scalar::Str), Scalar::Str(""));
}

/// Raw data: its `len` and its bytes as hex.
fn raw(table: &mut Table, data: &[u8]) {
    table.set_static(
        "len",
        Scalar::I64(i64::try_from(data.len()).unwrap_or(i64::MAX)),
    );
    table.set_static("data", Scalar::Str(&hex(data)));
}

/// An AEOLUS message's fields.
pub(crate) fn aeolus(table: &mut Table, message: &aeolus_proto::message::Message<'_>) {
    use aeolus_proto::message::Message as M;
    match message {
        M::AeolusInfo(v) => own(table, v),
        M::Pressure(v) => own(table, v),
        M::Gyro(v) => own(table, v),
        M::Accel(v) => own(table, v),
        M::Magnet(v) => own(table, v),
        M::Temp(v) => own(table, v),
        M::Gps(v) => own(table, v),
        M::Attitude(v) => own(table, v),
        M::Compass(v) => own(table, v),
        M::Wind(v) => own(table, v),
        M::SetTime(v) => own(table, v),
        M::Toast(t) | M::Command(t) => text(table, t.as_bytes()),
        M::CalibInfo(d) | M::DebugInfo(d) | M::Log(d) | M::Unknown { data: d, .. } => raw(table, d),
    }
}

/// An AYDP message's fields.
pub(crate) fn aydp(table: &mut Table, message: &aydp_proto::Message<'_>) {
    use aydp_proto::{Message as M, SystemControl, UpdateMode};
    match message {
        M::TimeSync | M::Heartbeat | M::NoOp => {}
        M::Position(v) => own(table, v),
        M::FixQuality(v) => own(table, v),
        M::FixDetail(d) => write_list(
            table,
            "satellites",
            d.satellites(),
            &aydp_proto::Satellite::default(),
        ),
        M::DirectOutput(d) => write_list(
            table,
            "entries",
            d.entries(),
            &aydp_proto::OutputEntry::default(),
        ),
        M::SystemValueUpdate(u) => {
            table.set_static("address", Scalar::U16(u.address));
            // The mode as `decode` renders it, flattened: a mode without data by name, the
            // others' number under their own column, each column in every row.
            let (single, count, index) = match u.mode {
                UpdateMode::Single => (Some("Single"), None, None),
                UpdateMode::Array { count } => (None, Some(count), None),
                UpdateMode::Element { index } => (None, None, Some(index)),
            };
            table.set_typed("mode", single.map(Scalar::Str), Scalar::Str(""));
            table.set_typed("mode.Array.count", count.map(Scalar::U32), Scalar::U32(0));
            table.set_typed("mode.Element.index", index.map(Scalar::U32), Scalar::U32(0));
            table.set_static("data", Scalar::Str(&hex(u.data)));
        }
        M::SystemControl(c) => {
            let (command, address) = match c {
                SystemControl::RequestData { address } => ("RequestData", Some(*address)),
                SystemControl::StoreConfiguration => ("StoreConfiguration", None),
            };
            table.set_static("command", Scalar::Str(command));
            table.set_typed("address", address.map(Scalar::U16), Scalar::U16(0));
        }
        // A bare number: its column `value`.
        M::WindSpeed(v) => own(table, v),
        M::WindDirection(v) => own(table, v),
        M::VesselData(v) => own(table, v),
        M::Tbd(r) | M::UserDefined(r) | M::Unknown(r) => {
            table.set_static("msg_type", Scalar::U8(r.msg_type));
            table.set_static("data", Scalar::Str(&hex(r.data)));
        }
    }
}

/// An AOK waypoint: its slot and actions by name, its coordinates raw.
fn waypoint(table: &mut Table, w: &aok_proto::Waypoint) {
    table.set_static("slot", Scalar::Str(&slot_name(w.slot)));
    table.set_static("longitude", Scalar::I32(w.longitude));
    table.set_static("latitude", Scalar::I32(w.latitude));
    table.set_static("action1", Scalar::Str(&action_name(w.action1)));
    table.set_static("action2", Scalar::Str(&action_name(w.action2)));
}

/// What an AOK device sends: its fields.
pub(crate) fn aok_message(table: &mut Table, message: &aok_proto::Message) {
    use aok_proto::Message as M;
    match message {
        M::Debug(v) => own(table, v),
        M::Ack(a) => own(table, a),
        M::Parameter(v) => own(table, v),
        M::Waypoint(w) => waypoint(table, w),
    }
}

/// What an AOK PC sends: its fields.
pub(crate) fn aok_command(table: &mut Table, command: &aok_proto::Command) {
    use aok_proto::Command as C;
    match command {
        C::DebugOff | C::DebugOn | C::Reset | C::SaveWaypoints | C::LoadWaypoints => {}
        C::LoadSet(n) | C::SaveSet(n) | C::StartSet(n) => table.set_static("set", Scalar::U8(*n)),
        C::SetParameter(v) => own(table, v),
        C::ReadParameter(n) => table.set_static("number", Scalar::U8(*n)),
        C::BulkRead(n) => table.set_static("first", Scalar::U8(*n)),
        C::MotorTest(v) => own(table, v),
        C::SetWaypoint(w) => waypoint(table, w),
        C::ReadWaypoint(s) => table.set_static("slot", Scalar::Str(&slot_name(*s))),
        C::ExternalControl(v) => own(table, v),
    }
}

/// A GDL90 message's fields. The first message of a type declares its table's columns from
/// samples of the type: every optional field present, every variant of its enums, so that the
/// columns and their types do not depend on what the messages hold.
pub(crate) fn gdl90(table: &mut Table, message: &gdl90_proto::message::Message<'_>) {
    use gdl90_proto::message::Message as M;
    if !table.declared() {
        table.declare_like(|t| gdl90_samples(t, message));
    }
    match message {
        M::Heartbeat(v) => own(table, v),
        M::Ownship(v) | M::Traffic(v) => own(table, v),
        M::GeoAltitude(v) => own(table, v),
        M::ForeFlightId(v) => own(table, v),
        M::Ahrs(v) => own(table, v),
        M::StratuxAhrs(v) => own(table, v),
        M::Unknown { id, data } => {
            table.set_static("id", Scalar::U8(*id));
            table.set_static("data", Scalar::Str(&hex(data)));
        }
    }
}

/// Writes samples of `message`'s type with every optional field present, one per variant of
/// the enums among its fields (GDL90's only optional fields and enums with data).
fn gdl90_samples(table: &mut Table, message: &gdl90_proto::message::Message<'_>) {
    use gdl90_proto::message::{Heading, LatLon, Message as M, Track};
    match message {
        M::Ownship(r) | M::Traffic(r) => {
            for track in [
                Track::TrueTrack(0.0),
                Track::MagneticHeading(0.0),
                Track::TrueHeading(0.0),
            ] {
                let full = gdl90_proto::message::Report {
                    position: Some(LatLon::default()),
                    pressure_altitude_ft: Some(0),
                    track: Some(track),
                    ground_speed_kt: Some(0),
                    vertical_rate_fpm: Some(0),
                    ..*r
                };
                own(table, &full);
            }
        }
        M::GeoAltitude(a) => own(
            table,
            &gdl90_proto::message::GeoAltitude {
                vfom_m: Some(0),
                ..*a
            },
        ),
        M::ForeFlightId(id) => own(
            table,
            &gdl90_proto::message::ForeFlightId {
                serial: Some(0),
                ..*id
            },
        ),
        M::Ahrs(_) => {
            for heading in [Heading::True(0.0), Heading::Magnetic(0.0)] {
                let full = gdl90_proto::message::Ahrs {
                    roll_deg: Some(0.0),
                    pitch_deg: Some(0.0),
                    heading: Some(heading),
                    indicated_airspeed_kt: Some(0),
                    true_airspeed_kt: Some(0),
                };
                own(table, &full);
            }
        }
        M::StratuxAhrs(_) => own(
            table,
            &gdl90_proto::message::StratuxAhrs {
                roll_deg: Some(0.0),
                pitch_deg: Some(0.0),
                heading_deg: Some(0.0),
                slip_skid_deg: Some(0.0),
                yaw_rate_dps: Some(0.0),
                g_load: Some(0.0),
                indicated_airspeed_kt: Some(0),
                pressure_altitude_ft: Some(0),
                vertical_speed_fpm: Some(0),
            },
        ),
        M::Heartbeat(_) | M::Unknown { .. } => {}
    }
}
