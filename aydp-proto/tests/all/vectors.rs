//! Every vector of `testdata/aydp-messages.json`, in the profile it names, with the outcome
//! its `expect` says; every accepted vector is also re-encoded byte for byte.

use aydp_proto::{
    Decode, Decoder, Encoder, Error, Frame, Message, OutputEntry, Payload, Position, Profile,
    SystemControl, SystemValueUpdate, Timestamp, UpdateMode, WindSpeed,
};

const JSON: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../testdata/aydp-messages.json"
));

fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// Decode a whole vector (then finish the stream), returning frames and errors.
fn decode(bytes: &[u8], profile: Profile) -> (Vec<Vec<u8>>, Vec<Error>, aydp_proto::Stats) {
    let mut dec = Decoder::<256>::new(profile);
    let (mut frames, mut errors) = (Vec::new(), Vec::new());
    let mut sink = |e: Result<Frame<'_>, Error>| match e {
        Ok(f) => frames.push(f.as_bytes().to_vec()),
        Err(e) => errors.push(e),
    };
    dec.feed(bytes, &mut sink);
    dec.finish(&mut sink);
    (frames, errors, dec.stats())
}

fn reencode(frame: &Frame<'_>, msg: &Message<'_>) -> Vec<u8> {
    let enc = Encoder::new(frame.profile());
    let mut buf = [0u8; 256];
    let n = enc.encode(msg, frame.timestamp(), &mut buf).unwrap();
    let it: Vec<u8> = enc.iter(msg, frame.timestamp()).unwrap().collect();
    assert_eq!(it, &buf[..n], "iterator and buffer encodings differ");
    buf[..n].to_vec()
}

