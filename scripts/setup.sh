#!/usr/bin/env bash
# Installs what the project needs on a fresh Debian machine. Idempotent: each
# step checks first and does nothing when the tool is already there.
#   scripts/setup.sh            toolchain + thumb targets (from rust-toolchain.toml), the
#                               thumbv6m target, and the libraries' MSRV toolchain (1.87)
#   scripts/setup.sh qemu       + qemu-system-arm (Debian package)
#   scripts/setup.sh defmt-print + defmt-print (decodes the firmware's defmt log)
#   scripts/setup.sh tshark     + tshark (Debian package; the dissector test runs it on captures)
#   scripts/setup.sh chromium   + chromium and chromium-driver (Debian packages; the browser tests of
#                               `protolink web` drive it headless)
#   scripts/setup.sh i686       + the i686 target and gcc-multilib (Debian): the protocol
#                               libraries' tests also run with 32-bit words, as on the firmware
#   scripts/setup.sh bench      + valgrind (Debian) and gungraun-runner 0.20 (crates.io): the x86-64
#                               instruction counts of bench/ under callgrind (scripts/bench-check.py)
#   scripts/setup.sh c          + what the C library's tests need: gcc-arm-none-eabi,
#                               picolibc-arm-none-eabi and clang (Debian), cbindgen (crates.io,
#                               it generates c-api/include/protolink.h), and the nightly
#                               toolchain's miri component (the C API's Rust tests under Miri)
#   scripts/setup.sh python     + python3, pip and venv (Debian) and from PyPI: pynmea2 1.19.0 (the
#                               NMEA test has an outside library parse `protolink nmea`'s output),
#                               maturin 1.16.0 (builds the Python package, python/), pytest 9.2.0,
#                               hypothesis 6.170.17 and pandas 3.1.1 (its tests), pymavlink 2.4.50
#                               (the peer of python/bench/bench.py), pyarrow 26.0.1 (to_arrow and
#                               to_frames), duckdb 2.0.1, polars 2.1.0 and pyspark 4.0.1 (the
#                               engines that read `protolink export`'s tables in python/tests:
#                               test_export.py, test_spark.py), and Java 17 for Spark (Debian's
#                               openjdk-17-jre-headless, where no java is on the PATH)
#   scripts/setup.sh fuzz       + the nightly toolchain and cargo-fuzz (crates.io): the fuzz targets'
#                               build and smoke run (scripts/fuzz.sh)
#   scripts/setup.sh mutants    + cargo-mutants 27.1.0 (crates.io): scripts/mutants.sh, which CI
#                               runs on the last commit's library lines
#   scripts/setup.sh gpsd       + gpsd and gpsd-clients (Debian packages; host-tool/tests/all/gpsd.rs
#                               has gpsd read `protolink nmea --for gpsd` and reads it with gpspipe)
set -euo pipefail
cd "$(dirname "$0")/.."

# rustup reads rust-toolchain.toml: this installs the pinned toolchain, its
# components and the thumb targets listed there.
rustup show active-toolchain >/dev/null 2>&1 || rustup toolchain install
rustup target list --installed | grep -q thumbv7m-none-eabi || rustup toolchain install
# Cortex-M0/M0+ (RP2040 and the cheapest boards): the libraries, footprint and panic-never
# are built for it too.
rustup target list --installed | grep -q thumbv6m-none-eabi || rustup target add thumbv6m-none-eabi
# The libraries' MSRV (rust-version in their Cargo.toml), checked with exactly that toolchain.
MSRV=1.87
rustup toolchain list | grep -q "^$MSRV-" || rustup toolchain install "$MSRV" --profile minimal
rustup +"$MSRV" target list --installed | grep -q thumbv6m-none-eabi \
  || rustup +"$MSRV" target add thumbv6m-none-eabi

need_apt=()
want_pypi=0
# PyPI packages of the `python` component: the pinned version of each, and the module it imports.
PYPI=(pynmea2==1.19.0 maturin==1.16.0 pytest==9.2.0 hypothesis==6.170.17 pandas==3.1.1 pymavlink==2.4.50
      pyarrow==26.0.1 duckdb==2.0.1 polars==2.1.0 pyspark==4.0.1)
