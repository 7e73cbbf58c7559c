//! What an application shows of an error: the `Display` text of every `Error`, `EncodeError`
//! and `IoError`.

use aydp_proto::registry::RegistryError;
use aydp_proto::{EncodeError, Error};

#[test]
fn every_encode_error_has_its_sentence() {
    let cases = [
        (
            EncodeError::BufferTooSmall { needed: 9 },
            "buffer too small: 9 bytes needed",
        ),
        (
            EncodeError::BadType(127),
            "base type 127 is outside 0..=126",
        ),
        (
            EncodeError::TooLong,
            "message too long for the length field",
        ),
        (
            EncodeError::ExpeditedInReference,
            "the Reference profile has no expedited header: send a normal message with a timestamp",
        ),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
}

#[test]
fn every_error_has_its_sentence() {
    let cases = [
        (Error::Truncated, "input truncated"),
        (Error::BadStart, "missing 0xFF start byte"),
        (Error::ReservedType, "type byte 0xFF is reserved"),
        (Error::BadType(127), "base type 127 is outside 0..=126"),
        (Error::BadLength(3), "bad length field 3"),
        (
            Error::ChecksumMismatch {
                id: 3,
                computed: 0xE2,
                received: 0x55,
            },
            "checksum mismatch",
        ),
        (
            Error::PayloadTooShort {
                msg_type: 4,
                expected: 10,
                actual: 2,
            },
            "type 4: data too short (2 bytes, needs 10)",
        ),
        (
            Error::PayloadTooLong {
                msg_type: 4,
                expected: 10,
                actual: 12,
            },
            "type 4: data too long (12 bytes, allows 10)",
        ),
        (
            Error::CountMismatch {
                msg_type: 5,
                count: 7,
            },
            "type 5: count 7 does not match the length",
        ),
        (Error::NegativeUflt16, "uflt16 field has its sign bit set"),
        (Error::UnknownUpdateMode(9), "unknown update type 9"),
        (
            Error::NonZeroSingleIndex(2),
            "single-value update with non-zero element field 2",
        ),
        (Error::UnknownCommand(8), "unknown system control command 8"),
        (
            Error::TooManySatellites(40),
            "40 satellites do not fit the list",
        ),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
}

#[test]
fn every_registry_error_has_its_sentence() {
    let cases = [
        (
            RegistryError::UnknownAddress(0x1234),
            "no system value at address 0x1234",
        ),
        (
            RegistryError::ReadOnly(0x0001),
            "address 0x0001 is read-only",
        ),
        (
            RegistryError::WrongMode(0x0200),
            "update mode does not fit address 0x0200",
        ),
        (
            RegistryError::WrongSize(0x0200),
            "data size does not fit address 0x0200",
        ),
        (
            RegistryError::OutOfBounds(0x0200),
            "index or count out of bounds at 0x0200",
        ),
        (
            RegistryError::OutOfRange(0x0000),
            "value out of range for address 0x0000",
        ),
        (
            RegistryError::BufferTooSmall { needed: 6 },
            "buffer too small: 6 bytes needed",
        ),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
}

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
#[test]
fn every_io_error_has_its_sentence() {
    use aydp_proto::IoError;
    let cases: [(IoError<&str>, &str); 5] = [
        (IoError::Transport("reset"), "transport error: \"reset\""),
        (
            IoError::Protocol(Error::BadStart),
            "protocol error: missing 0xFF start byte",
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
