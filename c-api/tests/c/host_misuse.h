/* Misused states through the C API (included by host_test.c, after host_hostile.h for rng()):
 * every call on a state its init did not set up (filled with 0x00, 0xA5, 0xFF or random
 * bytes, set up for another protocol, or moved to an odd address) returns PL_E_INVALID and
 * writes nothing, neither the state nor an output; init refuses an odd address. And the
 * header's sizes are the archive's: at compile time against the header's constants, at run
 * time against pl_state_size, pl_state_align and pl_abi_version. */

_Static_assert(sizeof(pl_aeolus_decoder) == PL_AEOLUS_DECODER_SIZE, "PL_AEOLUS_DECODER_SIZE");
_Static_assert(sizeof(pl_aydp_decoder) == PL_AYDP_DECODER_SIZE, "PL_AYDP_DECODER_SIZE");
_Static_assert(sizeof(pl_aok_device_decoder) == PL_AOK_DECODER_SIZE, "PL_AOK_DECODER_SIZE");
_Static_assert(sizeof(pl_aok_pc_decoder) == PL_AOK_DECODER_SIZE, "PL_AOK_DECODER_SIZE");
_Static_assert(sizeof(pl_gdl90_decoder) == PL_GDL90_DECODER_SIZE, "PL_GDL90_DECODER_SIZE");
_Static_assert(_Alignof(pl_aeolus_decoder) <= PL_AEOLUS_DECODER_ALIGN, "PL_AEOLUS_DECODER_ALIGN");
_Static_assert(_Alignof(pl_aydp_decoder) <= PL_AYDP_DECODER_ALIGN, "PL_AYDP_DECODER_ALIGN");
_Static_assert(_Alignof(pl_aok_pc_decoder) <= PL_AOK_DECODER_ALIGN, "PL_AOK_DECODER_ALIGN");
_Static_assert(_Alignof(pl_gdl90_decoder) <= PL_GDL90_DECODER_ALIGN, "PL_GDL90_DECODER_ALIGN");

/* Any state, as a firmware might share one buffer between protocols. */
typedef union {
    pl_aeolus_decoder aeolus;
    pl_aydp_decoder aydp;
    pl_aok_device_decoder aok_device;
    pl_aok_pc_decoder aok_pc;
    pl_gdl90_decoder gdl90;
} any_state;

/* Aligned for any state, and 8 bytes longer: a state fits at an odd address too. */
typedef struct {
    _Alignas(any_state) uint8_t bytes[sizeof(any_state) + 8];
} state_storage;

static const uint32_t kinds[] = {PL_STATE_AEOLUS, PL_STATE_AYDP, PL_STATE_AOK_DEVICE, PL_STATE_AOK_PC,
                                 PL_STATE_GDL90};

static const char *kind_name(uint32_t kind) {
    static const char *names[] = {"?", "AEOLUS", "AYDP", "AOK device", "AOK PC", "GDL90"};
    return kind < 6 ? names[kind] : "?";
}

/* Every output a call can write, filled with 0x5A before the calls; `fed` is set by the feed
 * callbacks. */
struct outputs {
    pl_aeolus_message aeolus;
    pl_aydp_message aydp;
    pl_gdl90_message gdl90;
    pl_aok_item item;
    pl_error err;
    size_t used;
    pl_aeolus_stats aeolus_stats;
    pl_aydp_stats aydp_stats;
    pl_aok_stats aok_stats;
    pl_gdl90_stats gdl90_stats;
    int fed;
};

static void fed_aeolus(void *ctx, int32_t st, const pl_aeolus_message *m, const pl_error *e) {
    (void)st, (void)m, (void)e;
    ((struct outputs *)ctx)->fed = 1;
}
static void fed_aydp(void *ctx, int32_t st, const pl_aydp_message *m, const pl_error *e) {
    (void)st, (void)m, (void)e;
    ((struct outputs *)ctx)->fed = 1;
}
static void fed_aok(void *ctx, int32_t st, const pl_aok_item *m, const pl_error *e) {
    (void)st, (void)m, (void)e;
    ((struct outputs *)ctx)->fed = 1;
}
static void fed_gdl90(void *ctx, int32_t st, const pl_gdl90_message *m, const pl_error *e) {
    (void)st, (void)m, (void)e;
    ((struct outputs *)ctx)->fed = 1;
}

/* The init of `kind` on the storage at p (the AEOLUS strict init and the AYDP Reference
 * profile write the same tags as these). */