PYPI_MODULES=(pynmea2 maturin pytest hypothesis pandas pymavlink pyarrow duckdb polars pyspark)
need_pypi=()
# crates.io tools, NAME or NAME@VERSION: installed after the loop, beside apt and PyPI.
need_cargo=()
for want in "$@"; do
  case "$want" in
    qemu) command -v qemu-system-arm >/dev/null || need_apt+=(qemu-system-arm) ;;
    defmt-print) command -v defmt-print >/dev/null || need_cargo+=(defmt-print) ;;
    tshark) command -v tshark >/dev/null || need_apt+=(tshark) ;;
    chromium) [ -x /usr/bin/chromium ] && command -v chromedriver >/dev/null || need_apt+=(chromium chromium-driver) ;;
    bench)
      command -v valgrind >/dev/null || need_apt+=(valgrind)
      gungraun-runner --version 2>/dev/null | grep -q ' 0\.20\.' \
        || need_cargo+=(gungraun-runner@0.20.0) ;;
    i686)
      rustup target list --installed | grep -q '^i686-unknown-linux-gnu$' || rustup target add i686-unknown-linux-gnu
      dpkg -s gcc-multilib >/dev/null 2>&1 || need_apt+=(gcc-multilib) ;;
    c)
      command -v arm-none-eabi-gcc >/dev/null || need_apt+=(gcc-arm-none-eabi)
      [ -f /usr/lib/picolibc/arm-none-eabi/picolibc.specs ] || need_apt+=(picolibc-arm-none-eabi)
      command -v clang >/dev/null || need_apt+=(clang)
      # 0.28 is the first cbindgen that reads edition-2024 `#[unsafe(no_mangle)]`.
      cbindgen --version 2>/dev/null | grep -qE ' 0\.(2[89]|[3-9][0-9])' \
        || need_cargo+=(cbindgen@0.29.4)
      rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
      rustup +nightly component list --installed | grep -q '^miri' \
        || rustup +nightly component add miri rust-src ;;
    python)
      command -v python3 >/dev/null || need_apt+=(python3)
      python3 -m pip --version >/dev/null 2>&1 || need_apt+=(python3-pip)
      # Debian's python3 makes venvs (scripts/test-python.sh) only with python3-venv.
      python3 -c 'import ensurepip' 2>/dev/null || need_apt+=(python3-venv)
      # pyspark 4 runs its engine in a JVM: Java 17 or later.
      command -v java >/dev/null || need_apt+=(openjdk-17-jre-headless)
      want_pypi=1 ;;
    fuzz)
      rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
      command -v cargo-fuzz >/dev/null || need_cargo+=(cargo-fuzz) ;;
    mutants) command -v cargo-mutants >/dev/null || need_cargo+=(cargo-mutants@27.1.0) ;;
    gpsd)
      # gpsd lives in /usr/sbin, which a user's PATH may lack.
      command -v gpsd >/dev/null || [ -x /usr/sbin/gpsd ] || need_apt+=(gpsd)
      command -v gpspipe >/dev/null || need_apt+=(gpsd-clients) ;;
    *) echo "setup.sh: unknown component '$want'" >&2; exit 2 ;;
  esac
done
# The Debian packages, then PyPI's (python3 and pip may come from apt), in the background beside
# the crates.io tools: those compile, these wait on the network and dpkg.
packages() {
  if [ ${#need_apt[@]} -gt 0 ]; then
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    # tshark's package asks whether non-root users may capture: answer no, never prompt.
    echo "wireshark-common wireshark-common/install-setuid boolean false" | $SUDO debconf-set-selections 2>/dev/null || true
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}" >/dev/null
  fi
  # A Debian python3 refuses a system-wide pip install (PEP 668) unless told: then the user's
  # site-packages take it.
  if [ "$want_pypi" = 1 ]; then
    for i in "${!PYPI[@]}"; do
      python3 -c "import ${PYPI_MODULES[$i]}" 2>/dev/null || need_pypi+=("${PYPI[$i]}")
    done
    if [ ${#need_pypi[@]} -gt 0 ]; then
      python3 -m pip install -q "${need_pypi[@]}" 2>/dev/null \
        || python3 -m pip install -q --user --break-system-packages "${need_pypi[@]}"
    fi
    python3 -c "import $(IFS=,; echo "${PYPI_MODULES[*]}")"
  fi
}
packages &
packages_pid=$!
# Unoptimised (opt-level 0, no LTO, no debug info), as they only drive other programs: a
# quarter of the compile (cbindgen: 28 s of CPU against 117 s) for no run time that counts.
# defmt-print keeps its release build: the QEMU tests decode the firmware's log with it as the
# log streams in.
fast=()
for c in "${need_cargo[@]}"; do
  if [ "$c" = defmt-print ]; then
    cargo install --locked defmt-print
  else
    fast+=("$c")
  fi
done
if [ ${#fast[@]} -gt 0 ]; then
  CARGO_PROFILE_RELEASE_OPT_LEVEL=0 CARGO_PROFILE_RELEASE_LTO=false CARGO_PROFILE_RELEASE_DEBUG=false \
    CARGO_PROFILE_RELEASE_CODEGEN_UNITS=256 cargo install --locked "${fast[@]}"
fi
wait "$packages_pid"
