//! `protolink.gdl90`: the GDL90 `Decoder` (GDL90 and the ForeFlight and Stratux extensions, as
//! EFB apps receive them on UDP port 4000).

use protolink::proto::Proto;

use crate::decoder::protocol_decoder;

protocol_decoder!(
    /// The GDL90 stream decoder, as `protolink decode --proto gdl90` runs it. `finish()`: a
    /// frame still open is a `truncated` error.
    Gdl90PyDecoder,
    "protolink.gdl90",
    Proto::Gdl90
);
