/* Hostile input through the C API (included by host_test.c): random bytes, truncated,
 * corrupted and oversized frames, NULL pointers and absurd lengths. The sanitizers report any
 * memory or undefined-behaviour error; the checks here make sure the errors are reported as
 * codes and events. */

static uint64_t rng_state = 0x9E3779B97F4A7C15u;

static uint64_t rng(void) {
    /* xorshift64*: reproducible, no libc state. */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545F4914F6CDD1Du;
}

/* Every decoder over buf, with the slice calls in random chunks. Returns the events. */
static long all_decoders(const uint8_t *buf, size_t len) {
    static const char *protos[] = {"aeolus", "aydp-spec", "aydp-reference", "aok-pc", "aok-device", "gdl90"};
    long events = 0;
    for (int p = 0; p < 6; p++) {
        long slices = dump(protos[p], buf, len, (size_t)(rng() % 300), 0);
        /* The feed calls (other chunking) give exactly the events of the slice calls. */
        CHECK(count_feed(protos[p], buf, len, (size_t)(rng() % 4096)) == slices);
        events += slices;
    }
    return events;
}

static void null_checks(void) {
    pl_error err;
    uint8_t buf[8];
    size_t used;
    pl_aeolus_decoder ad;
    pl_aeolus_message am;
    pl_aeolus_stats as;
    CHECK(pl_aeolus_init(NULL) == PL_E_NULL);
    CHECK(pl_aeolus_init_strict(NULL) == PL_E_NULL);
    pl_aeolus_init(&ad);
    CHECK(BYTE(pl_aeolus_parse, NULL, 0, &am, &err) == PL_E_NULL);
    CHECK(BYTE(pl_aeolus_parse, &ad, 0, NULL, &err) == PL_E_NULL);
    CHECK(BYTE(pl_aeolus_parse, &ad, 0, &am, NULL) == PL_E_NULL);
    CHECK(pl_aeolus_parse(&ad, NULL, 5, &used, &am, &err) == PL_E_NULL);
    CHECK(pl_aeolus_parse(&ad, NULL, 0, &used, &am, &err) == PL_NOTHING && used == 0);
    CHECK(pl_aeolus_parse(&ad, buf, SIZE_MAX, &used, &am, &err) == PL_E_NULL);
    CHECK(pl_aeolus_parse(&ad, buf, 1, NULL, &am, &err) == PL_E_NULL);
    CHECK(pl_aeolus_finish(NULL, &am, &err) == PL_E_NULL);
    CHECK(pl_aeolus_get_stats(&ad, NULL) == PL_E_NULL);
    CHECK(pl_aeolus_get_stats(NULL, &as) == PL_E_NULL);
    memset(&am, 0, sizeof am);
    am.id = PL_AEOLUS_ID_GYRO;
    CHECK(pl_aeolus_encode(NULL, buf, sizeof buf) == PL_E_NULL);
    CHECK(pl_aeolus_encode(&am, NULL, 100) == PL_E_NULL);
    CHECK(pl_aeolus_encode(&am, buf, sizeof buf) == PL_E_BUFFER_TOO_SMALL);
    CHECK(pl_aeolus_encode(&am, buf, 0) == PL_E_BUFFER_TOO_SMALL);
    am.id = PL_AEOLUS_ID_LOG;
    am.data_len = 10; /* data NULL with a length */
    CHECK(pl_aeolus_encode(&am, buf, sizeof buf) == PL_E_NULL);
    CHECK(pl_aeolus_max_encoded_len(SIZE_MAX) == SIZE_MAX);
    CHECK(pl_aeolus_max_encoded_len(32) == 72);
    CHECK(pl_aeolus_feed(&ad, buf, 1, NULL, NULL) == PL_E_NULL);
    CHECK(pl_aeolus_feed(NULL, buf, 1, count_aeolus, NULL) == PL_E_NULL);
    CHECK(pl_aeolus_feed(&ad, NULL, 1, count_aeolus, NULL) == PL_E_NULL);

    pl_aydp_decoder yd;
    pl_aydp_message ym;
    CHECK(pl_aydp_init(NULL, PL_AYDP_SPEC) == PL_E_NULL);
    CHECK(pl_aydp_init(&yd, 2) == PL_E_BAD_TAG);
    pl_aydp_init(&yd, PL_AYDP_SPEC);
    CHECK(BYTE(pl_aydp_parse, &yd, 0, NULL, &err) == PL_E_NULL);
    CHECK(QUEUED(pl_aydp_parse, &yd, &ym, NULL) == PL_E_NULL);
    CHECK(pl_aydp_finish(NULL, &ym, &err) == PL_E_NULL);
    CHECK(pl_aydp_parse(&yd, NULL, 3, &used, &ym, &err) == PL_E_NULL);
    CHECK(pl_aydp_get_stats(&yd, NULL) == PL_E_NULL);
    CHECK(pl_aydp_feed(&yd, buf, 1, NULL, NULL) == PL_E_NULL);
    CHECK(pl_aydp_encode(PL_AYDP_SPEC, NULL, buf, sizeof buf) == PL_E_NULL);
    memset(&ym, 0, sizeof ym);
    ym.kind = PL_AYDP_FIX_DETAIL;
    CHECK(pl_aydp_satellite_at(&ym, 0, NULL) == PL_E_NULL);
    pl_aydp_satellite sat;
    CHECK(pl_aydp_satellite_at(&ym, 0, &sat) == PL_E_BAD_TAG); /* no data */
    pl_aydp_output_entry entry;
    CHECK(pl_aydp_output_entry_at(&ym, 0, &entry) == PL_E_BAD_TAG); /* wrong kind */
    ym.kind = PL_AYDP_SYSTEM_VALUE_UPDATE;
    ym.body.update.value = NULL;
    ym.body.update.value_len = 4;
    ym.body.update.mode = 1;
    CHECK(pl_aydp_encode(PL_AYDP_SPEC, &ym, buf, sizeof buf) == PL_E_NULL);

    pl_aok_device_decoder kd;
    pl_aok_pc_decoder kp;
    pl_aok_item it;
    pl_aok_stats ks;
    CHECK(pl_aok_device_init(NULL) == PL_E_NULL);
    CHECK(pl_aok_pc_init(NULL, 0, 35) == PL_E_NULL);
    pl_aok_device_init(&kd);
    pl_aok_pc_init(&kp, 0, 30);
    CHECK(BYTE(pl_aok_device_parse, &kd, 0, NULL, &err) == PL_E_NULL);
    CHECK(QUEUED(pl_aok_device_parse, NULL, &it, &err) == PL_E_NULL);
    CHECK(pl_aok_device_finish(&kd, &it, NULL) == PL_E_NULL);
    CHECK(pl_aok_device_parse(&kd, buf, 1, NULL, &it, &err) == PL_E_NULL);
    CHECK(pl_aok_device_get_stats(NULL, &ks) == PL_E_NULL);
    CHECK(BYTE(pl_aok_pc_parse, NULL, 0, &it, &err) == PL_E_NULL);
    CHECK(QUEUED(pl_aok_pc_parse, &kp, NULL, &err) == PL_E_NULL);
    CHECK(pl_aok_pc_finish(&kp, &it, NULL) == PL_E_NULL);
    CHECK(pl_aok_pc_parse(&kp, NULL, 2, &used, &it, &err) == PL_E_NULL);
    CHECK(pl_aok_pc_get_stats(&kp, NULL) == PL_E_NULL);
    CHECK(pl_aok_pc_expect_reply(&kp, NULL) == PL_E_NULL);
    CHECK(pl_aok_pc_feed(&kp, buf, 1, NULL, NULL) == PL_E_NULL);
    CHECK(pl_aok_device_feed(&kd, NULL, 3, count_aok, NULL) == PL_E_NULL);
    CHECK(pl_aok_encode_command(NULL, buf, sizeof buf) == PL_E_NULL);
    CHECK(pl_aok_encode_message(NULL, 1, buf, sizeof buf) == PL_E_NULL);
    memset(&it, 0, sizeof it);
    CHECK(pl_aok_encode_command(&it, NULL, 10) == PL_E_NULL);

    pl_gdl90_decoder gd;
    pl_gdl90_message gm;
    CHECK(pl_gdl90_init(NULL) == PL_E_NULL);
    pl_gdl90_init(&gd);
    CHECK(BYTE(pl_gdl90_parse, &gd, 0, &gm, NULL) == PL_E_NULL);
    CHECK(pl_gdl90_parse(&gd, NULL, 1, &used, &gm, &err) == PL_E_NULL);
    CHECK(pl_gdl90_finish(NULL, &gm, &err) == PL_E_NULL);
    CHECK(pl_gdl90_finish(&gd, NULL, &err) == PL_E_NULL);
    CHECK(pl_gdl90_finish(&gd, &gm, NULL) == PL_E_NULL);
    CHECK(pl_gdl90_get_stats(NULL, NULL) == PL_E_NULL);
    CHECK(pl_gdl90_encode(NULL, buf, sizeof buf) == PL_E_NULL);
    CHECK(pl_gdl90_feed(&gd, buf, 1, NULL, NULL) == PL_E_NULL);
    memset(&gm, 0, sizeof gm);
    gm.kind = 77;
    CHECK(pl_gdl90_encode(&gm, buf, sizeof buf) == PL_E_BAD_TAG);
}

