//! What an application shows of an error: the `Display` text of every `Error`, `EncodeError`, `ClientError`
//! and `IoError`,
//! and the `SerialError` kind of every `embedded-hal-nb` serial error kind.

use aok_proto::{ClientError, EncodeError, Error, SerialError};
use embedded_hal_nb::serial::ErrorKind;

#[test]
fn the_encode_error_has_its_sentence() {
    assert_eq!(
        EncodeError::BufferTooSmall { needed: 7 }.to_string(),
        "output buffer too small: 7 bytes needed"
    );
}

#[test]
fn every_error_has_its_sentence() {
    let cases = [
        (Error::Truncated, "frame truncated"),
        (Error::UnknownCommand(0x0c), "unknown command byte 0x0c"),
        (
            Error::ChecksumMismatch {
                id: 0x31,
                computed: 0x56,
                received: 0x0c,
            },
            "checksum mismatch",
        ),
        (Error::InvalidSlot(9), "invalid waypoint slot 9"),
        (
            Error::InvalidWaypoint(32),
            "waypoint number 32 outside 1..=31",
        ),
        (Error::InvalidMotor(13), "motor number 13 outside 1..=12"),
        (
            Error::StickOutOfRange(-201),
            "stick value -201 outside -200..=200",
        ),
        (Error::InvalidAction(7), "waypoint action 7 outside 0..=6"),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
}

#[test]
fn every_client_error_has_its_sentence() {
    let cases = [
        (
            ClientError::Unsupported,
            "not supported by the configured firmware",
        ),
        (ClientError::Busy, "an operation is already running"),
        (ClientError::Timeout, "the device did not answer in time"),
        (ClientError::Rejected, "the device answered 'E'"),
        (
            ClientError::RefusedInFlight,
            "the device refused in flight ('I')",
        ),
        (
            ClientError::Serial(SerialError::Parity),
            "serial error: Parity",
        ),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
}

#[test]
fn every_serial_error_kind_maps_to_its_own() {
    let cases = [
        (ErrorKind::Overrun, SerialError::Overrun),
        (ErrorKind::FrameFormat, SerialError::FrameFormat),
        (ErrorKind::Parity, SerialError::Parity),
        (ErrorKind::Noise, SerialError::Noise),
        (ErrorKind::Other, SerialError::Other),
    ];
    for (kind, want) in cases {
        assert_eq!(SerialError::from_hal(&kind), want, "{kind:?}");
    }
}

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
#[test]
fn every_io_error_has_its_sentence() {
    use aok_proto::IoError;
    let cases: [(IoError<&str>, &str); 5] = [
        (IoError::Transport("reset"), "transport error: \"reset\""),
        (
            IoError::Protocol(Error::UnknownCommand(0x0c)),
            "protocol error: unknown command byte 0x0c",
        ),
        (
            IoError::UnexpectedEof { pending: 5 },
            "end of stream inside a frame (5 bytes pending)",
        ),
        (IoError::Eof, "end of stream"),
        (IoError::WriteZero, "the transport accepted no bytes"),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
        // Only a protocol error leaves the stream usable.
        assert_eq!(e.is_protocol(), matches!(e, IoError::Protocol(_)), "{e:?}");
    }
}
