#!/usr/bin/env bash
# The host C test of libprotolink_c.a (run by scripts/test.sh): builds the archive for the host,
# checks the header compiles as C11 and C++17 under gcc and clang with warnings as errors,
# builds c-api/tests/c/host_test.c with AddressSanitizer and UndefinedBehaviorSanitizer (any
# report aborts), then:
#   1. round trips every message type (encode, decode, re-encode, same bytes);
#   2. feeds 10 MiB of random bytes twice, every truncation and single-byte corruption of the
#      round-trip frames, oversized frames and NULL/length abuse;
#   3. calls every function on states their init did not set up (0x00, 0xA5, 0xFF and random
#      fills, another protocol's state, an odd address): PL_E_INVALID and nothing written; and
#      checks the header's state sizes, alignments and ABI version against the archive's;
#   4. compiles the root README's C examples as printed and runs them over a capture
#      (c-api/tests/readme_c.py);
#   5. decodes ../shared/vectors/, testdata/*.bin and the round-trip frames through the C API
#      and compares every message field and counter with `protolink decode --json`.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=target/c-api-host
mkdir -p "$out/rt" "$out/vectors"
# The archive in the dev profile: Rust's debug assertions and overflow checks are on, so a
# violated precondition inside the library (a NULL slice, an overflow) aborts the test too.
cargo build -q -p protolink-c
protolink=$(scripts/protolink-bin.sh)
lib=target/debug/libprotolink_c.a

flags=(-Wall -Wextra -Werror -pedantic -Ic-api/include)
printf '#include "protolink.h"\nint main(void) { pl_aeolus_decoder d; return pl_aeolus_init(&d); }\n' >"$out/header.c"
for cc in gcc clang; do
  $cc -std=c11 "${flags[@]}" -c "$out/header.c" -o "$out/header-$cc.o"
done
for cxx in g++ clang++; do
  $cxx -std=c++17 "${flags[@]}" -x c++ -c "$out/header.c" -o "$out/header-$cxx.o"
done
echo "header: C11 (gcc, clang) and C++17 (g++, clang++) clean with -Wall -Wextra -Werror -pedantic"

san=(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g -O1)
gcc -std=c11 "${flags[@]}" "${san[@]}" c-api/tests/c/host_test.c "$lib" -lpthread -ldl -lm -o "$out/host_test"
export ASAN_OPTIONS=abort_on_error=1:detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

"$out/host_test" roundtrip "$out/rt"
RT_DIR="$out/rt" "$out/host_test" hostile 10
"$out/host_test" misuse

# The root README's C examples ("Use it from C"), compiled as printed and run over a capture.
python3 c-api/tests/readme_c.py "$out/readme" "$lib" "$protolink"

python3 c-api/tests/vectors.py ../shared/vectors "$out/vectors"
python3 c-api/tests/compare.py "$out/host_test" "$protolink" \
  aeolus:"$out/vectors/aeolus.bin" aydp-spec:"$out/vectors/aydp-spec.bin" \
  aydp-reference:"$out/vectors/aydp-reference.bin" aok-pc:"$out/vectors/aok-pc.bin" \
  aok-device:"$out/vectors/aok-device.bin" \
  aeolus:testdata/qemu-uart0-aeolus.bin aydp-spec:testdata/qemu-uart1-aydp.bin \
  aok-device:testdata/qemu-uart2-aok.bin aok-pc:testdata/qemu-uart2-aok.bin \
  aeolus:"$out/rt/rt-aeolus.bin" aydp-spec:"$out/rt/rt-aydp-spec.bin" \
  aydp-reference:"$out/rt/rt-aydp-reference.bin" aok-pc:"$out/rt/rt-aok-pc.bin" \
  aok-device:"$out/rt/rt-aok-device.bin" gdl90:"$out/rt/rt-gdl90.bin"