static int32_t init_state(uint32_t kind, void *p) {
    switch (kind) {
    case PL_STATE_AEOLUS: return pl_aeolus_init(p);
    case PL_STATE_AYDP: return pl_aydp_init(p, PL_AYDP_SPEC);
    case PL_STATE_AOK_DEVICE: return pl_aok_device_init(p);
    case PL_STATE_AOK_PC: return pl_aok_pc_init(p, 0, 35);
    default: return pl_gdl90_init(p);
    }
}

/* Every call on the state of `kind` at p but init, with valid other arguments (bytes that
 * complete no frame); the statuses go to st[], the count is returned. */
static int state_calls(uint32_t kind, void *p, struct outputs *o, int32_t *st) {
    static const uint8_t bytes[4] = {0x7E, 0x3E, 0xFF, 0x63};
    const pl_aok_item get = {.kind = PL_AOK_READ_PARAMETER, .number = 12};
    int n = 0;
    switch (kind) {
    case PL_STATE_AEOLUS:
        st[n++] = BYTE(pl_aeolus_parse, p, 0x7E, &o->aeolus, &o->err);
        st[n++] = pl_aeolus_parse(p, bytes, 4, &o->used, &o->aeolus, &o->err);
        st[n++] = pl_aeolus_feed(p, bytes, 4, fed_aeolus, o);
        st[n++] = pl_aeolus_finish(p, &o->aeolus, &o->err);
        st[n++] = pl_aeolus_get_stats(p, &o->aeolus_stats);
        break;
    case PL_STATE_AYDP:
        st[n++] = BYTE(pl_aydp_parse, p, 0xFF, &o->aydp, &o->err);
        st[n++] = QUEUED(pl_aydp_parse, p, &o->aydp, &o->err);
        st[n++] = pl_aydp_parse(p, bytes, 4, &o->used, &o->aydp, &o->err);
        st[n++] = pl_aydp_feed(p, bytes, 4, fed_aydp, o);
        st[n++] = pl_aydp_finish(p, &o->aydp, &o->err);
        st[n++] = pl_aydp_get_stats(p, &o->aydp_stats);
        break;
    case PL_STATE_AOK_DEVICE:
        st[n++] = BYTE(pl_aok_device_parse, p, 0x63, &o->item, &o->err);
        st[n++] = QUEUED(pl_aok_device_parse, p, &o->item, &o->err);
        st[n++] = pl_aok_device_finish(p, &o->item, &o->err);
        st[n++] = pl_aok_device_parse(p, bytes, 4, &o->used, &o->item, &o->err);
        st[n++] = pl_aok_device_feed(p, bytes, 4, fed_aok, o);
        st[n++] = pl_aok_device_get_stats(p, &o->aok_stats);
        break;
    case PL_STATE_AOK_PC:
        st[n++] = pl_aok_pc_expect_reply(p, &get);
        st[n++] = BYTE(pl_aok_pc_parse, p, 0x1C, &o->item, &o->err);
        st[n++] = QUEUED(pl_aok_pc_parse, p, &o->item, &o->err);
        st[n++] = pl_aok_pc_finish(p, &o->item, &o->err);
        st[n++] = pl_aok_pc_parse(p, bytes, 4, &o->used, &o->item, &o->err);
        st[n++] = pl_aok_pc_feed(p, bytes, 4, fed_aok, o);
        st[n++] = pl_aok_pc_get_stats(p, &o->aok_stats);
        break;
    default:
        st[n++] = BYTE(pl_gdl90_parse, p, 0x7E, &o->gdl90, &o->err);
        st[n++] = pl_gdl90_parse(p, bytes, 4, &o->used, &o->gdl90, &o->err);
        st[n++] = pl_gdl90_feed(p, bytes, 4, fed_gdl90, o);
        st[n++] = pl_gdl90_finish(p, &o->gdl90, &o->err);
        st[n++] = pl_gdl90_get_stats(p, &o->gdl90_stats);
        break;
    }
    return n;
}

static int refused_calls; /* calls that returned PL_E_INVALID as they must */

