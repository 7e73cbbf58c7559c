//! The sensor-box application (work in progress).
#![no_std]
#![deny(missing_docs)]
