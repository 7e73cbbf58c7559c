//! Picks the memory map and linker scripts for the board being built.
//!
//! * host builds (any `target_os` but `none`): nothing to do;
//! * `board-qemu`: the workspace's top-level `memory.x` (lm3s6965) and a
//!   `device.x` (the interrupt vectors are defined in `src/board/qemu.rs`);
//! * `board-stm32f411`: `src/board/stm32f411.x` (the PAC brings `device.x`).
//!
//! The chosen map is copied to `OUT_DIR/memory.x` (and the linker is told to
//! read that file for cortex-m-rt's `INCLUDE memory.x`), and `-Tlink.x -Tdefmt.x`
//! go to this package's binaries only (`rustc-link-arg-bins`), so other
//! thumb binaries of the workspace are not affected.

use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let bare_metal = env::var("CARGO_CFG_TARGET_OS").is_ok_and(|os| os == "none");
    let qemu = env::var_os("CARGO_FEATURE_BOARD_QEMU").is_some();
    let stm32 = env::var_os("CARGO_FEATURE_BOARD_STM32F411").is_some();
    if !bare_metal || qemu == stm32 {
        // Host build, or no/both boards on the target: src/main.rs explains
        // the latter with a compile_error!.
        return;
    }
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("set by cargo"));
    let map = if qemu {
        manifest.join("../memory.x")
    } else {
        manifest.join("src/board/stm32f411.x")
    };
    println!("cargo:rerun-if-changed={}", map.display());
    fs::copy(&map, out.join("memory.x")).expect("copy the memory map to OUT_DIR");
    if qemu {
        // cortex-m-rt's `device` feature INCLUDEs device.x; our vector table
        // is Rust code, so it only needs to exist.
        fs::write(
            out.join("device.x"),
            "/* lm3s6965: vectors are defined in src/board/qemu.rs */\n",
        )
        .expect("write device.x");
    }
    println!("cargo:rustc-link-search={}", out.display());
    // The linker runs in the workspace root, and lld looks for an INCLUDEd
    // script in the current directory before the search path: cortex-m-rt's
    // `INCLUDE memory.x` would always find the top-level (lm3s6965) map.
    // Remap that name to the map picked above.
    println!(
        "cargo:rustc-link-arg-bins=--remap-inputs=memory.x={}",
        out.join("memory.x").display()
    );
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