/* A frame longer than every decoder's capacity gives an overflow (AEOLUS, GDL90) or a length
 * error (AYDP), and the decoder still reads the next good frame. */
static void oversized(void) {
    static uint8_t big[4096];
    pl_error err;
    size_t used;
    /* AEOLUS and GDL90: a flag, 1000 ordinary bytes, a flag, then a good GYRO frame. */
    pl_aeolus_message am;
    memset(&am, 0, sizeof am);
    am.id = PL_AEOLUS_ID_GYRO;
    uint8_t good[PL_AEOLUS_MAX_FRAME_LEN];
    int32_t n = pl_aeolus_encode(&am, good, sizeof good);
    CHECK(n > 0);
    size_t len = 0;
    big[len++] = 0x7E;
    for (int i = 0; i < 1000; i++) big[len++] = 0x11;
    memcpy(big + len, good, (size_t)n);
    len += (size_t)n;
    pl_aeolus_decoder ad;
    pl_aeolus_init(&ad);
    int overflow = 0, gyro = 0;
    for (size_t off = 0; off < len; off += used) {
        int st = pl_aeolus_parse(&ad, big + off, len - off, &used, &am, &err);
        if (st == PL_ERROR && err.kind == PL_ERR_OVERFLOW) overflow++;
        if (st == PL_MESSAGE && am.id == PL_AEOLUS_ID_GYRO) gyro++;
    }
    CHECK(overflow == 1 && gyro == 1);
    pl_gdl90_decoder gd;
    pl_gdl90_message gm;
    pl_gdl90_init(&gd);
    overflow = 0;
    for (size_t off = 0; off < len; off += used) {
        int st = pl_gdl90_parse(&gd, big + off, len - off, &used, &gm, &err);
        if (st == PL_ERROR && err.kind == PL_ERR_OVERFLOW) overflow++;
    }
    CHECK(overflow == 1);

    /* AYDP: a header announcing 100000 bytes, then a good message. */
    pl_aydp_message ym;
    memset(&ym, 0, sizeof ym);
    ym.kind = PL_AYDP_HEARTBEAT;
    ym.expedited = 1;
    uint8_t hb[16];
    n = pl_aydp_encode(PL_AYDP_SPEC, &ym, hb, sizeof hb);
    CHECK(n == 7);
    uint8_t hostile[] = {0xFF, 0x03, 0xA0, 0x86, 0x01, 0x00};
    len = 0;
    memcpy(big, hostile, sizeof hostile);
    len += sizeof hostile;
    memcpy(big + len, hb, (size_t)n);
    len += (size_t)n;
    pl_aydp_decoder yd;
    pl_aydp_init(&yd, PL_AYDP_SPEC);
    int bad_length = 0, heartbeat = 0;
    for (size_t off = 0; off < len; off += used) {
        int st = pl_aydp_parse(&yd, big + off, len - off, &used, &ym, &err);
        if (st == PL_ERROR && err.kind == PL_ERR_BAD_LENGTH) bad_length++;
        if (st == PL_MESSAGE && ym.kind == PL_AYDP_HEARTBEAT) heartbeat++;
        if (st == PL_NOTHING && used == 0) break;
    }
    while (pl_aydp_finish(&yd, &ym, &err) > 0)
        if (ym.kind == PL_AYDP_HEARTBEAT) heartbeat++;
    CHECK(bad_length == 1 && heartbeat == 1);
}

