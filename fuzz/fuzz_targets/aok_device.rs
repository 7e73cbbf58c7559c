//! The AOK device-side decoder (what the PC sends) on any byte stream: no panic; every
//! command it yields re-encodes to bytes that decode to the same command.
#![no_main]
use aeolus_proto::Decode as _;
use aok_proto::{Command, CommandDecoder};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut d = CommandDecoder::new();
    let mut cmds = Vec::new();
    for &b in data {
        d.feed(&[b], |ev| {
            cmds.extend(ev);
        });
    }
    d.finish(|ev| cmds.extend(ev));
    for c in cmds {
        let mut bytes = [0u8; aok_proto::command::MAX_COMMAND_LEN];
        let n = c.emit(&mut bytes).unwrap();
        let (again, used) = Command::parse(&bytes[..n]).unwrap();
        assert_eq!(again, c);
        assert_eq!(used, n);
    }
});
