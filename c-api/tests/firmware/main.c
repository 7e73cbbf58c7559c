/*
 * The C firmware test: a Cortex-M3 program for QEMU lm3s6965evb, built with Debian's
 * arm-none-eabi-gcc and picolibc and linked with libprotolink_c.a (thumbv7m). It decodes the
 * three UART captures of testdata/ (built into the image by capture.S) through the C API,
 * AEOLUS a byte at a time (pl_aeolus_parse on one byte, as a receive interrupt would), AYDP and
 * AOK a capture at a time (the same call, the one loop), after checking that the header and
 * the archive agree: ABI version, state sizes), and prints the decoders' counters
 * over semihosting; c-api/tests/firmware.sh compares them with the Rust decoder's
 * (`protolink decode --json`).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "protolink.h"

extern const uint8_t aeolus_capture[], aeolus_capture_end[];
extern const uint8_t aydp_capture[], aydp_capture_end[];
extern const uint8_t aok_capture[], aok_capture_end[];

/* Decoders in .bss, one per link, as a firmware keeps them. */
static pl_aeolus_decoder aeolus;
static pl_aydp_decoder aydp;
static pl_aok_pc_decoder aok;

int main(void) {
    pl_error err;
    unsigned aeolus_messages = 0, aydp_messages = 0, aok_messages = 0, errors = 0;

    /* The header this was compiled with describes the archive it is linked with. */
    if (pl_abi_version() != PL_ABI_VERSION || pl_state_size(PL_STATE_AEOLUS) != sizeof aeolus ||
        pl_state_size(PL_STATE_AYDP) != sizeof aydp || pl_state_size(PL_STATE_AOK_PC) != sizeof aok ||
        pl_state_align(PL_STATE_AEOLUS) != _Alignof(pl_aeolus_decoder)) {
        printf("protolink.h and libprotolink_c.a differ\n");
        exit(1);
    }

    pl_aeolus_message am;
    pl_aeolus_init(&aeolus);
    size_t used;
    for (const uint8_t *p = aeolus_capture; p < aeolus_capture_end; p++) {
        /* One byte: AEOLUS gives at most one event a byte, so nothing stays queued. */
        int st = pl_aeolus_parse(&aeolus, p, 1, &used, &am, &err);
        aeolus_messages += st == PL_MESSAGE;
        errors += st == PL_ERROR;
    }
    for (int st; (st = pl_aeolus_finish(&aeolus, &am, &err)) > 0;) errors += st == PL_ERROR;

    pl_aydp_message ym;
    pl_aydp_init(&aydp, PL_AYDP_SPEC);
    size_t len = (size_t)(aydp_capture_end - aydp_capture), off = 0;
    for (int st; (st = pl_aydp_parse(&aydp, aydp_capture + off, len - off, &used, &ym, &err)) > 0;) {
        off += used;
        aydp_messages += st == PL_MESSAGE;
        errors += st == PL_ERROR;
    }
    for (int st; (st = pl_aydp_finish(&aydp, &ym, &err)) > 0;) {
        aydp_messages += st == PL_MESSAGE;
        errors += st == PL_ERROR;
    }

    pl_aok_item it;
    pl_aok_pc_init(&aok, 0, 35);
    len = (size_t)(aok_capture_end - aok_capture);
    off = 0;
    for (int st; (st = pl_aok_pc_parse(&aok, aok_capture + off, len - off, &used, &it, &err)) > 0;) {
        off += used;
        aok_messages += st == PL_MESSAGE;
        errors += st == PL_ERROR;
    }
    for (int st; (st = pl_aok_pc_finish(&aok, &it, &err)) > 0;) {
        aok_messages += st == PL_MESSAGE;
        errors += st == PL_ERROR;
    }

    pl_aeolus_stats as;
    pl_aydp_stats ys;
    pl_aok_stats ks;
    pl_aeolus_get_stats(&aeolus, &as);
    pl_aydp_get_stats(&aydp, &ys);
    pl_aok_pc_get_stats(&aok, &ks);
    printf("aeolus messages=%u frames_ok=%lu frames_no_crc=%lu checksum_errors=%lu overflows=%lu "
           "bytes_discarded=%lu frame_bytes=%lu flags=%lu\n",
           aeolus_messages, (unsigned long)as.frames_ok, (unsigned long)as.frames_no_crc,
           (unsigned long)as.checksum_errors, (unsigned long)as.overflows, (unsigned long)as.bytes_discarded,
           (unsigned long)as.frame_bytes, (unsigned long)as.flags);
    printf("aydp messages=%u frames_ok=%lu checksum_errors=%lu length_errors=%lu bytes_discarded=%lu\n",
           aydp_messages, (unsigned long)ys.frames_ok, (unsigned long)ys.checksum_errors,
           (unsigned long)ys.length_errors, (unsigned long)ys.bytes_discarded);
    printf("aok messages=%u frames_ok=%lu checksum_errors=%lu unknown_bytes=%lu invalid=%lu "
           "bytes_discarded=%lu\n",
           aok_messages, (unsigned long)ks.frames_ok, (unsigned long)ks.checksum_errors,
           (unsigned long)ks.unknown_bytes, (unsigned long)ks.invalid, (unsigned long)ks.bytes_discarded);
    printf("errors=%u\n", errors);
    exit(0);
}
