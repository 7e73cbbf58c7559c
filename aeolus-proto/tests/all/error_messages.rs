//! What an application shows of an error: the `Display` text of every `Error` and `IoError`,
//! and the `Debug` form of a `Text` (a string when it is UTF-8, bytes otherwise).

use aeolus_proto::{EncodeError, Error, TEXT_CAPACITY, message::Text};

#[test]
fn every_error_has_its_sentence() {
    let cases = [
        (
            Error::Overflow,
            "frame longer than the decoder capacity".to_string(),
        ),
        (
            Error::ChecksumMismatch {
                id: 82,
                computed: 0xEC73,
                received: 0x0A,
            },
            "CRC mismatch on message 82: computed 0xec73, received 0x000a".into(),
        ),
        (
            Error::MissingCrc { id: 62 },
            "message 62 carries no CRC (strict mode)".into(),
        ),
        (
            Error::TooShort,
            "frame too short to hold an ID and a CRC".into(),
        ),
        (
            Error::InvalidEscape,
            "escape byte followed by an invalid byte".into(),
        ),
        (
            Error::EscapedFlag,
            "escape byte right before a flag (frame aborted)".into(),
        ),
        (Error::Truncated, "datagram ends inside a frame".into()),
        (
            Error::WrongLength {
                id: 62,
                expected: 32,
                actual: 31,
            },
            "message 62 has 31 data bytes, expected 32".into(),
        ),
        (
            Error::TextTooLong { id: 82, len: 200 },
            format!("message 82 carries a 200-byte text, more than {TEXT_CAPACITY} allowed"),
        ),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
    assert_eq!(TEXT_CAPACITY, 120);
}

#[test]
fn every_encode_error_has_its_sentence() {
    let cases = [
        (
            EncodeError::BufferTooSmall { needed: 9 },
            "output buffer too small: 9 bytes needed",
        ),
        (
            EncodeError::TextTooLong { len: 200 },
            "a 200-byte text, more than 120 allowed",
        ),
    ];
    for (e, want) in cases {
        assert_eq!(e.to_string(), want, "{e:?}");
    }
}

#[cfg(any(feature = "embedded-io", feature = "embedded-io-async"))]
#[test]
fn every_io_error_has_its_sentence() {
    use aeolus_proto::IoError;
    let cases: [(IoError<&str>, &str); 5] = [
        (IoError::Transport("reset"), "transport error: \"reset\""),
        (
            IoError::Protocol(Error::Overflow),
            "protocol error: frame longer than the decoder capacity",
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

#[test]
fn a_text_shows_as_a_string_or_as_bytes() {
    assert_eq!(format!("{:?}", Text::new("hi").unwrap()), "Text(\"hi\")");
    assert_eq!(
        format!("{:?}", Text::from_bytes(&[0x68, 0xFF]).unwrap()),
        "Text([104, 255])"
    );
}