/* Every prefix and every single-byte corruption of every round-trip frame file. */
static void truncated_and_corrupted(const char *dir) {
    static const char *protos[] = {"aeolus", "aydp-spec", "aydp-reference", "aok-pc", "aok-device", "gdl90"};
    for (int p = 0; p < 6; p++) {
        char path[512];
        snprintf(path, sizeof path, "%s/rt-%s.bin", dir, protos[p]);
        size_t len = 0;
        uint8_t *buf = read_file(path, &len);
        CHECK(buf != NULL);
        if (!buf) continue;
        size_t step = len > 600 ? len / 600 : 1;
        for (size_t cut = 0; cut <= len; cut += step) dump(protos[p], buf, cut, cut % 17, 0);
        for (size_t i = 0; i < len; i += step) {
            uint8_t saved = buf[i];
            buf[i] ^= (uint8_t)(1u << (i % 8));
            dump(protos[p], buf, len, i % 13, 0);
            buf[i] = 0xFF;
            dump(protos[p], buf, len, 0, 0);
            buf[i] = saved;
        }
        free(buf);
    }
}

static int cmd_hostile(int mbytes) {
    null_checks();
    oversized();
    const char *dir = getenv("RT_DIR");
    if (dir) truncated_and_corrupted(dir);
    size_t len = (size_t)mbytes << 20;
    uint8_t *buf = malloc(len ? len : 1);
    if (!buf) return 1;
    for (size_t i = 0; i < len; i++) buf[i] = (uint8_t)(rng() >> 56);
    long events = all_decoders(buf, len);
    /* The same bytes with frame starts sprinkled in, so decoders get deep into frames. */
    for (size_t i = 0; i < len; i += 1 + rng() % 64) buf[i] = (uint8_t[]){0x7E, 0xFF, 0x1C, 0x73}[rng() % 4];
    events += all_decoders(buf, len);
    free(buf);
    printf("hostile: %d MiB random twice, %ld events, %d failed checks\n", mbytes, events, failures);
    return failures != 0;
}