/* Every call on the state of `kind` at p returns PL_E_INVALID and writes nothing. */
static void expect_refused(uint32_t kind, void *p, const char *what) {
    static struct outputs o, before;
    static uint8_t state_before[sizeof(any_state)];
    size_t size = pl_state_size(kind);
    memset(&o, 0x5A, sizeof o);
    memcpy(&before, &o, sizeof o);
    memcpy(state_before, p, size);
    int32_t st[8];
    int n = state_calls(kind, p, &o, st);
    for (int i = 0; i < n; i++) {
        if (st[i] == PL_E_INVALID) {
            refused_calls++;
        } else {
            fprintf(stderr, "%s state %s: call %d returned %d, not PL_E_INVALID\n", kind_name(kind), what, i, st[i]);
            failures++;
        }
    }
    if (memcmp(&o, &before, sizeof o) != 0) {
        fprintf(stderr, "%s state %s: an output was written\n", kind_name(kind), what);
        failures++;
    }
    if (memcmp(p, state_before, size) != 0) {
        fprintf(stderr, "%s state %s: the state was written\n", kind_name(kind), what);
        failures++;
    }
}

static void abi_checks(void) {
    CHECK(pl_abi_version() == PL_ABI_VERSION);
    CHECK(pl_state_size(PL_STATE_AEOLUS) == sizeof(pl_aeolus_decoder));
    CHECK(pl_state_size(PL_STATE_AYDP) == sizeof(pl_aydp_decoder));
    CHECK(pl_state_size(PL_STATE_AOK_DEVICE) == sizeof(pl_aok_device_decoder));
    CHECK(pl_state_size(PL_STATE_AOK_PC) == sizeof(pl_aok_pc_decoder));
    CHECK(pl_state_size(PL_STATE_GDL90) == sizeof(pl_gdl90_decoder));
    CHECK(pl_state_align(PL_STATE_AEOLUS) == _Alignof(pl_aeolus_decoder));
    CHECK(pl_state_align(PL_STATE_AYDP) == _Alignof(pl_aydp_decoder));
    CHECK(pl_state_align(PL_STATE_AOK_DEVICE) == _Alignof(pl_aok_device_decoder));
    CHECK(pl_state_align(PL_STATE_AOK_PC) == _Alignof(pl_aok_pc_decoder));
    CHECK(pl_state_align(PL_STATE_GDL90) == _Alignof(pl_gdl90_decoder));
    CHECK(pl_state_size(0) == 0 && pl_state_align(0) == 0);
    CHECK(pl_state_size(6) == 0 && pl_state_align(UINT32_MAX) == 0);
}

static int cmd_misuse(void) {
    static state_storage mem, good;
    abi_checks();
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        uint32_t kind = kinds[k];
        size_t size = pl_state_size(kind);
        struct outputs o;
        int32_t st[8];
        char what[64];

        /* Set up by its init: every call accepts it (the control). */
        memset(&mem, 0xA5, sizeof mem);
        CHECK(init_state(kind, mem.bytes) == 0);
        int n = state_calls(kind, mem.bytes, &o, st);
        for (int i = 0; i < n; i++) CHECK(st[i] >= 0);

        /* Never set up. */
        static const uint8_t fills[] = {0x00, 0xA5, 0xFF};
        for (size_t f = 0; f < sizeof fills; f++) {
            memset(&mem, fills[f], sizeof mem);
            snprintf(what, sizeof what, "filled with 0x%02X", fills[f]);
            expect_refused(kind, mem.bytes, what);
        }
        for (int r = 0; r < 3; r++) {
            for (size_t i = 0; i < sizeof mem.bytes; i++) mem.bytes[i] = (uint8_t)(rng() >> 56);
            expect_refused(kind, mem.bytes, "of random bytes");
        }

        /* Set up for another protocol. */
        for (size_t j = 0; j < sizeof kinds / sizeof kinds[0]; j++) {
            if (j == k) continue;
            memset(&mem, 0, sizeof mem);
            CHECK(init_state(kinds[j], mem.bytes) == 0);
            snprintf(what, sizeof what, "set up as %s", kind_name(kinds[j]));
            expect_refused(kind, mem.bytes, what);
        }

        /* Not aligned: init refuses an odd address and writes nothing; a good state moved
         * there, tag and all, is refused. */
        memset(&mem, 0, sizeof mem);
        CHECK(init_state(kind, mem.bytes + 1) == PL_E_INVALID);
        for (size_t i = 0; i < sizeof mem.bytes; i++) CHECK(mem.bytes[i] == 0);
        memset(&good, 0, sizeof good);
        CHECK(init_state(kind, good.bytes) == 0);
        memcpy(mem.bytes + 1, good.bytes, size);
        expect_refused(kind, mem.bytes + 1, "moved to an odd address");
    }
    printf("misuse: %d calls on misused states, each PL_E_INVALID with nothing written; "
           "sizes, alignments and ABI version as the header says; %d failed checks\n",
           refused_calls, failures);
    return failures != 0;
}
