//! The calibration status byte of CALIBINFO/AEOLUSINFO: the eight named values with their
//! signed bytes, every other byte kept as `Other`, and every byte round-trips.

use aeolus_proto::message::CalibrationStatus::{self, *};

const NAMED: [(i8, CalibrationStatus); 8] = [
    (1, NoCalibration),
    (2, JustFinished),
    (3, Ok),
    (4, Calibrating),
    (-1, TooFewData),
    (-2, FieldWeak),
    (-3, FieldDistorted),
    (-4, ErrorVeryHigh),
];

#[test]
fn each_named_status_has_its_signed_byte() {
    for (byte, status) in NAMED {
        assert_eq!(CalibrationStatus::from_i8(byte), status, "{byte}");
        assert_eq!(status.to_i8(), byte, "{status:?}");
    }
}

#[test]
fn every_byte_round_trips_and_the_others_stay_other() {
    for byte in i8::MIN..=i8::MAX {
        let status = CalibrationStatus::from_i8(byte);
        assert_eq!(status.to_i8(), byte);
        if !NAMED.iter().any(|&(b, _)| b == byte) {
            assert_eq!(status, Other(byte));
        }
    }
}
