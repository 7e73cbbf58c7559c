//! Picks the memory map for the board being built and copies it to `OUT_DIR/memory.x` for
//! cortex-m-rt's `link.x`:
//!
//! * `board-stm32f411`: the repository's STM32F411 map
//!   (`firmware-example/src/board/stm32f411.x`: the program in sectors 0-4, 128 KiB; sectors
//!   5-7 kept for the settings store; 128 KiB RAM), the map the blocking board uses;
//! * `board-qemu`: the workspace's top-level `memory.x` (lm3s6965: 256 KiB flash, 56 KiB RAM
//!   and the 8 KiB `.flash_emu` region the settings live in), the blocking QEMU board's map,
//!   and an empty `device.x` (the interrupt vectors are Rust code, `src/qemu/chip.rs`).

use std::{env, fs, path::PathBuf};

fn main() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("set by cargo"));
    println!("cargo:rerun-if-changed=build.rs");
    let qemu = env::var_os("CARGO_FEATURE_BOARD_QEMU").is_some();
    let stm32 = env::var_os("CARGO_FEATURE_BOARD_STM32F411").is_some();
    if qemu == stm32 {
        // No board, or both: src/main.rs says so with a compile_error!.
        return;
    }
    let map = if qemu {
        manifest.join("../memory.x")
    } else {
        manifest.join("../firmware-example/src/board/stm32f411.x")
    };
    println!("cargo:rerun-if-changed={}", map.display());
    fs::copy(&map, out.join("memory.x")).expect("copy the memory map to OUT_DIR");
    if qemu {
        fs::write(
            out.join("device.x"),
            "/* lm3s6965: the vectors are defined in src/qemu/chip.rs */\n",
        )
        .expect("write device.x");
    }
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
