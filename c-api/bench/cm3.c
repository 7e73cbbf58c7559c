/*
 * Instructions per byte of the C calls on Cortex-M3, by the checks/cm3-bench method: QEMU
 * lm3s6965evb with -icount shift=0 (one instruction = 1 ns of virtual time), SysTick from the
 * core clock read before and after each window, one tick calibrated against a loop of known
 * length. Beside each C call, the Rust path on the same bytes in the same run: the crates'
 * own push/poll or feed loop and typed parse, exported by the archive's `bench` feature.
 * Input: a UART capture of testdata/ (-DPROTO=1 AEOLUS, 2 AYDP, 3 AOK, one build each).
 * scripts/c-bench.sh builds and runs it and prints the table.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "protolink.h"

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

extern const uint8_t stream_a[], stream_a_end[];

static uint32_t events, messages;

/* The Rust path, from the archive built with the `bench` feature (not in the header). */
uint32_t pl_bench_rust_aeolus_push(const uint8_t *bytes, size_t len);
uint32_t pl_bench_rust_aeolus_feed(const uint8_t *bytes, size_t len);
uint32_t pl_bench_rust_aydp_push(const uint8_t *bytes, size_t len);
uint32_t pl_bench_rust_aydp_feed(const uint8_t *bytes, size_t len);
uint32_t pl_bench_rust_aok_pc_push(const uint8_t *bytes, size_t len);
uint32_t pl_bench_rust_aok_pc_feed(const uint8_t *bytes, size_t len);

/* Ticks taken by fn(), from a tick edge; SysTick restarted at its full 24-bit reload, so a
 * window under 2^24 ticks never wraps. */
static uint32_t window(void (*fn)(void)) {
    SYST_CVR = 0;
    uint32_t t = SYST_CVR;
    while (SYST_CVR == t) {
    }
    uint32_t t0 = SYST_CVR;
    fn();
    uint32_t t1 = SYST_CVR;
    return t0 - t1;
}

static void empty(void) {}

static volatile uint32_t loops;
static void spin(void) {
    uint32_t n = loops;
    __asm__ volatile("1: subs %0, #1\n bne 1b" : "+r"(n));
}

static const uint8_t *in;
static size_t in_len;

#define RUST_ROW(fn) \
    static void rust_##fn(void) { messages = events = pl_bench_rust_##fn(in, in_len); }

/* The feed calls' callbacks: count, as the other rows do. */
static void count_event(int32_t st) {
    events++;
    messages += st == PL_MESSAGE;
}

#if PROTO == 1
RUST_ROW(aeolus_push)
RUST_ROW(aeolus_feed)
static pl_aeolus_decoder aeolus;
static void aeolus_bytes(void) {
    pl_aeolus_message m;
    pl_error e;
    pl_aeolus_init(&aeolus);
    for (size_t i = 0; i < in_len; i++) {
        size_t used;
        int st = pl_aeolus_parse(&aeolus, in + i, 1, &used, &m, &e);
        events += st > 0;
        messages += st == PL_MESSAGE;
    }
}
static void on_aeolus(void *ctx, int32_t st, const pl_aeolus_message *m, const pl_error *e) {
    (void)ctx, (void)m, (void)e;
    count_event(st);
}
static void aeolus_feed(void) {
    pl_aeolus_init(&aeolus);
    pl_aeolus_feed(&aeolus, in, in_len, on_aeolus, NULL);
}
static void aeolus_slices(void) {
    pl_aeolus_message m;
    pl_error e;
    size_t off = 0, used;
    pl_aeolus_init(&aeolus);
    while (off < in_len) {
        int st = pl_aeolus_parse(&aeolus, in + off, in_len - off, &used, &m, &e);
        off += used;
        events += st > 0;
        messages += st == PL_MESSAGE;
    }
}
#elif PROTO == 2
RUST_ROW(aydp_push)
RUST_ROW(aydp_feed)
static pl_aydp_decoder aydp;
static void aydp_bytes(void) {
    pl_aydp_message m;
    pl_error e;
    pl_aydp_init(&aydp, PL_AYDP_SPEC);
    /* The one loop on one byte a call: an event a rescan left queued comes with no byte used,
     * and what is queued after the last byte with no bytes given. */
    size_t used;
    for (size_t i = 0; i < in_len; i += used) {
        int st = pl_aydp_parse(&aydp, in + i, 1, &used, &m, &e);
        events += st > 0;
        messages += st == PL_MESSAGE;
    }
    for (int st; (st = pl_aydp_parse(&aydp, NULL, 0, &used, &m, &e)) > 0;) {
        events++;
        messages += st == PL_MESSAGE;
    }
}
static void on_aydp(void *ctx, int32_t st, const pl_aydp_message *m, const pl_error *e) {
    (void)ctx, (void)m, (void)e;
    count_event(st);
}
static void aydp_feed(void) {
    pl_aydp_init(&aydp, PL_AYDP_SPEC);
    pl_aydp_feed(&aydp, in, in_len, on_aydp, NULL);
}
static void aydp_slices(void) {
    pl_aydp_message m;
    pl_error e;
    size_t off = 0, used;
    pl_aydp_init(&aydp, PL_AYDP_SPEC);
    for (;;) {
        int st = pl_aydp_parse(&aydp, in + off, in_len - off, &used, &m, &e);
        off += used;
        if (st <= 0) break;
        events++;
        messages += st == PL_MESSAGE;
    }
}
#else
RUST_ROW(aok_pc_push)
RUST_ROW(aok_pc_feed)
static pl_aok_pc_decoder pc;
static void pc_bytes(void) {
    pl_aok_item m;
    pl_error e;
    pl_aok_pc_init(&pc, 0, 35);
    /* The one loop on one byte a call: an event a rescan left queued comes with no byte used,
     * and what is queued after the last byte with no bytes given. */
    size_t used;
    for (size_t i = 0; i < in_len; i += used) {
        int st = pl_aok_pc_parse(&pc, in + i, 1, &used, &m, &e);
        events += st > 0;
        messages += st == PL_MESSAGE;
    }
    for (int st; (st = pl_aok_pc_parse(&pc, NULL, 0, &used, &m, &e)) > 0;) {
        events++;
        messages += st == PL_MESSAGE;
    }
}
static void on_aok(void *ctx, int32_t st, const pl_aok_item *m, const pl_error *e) {
    (void)ctx, (void)m, (void)e;
    count_event(st);
}
static void pc_feed(void) {
    pl_aok_pc_init(&pc, 0, 35);
    pl_aok_pc_feed(&pc, in, in_len, on_aok, NULL);
}
static void pc_slices(void) {
    pl_aok_item m;
    pl_error e;
    size_t off = 0, used;
    pl_aok_pc_init(&pc, 0, 35);
    for (;;) {
        int st = pl_aok_pc_parse(&pc, in + off, in_len - off, &used, &m, &e);
        off += used;
        if (st <= 0) break;
        events++;
        messages += st == PL_MESSAGE;
    }
}
#endif

