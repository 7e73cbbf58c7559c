//! Which AEOLUS messages are due when, built from the simulated flight.
//!
//! STUB: to be implemented (shared with `protolink sim`).
