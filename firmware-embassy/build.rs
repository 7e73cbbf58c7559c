//! Links with the repository's STM32F411 memory map (`firmware-example/src/board/stm32f411.x`:
//! the program in sectors 0-4, 128 KiB; sectors 5-7 kept for the settings store; 128 KiB RAM),
//! the same map the blocking board uses, copied to `OUT_DIR/memory.x` for cortex-m-rt's
//! `link.x`.

use std::{env, fs, path::PathBuf};

fn main() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("set by cargo"));
    let map = manifest.join("../firmware-example/src/board/stm32f411.x");
    println!("cargo:rerun-if-changed={}", map.display());
    println!("cargo:rerun-if-changed=build.rs");
    fs::copy(&map, out.join("memory.x")).expect("copy the memory map to OUT_DIR");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