static uint32_t overhead;

static void row(const char *name, void (*fn)(void), const uint8_t *start, const uint8_t *end, double per_tick) {
    in = start;
    in_len = (size_t)(end - start);
    uint32_t ticks[2];
    for (int run = 0; run < 2; run++) {
        events = messages = 0;
        ticks[run] = window(fn) - overhead;
    }
    printf("row %s bytes=%lu ticks=%lu ticks2=%lu instructions=%.0f messages=%lu events=%lu\n", name,
           (unsigned long)in_len, (unsigned long)ticks[0], (unsigned long)ticks[1], ticks[0] * per_tick,
           (unsigned long)messages, (unsigned long)events);
}

int main(void) {
    SYST_CSR = 0;
    SYST_RVR = 0x00FFFFFFu;
    SYST_CVR = 0;
    SYST_CSR = 5; /* enable, core clock, no interrupt */
    overhead = window(empty);
    loops = 5000000;
    uint32_t a = window(spin);
    loops = 10000000;
    uint32_t b = window(spin);
    /* Two loops differ by exactly 2 x 5 000 000 instructions (subs; bne). */
    double per_tick = 10000000.0 / (double)(b - a);
    printf("calibration overhead=%lu ticks, 1 tick = %.3f instructions\n", (unsigned long)overhead, per_tick);
#if PROTO == 1
    row("aeolus_parse_1", aeolus_bytes, stream_a, stream_a_end, per_tick);
    row("aeolus_parse", aeolus_slices, stream_a, stream_a_end, per_tick);
    row("aeolus_feed", aeolus_feed, stream_a, stream_a_end, per_tick);
    row("rust_aeolus_push", rust_aeolus_push, stream_a, stream_a_end, per_tick);
    row("rust_aeolus_feed", rust_aeolus_feed, stream_a, stream_a_end, per_tick);
#elif PROTO == 2
    row("aydp_parse_1", aydp_bytes, stream_a, stream_a_end, per_tick);
    row("aydp_parse", aydp_slices, stream_a, stream_a_end, per_tick);
    row("aydp_feed", aydp_feed, stream_a, stream_a_end, per_tick);
    row("rust_aydp_push", rust_aydp_push, stream_a, stream_a_end, per_tick);
    row("rust_aydp_feed", rust_aydp_feed, stream_a, stream_a_end, per_tick);
#else
    row("aok_pc_parse_1", pc_bytes, stream_a, stream_a_end, per_tick);
    row("aok_pc_parse", pc_slices, stream_a, stream_a_end, per_tick);
    row("aok_pc_feed", pc_feed, stream_a, stream_a_end, per_tick);
    row("rust_aok_pc_push", rust_aok_pc_push, stream_a, stream_a_end, per_tick);
    row("rust_aok_pc_feed", rust_aok_pc_feed, stream_a, stream_a_end, per_tick);
#endif
    exit(0);
}
