//! What a stream carries, as the command line names it: the protocol ([`Proto`]), the AYDP
//! profile ([`ProfileArg`]) and, for AOK, who sent the bytes ([`Side`]). Shared by `decode`,
//! `record` and the capture files, which name a stream's protocol by its link type.

use aydp_proto::Profile;

/// Which protocol a stream carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Proto {
    /// AEOLUS sensor-box telemetry (7E-framed, CRC-16).
    Aeolus,
    /// AYDP, the yacht protocol (FF start, XOR checksum).
    Aydp,
    /// AOK, the copter's serial protocol.
    Aok,
    /// GDL90 and the ForeFlight extensions, as EFB apps receive them (7E-framed, CRC-16).
    Gdl90,
}

/// Which AYDP convention applies (DECISIONS.md Y1, Y2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum ProfileArg {
    /// The 2016 document: the length counts the whole message, sub-seconds are ms.
    #[default]
    Spec,
    /// The released AYDP software: the length counts data only, sub-seconds are µs.
    Reference,
}

impl From<ProfileArg> for Profile {
    fn from(p: ProfileArg) -> Self {
        match p {
            ProfileArg::Spec => Profile::Spec,
            ProfileArg::Reference => Profile::Reference,
        }
    }
}

/// Who sent the AOK bytes being decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Side {
    /// The ground PC sent them: commands, read as the device reads them.
    Pc,
    /// The device sent them: debug values, acks and replies, read as the PC reads them.
    #[default]
    Device,
}

/// The protocol's name as `decode --json` writes it (`"proto"`): `aeolus`, `aydp`, `aok`,
/// `gdl90`.
pub fn proto_name(p: Proto) -> &'static str {
    match p {
        Proto::Aeolus => "aeolus",
        Proto::Aydp => "aydp",
        Proto::Aok => "aok",
        Proto::Gdl90 => "gdl90",
    }
}