#[test]
fn every_vector_has_its_expected_outcome() {
    let doc: serde_json::Value = serde_json::from_str(JSON).unwrap();
    let vectors = doc["vectors"].as_array().unwrap();
    assert_eq!(vectors.len(), 11);
    let mut checked = 0;
    for v in vectors {
        let name = v["name"].as_str().unwrap();
        let bytes = hex(v["bytes"].as_str().unwrap());
        let profile = match v["profile"].as_str().unwrap() {
            "spec" => Profile::Spec,
            "reference" => Profile::Reference,
            p => panic!("unknown profile {p}"),
        };
        let (frames, errors, stats) = decode(&bytes, profile);

        if name == "seed-example-request-data-as-printed" {
            assert!(frames.is_empty(), "{name}: must be rejected");
            assert!(
                errors
                    .iter()
                    .any(|e| matches!(e, Error::ChecksumMismatch { id: 0x89, .. })),
                "{name}: {errors:?}"
            );
            assert_eq!(
                Frame::new_checked(&bytes, profile),
                Err(Error::BadLength(9))
            );
            assert_eq!(aydp_proto::checksum::xor(&bytes[..9]), 0x76);
            checked += 1;
            continue;
        }

        assert_eq!(frames.len(), 1, "{name}: {errors:?}");
        assert_eq!(stats.frames_ok, 1);
        let frame = Frame::new_checked(&frames[0], profile).unwrap();
        if let Some(t) = v.get("type") {
            assert_eq!(frame.type_byte() as u64, t.as_u64().unwrap(), "{name}");
        }
        let msg = frame.message();
        match name {
            "seed-example-enable-direct-control" => {
                assert_eq!(frame.data(), &[0x00, 0x01]);
                assert_eq!(
                    msg,
                    Err(Error::PayloadTooShort {
                        msg_type: 8,
                        expected: 7,
                        actual: 2
                    })
                );
                assert_eq!(frame.checksum(), 0x7F);
            }
            "seed-example-save-config" => {
                assert_eq!(
                    msg,
                    Ok(Message::SystemControl(SystemControl::StoreConfiguration))
                );
                assert_eq!(frame.checksum(), 0x7C);
            }
            "request-data-address-8-corrected" => {
                assert_eq!(
                    msg,
                    Ok(Message::SystemControl(SystemControl::RequestData {
                        address: 8
                    }))
                );
            }
            "svu-enable-direct-control-table-3.8" => {
                assert_eq!(
                    msg,
                    Ok(Message::SystemValueUpdate(SystemValueUpdate {
                        address: 0,
                        mode: UpdateMode::Single,
                        data: &[1],
                    }))
                );
            }
            "direct-output-rudder" => {
                let Ok(Message::DirectOutput(out)) = msg else {
                    panic!("{msg:?}")
                };
                let e: Vec<_> = out.entries().collect();
                assert_eq!(
                    e,
                    vec![OutputEntry {
                        device: 1,
                        channel: 2,
                        value: 10.0
                    }]
                );
                assert_eq!(&frame.data()[2..], &[0x01, 0x02, 0x00, 0x00, 0x20, 0x41]);
            }
            "position-timed" => {
                assert_eq!(
                    msg,
                    Ok(Message::Position(Position {
                        latitude: 50.5,
                        longitude: -1.25,
                        altitude: 12.5
                    }))
                );
                assert_eq!(frame.timestamp(), Some(Timestamp::new(1_700_000_000, 250)));
            }
            "heartbeat" => {
                assert_eq!(msg, Ok(Message::Heartbeat));
                assert_eq!(frame.as_bytes().len(), 7);
            }
            "time-sync" => {
                assert_eq!(msg, Ok(Message::TimeSync));
                assert_eq!(frame.timestamp(), Some(Timestamp::new(86_400, 999)));
            }
            "resync-ff-ff" => {
                assert_eq!(msg, Ok(Message::Heartbeat));
                assert_eq!(frame.as_bytes(), &bytes[1..]);
                assert_eq!(stats.bytes_discarded, 1);
            }
            "reference-profile-wind-speed" => {
                assert_eq!(msg, Ok(Message::WindSpeed(WindSpeed(3.5))));
                let t = frame.timestamp().unwrap();
                assert_eq!(t, Timestamp::new(42, 500_000));
                assert_eq!(t.subsec_micros(Profile::Reference), 500_000);
                assert_eq!(frame.as_bytes()[2..6], [4, 0, 0, 0]); // the length field: data only
                assert_eq!(frame.as_bytes().len(), 4 + 23);
                // The same bytes are not a valid Spec message.
                assert_eq!(
                    Frame::new_checked(&bytes, Profile::Spec),
                    Err(Error::BadLength(4))
                );
            }
            other => panic!("vector {other} has no expectation here"),
        }
        if let Ok(m) = msg {
            assert_eq!(
                reencode(&frame, &m),
                frames[0],
                "{name}: re-encoding differs"
            );
        } else {
            // Malformed typed data still re-encodes raw, byte for byte.
            let raw = aydp_proto::Raw {
                msg_type: frame.base_type(),
                data: frame.data(),
            };
            let mut buf = [0u8; 64];
            let n = Encoder::new(profile)
                .encode(&raw, frame.timestamp(), &mut buf)
                .unwrap();
            assert_eq!(&buf[..n], &frames[0][..]);
            assert_eq!(raw.buffer_len(), 2);
        }
        checked += 1;
    }
    assert_eq!(checked, vectors.len());
}

#[test]
fn vectors_concatenated_and_split_at_every_boundary() {
    let doc: serde_json::Value = serde_json::from_str(JSON).unwrap();
    let mut stream = Vec::new();
    let mut expected = 0;
    for v in doc["vectors"].as_array().unwrap() {
        if v["profile"] == "spec" {
            stream.extend(hex(v["bytes"].as_str().unwrap()));
            if !v["expect"].as_str().unwrap().starts_with("rejected") {
                expected += 1;
            }
        }
    }
    let whole = decode(&stream, Profile::Spec);
    assert_eq!(whole.0.len(), expected);
    for cut in 0..=stream.len() {
        let mut dec = Decoder::<256>::new(Profile::Spec);
        let mut frames = Vec::new();
        dec.feed(&stream[..cut], |e| {
            frames.extend(e.ok().map(|f| f.as_bytes().to_vec()))
        });
        dec.feed(&stream[cut..], |e| {
            frames.extend(e.ok().map(|f| f.as_bytes().to_vec()))
        });
        dec.finish(|e| frames.extend(e.ok().map(|f| f.as_bytes().to_vec())));
        assert_eq!(frames, whole.0, "split at {cut}");
    }
}
