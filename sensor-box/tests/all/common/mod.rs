//! Test support shared by the integration tests.
#![allow(dead_code)]

pub mod cut_flash;
pub mod genuine_aok;
