/* Round trips of every message type through the C encoders and decoders (included by
 * host_test.c). Each message is encoded, decoded byte by byte, re-encoded from the decoded
 * struct, and the two frames must be equal byte for byte; the frames go to DIR/rt-*.bin,
 * which host.sh then dumps and compares with `protolink decode --json`. */

static FILE *open_out(const char *dir, const char *name) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f) fprintf(stderr, "cannot write %s\n", path);
    return f;
}

static int aeolus_rt(FILE *out, const pl_aeolus_message *m) {
    uint8_t a[PL_AEOLUS_MAX_FRAME_LEN], b[PL_AEOLUS_MAX_FRAME_LEN];
    int32_t n = pl_aeolus_encode(m, a, sizeof a);
    CHECK(n > 0);
    if (n <= 0) return 0;
    /* One byte short never fits. */
    CHECK(pl_aeolus_encode(m, a, (size_t)n - 1) == PL_E_BUFFER_TOO_SMALL);
    n = pl_aeolus_encode(m, a, sizeof a);
    pl_aeolus_decoder d;
    pl_aeolus_message got;
    pl_error err;
    pl_aeolus_init(&d);
    int events = 0;
    for (int32_t i = 0; i < n; i++) {
        int st = BYTE(pl_aeolus_parse, &d, a[i], &got, &err);
        if (st == PL_MESSAGE) {
            events++;
            CHECK(i == n - 1);
            CHECK(got.id == m->id);
            int32_t k = pl_aeolus_encode(&got, b, sizeof b);
            CHECK(k == n && memcmp(a, b, (size_t)n) == 0);
        }
        CHECK(st != PL_ERROR);
    }
    CHECK(events == 1);
    fwrite(a, 1, (size_t)n, out);
    return 1;
}

static int aydp_rt(FILE *out, uint32_t profile, const pl_aydp_message *m) {
    uint8_t a[PL_AYDP_MAX_FRAME_LEN], b[PL_AYDP_MAX_FRAME_LEN];
    int32_t n = pl_aydp_encode(profile, m, a, sizeof a);
    CHECK(n > 0);
    if (n <= 0) return 0;
    CHECK(pl_aydp_encode(profile, m, a, (size_t)n - 1) == PL_E_BUFFER_TOO_SMALL);
    n = pl_aydp_encode(profile, m, a, sizeof a);
    pl_aydp_decoder d;
    pl_aydp_message got;
    pl_error err;
    pl_aydp_init(&d, profile);
    int events = 0;
    for (int32_t i = 0; i < n; i++) {
        for (int st = BYTE(pl_aydp_parse, &d, a[i], &got, &err); st > 0; st = QUEUED(pl_aydp_parse, &d, &got, &err)) {
            CHECK(st == PL_MESSAGE);
            events++;
            CHECK(got.kind == m->kind && got.expedited == m->expedited);
            int32_t k = pl_aydp_encode(profile, &got, b, sizeof b);
            CHECK(k == n && memcmp(a, b, (size_t)n) == 0);
        }
    }
    CHECK(events == 1);
    fwrite(a, 1, (size_t)n, out);
    return 1;
}

static int aok_cmd_rt(FILE *out, const pl_aok_item *c) {
    uint8_t a[PL_AOK_MAX_FRAME_LEN], b[PL_AOK_MAX_FRAME_LEN];
    int32_t n = pl_aok_encode_command(c, a, sizeof a);
    CHECK(n > 0);
    if (n <= 0) return 0;
    CHECK(pl_aok_encode_command(c, a, (size_t)n - 1) == PL_E_BUFFER_TOO_SMALL);
    pl_aok_device_decoder d;
    pl_aok_item got;
    pl_error err;
    pl_aok_device_init(&d);
    int events = 0;
    for (int32_t i = 0; i < n; i++)
        for (int st = BYTE(pl_aok_device_parse, &d, a[i], &got, &err); st > 0;
             st = QUEUED(pl_aok_device_parse, &d, &got, &err)) {
            CHECK(st == PL_MESSAGE);
            events++;
            CHECK(memcmp(&got, c, sizeof got) == 0 || got.kind == c->kind);
            int32_t k = pl_aok_encode_command(&got, b, sizeof b);
            CHECK(k == n && memcmp(a, b, (size_t)n) == 0);
        }
    CHECK(events == 1);
    fwrite(a, 1, (size_t)n, out);
    return 1;
}

/* A device message, read by a PC decoder expecting the reply to `asked` (NULL: nothing). */
static int aok_msg_rt(FILE *out, const pl_aok_item *m, const pl_aok_item *asked) {
    uint8_t a[PL_AOK_MAX_FRAME_LEN], b[PL_AOK_MAX_FRAME_LEN];
    int32_t n = pl_aok_encode_message(m, 1, a, sizeof a);
    CHECK(n > 0);
    if (n <= 0) return 0;
    CHECK(pl_aok_encode_message(m, 1, a, (size_t)n - 1) == PL_E_BUFFER_TOO_SMALL);
    pl_aok_pc_decoder d;
    pl_aok_item got;
    pl_error err;
    pl_aok_pc_init(&d, 0, 35);
    if (asked) CHECK(pl_aok_pc_expect_reply(&d, asked) == 0);
    int events = 0;
    for (int32_t i = 0; i < n; i++)
        for (int st = BYTE(pl_aok_pc_parse, &d, a[i], &got, &err); st > 0; st = QUEUED(pl_aok_pc_parse, &d, &got, &err)) {
            CHECK(st == PL_MESSAGE);
            events++;
            CHECK(got.kind == m->kind);
            int32_t k = pl_aok_encode_message(&got, 1, b, sizeof b);
            CHECK(k == n && memcmp(a, b, (size_t)n) == 0);
        }
    CHECK(events == 1);
    if (out) fwrite(a, 1, (size_t)n, out);
    return 1;
}

static int gdl90_rt(FILE *out, const pl_gdl90_message *m) {
    uint8_t a[PL_GDL90_MAX_FRAME_LEN + 64], b[PL_GDL90_MAX_FRAME_LEN + 64];
    int32_t n = pl_gdl90_encode(m, a, sizeof a);
    CHECK(n > 0);
    if (n <= 0) return 0;
    CHECK(pl_gdl90_encode(m, a, (size_t)n - 1) == PL_E_BUFFER_TOO_SMALL);
    n = pl_gdl90_encode(m, a, sizeof a);
    pl_gdl90_decoder d;
    pl_gdl90_message got;
    pl_error err;
    pl_gdl90_init(&d);
    int events = 0;
    for (int32_t i = 0; i < n; i++) {
        int st = BYTE(pl_gdl90_parse, &d, a[i], &got, &err);
        if (st == PL_MESSAGE) {
            events++;
            CHECK(got.kind == m->kind);
            int32_t k = pl_gdl90_encode(&got, b, sizeof b);
            CHECK(k == n && memcmp(a, b, (size_t)n) == 0);
        }
        CHECK(st != PL_ERROR);
    }
    CHECK(events == 1);
    fwrite(a, 1, (size_t)n, out);
    return 1;
}

static int cmd_roundtrip(const char *dir) {
    int count = 0;
    FILE *f = open_out(dir, "rt-aeolus.bin");
    if (!f) return 1;
    {
        static uint8_t raw[208];
        for (int i = 0; i < 208; i++) raw[i] = (uint8_t)(i * 37 + 0x7D); /* escapes included */
        pl_aeolus_message m;
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_AEOLUSINFO;
        m.body.info = (pl_aeolus_info){.model = 83, .firmware = {3, 8, 0}, .mac = {0x7C, 0xDD, 0x90, 0x7E, 0x7D, 10}};
        count += aeolus_rt(f, &m);
        uint8_t motion_ids[] = {PL_AEOLUS_ID_PRESSURE, PL_AEOLUS_ID_GYRO, PL_AEOLUS_ID_ACCEL, PL_AEOLUS_ID_MAGNET};
        for (int i = 0; i < 4; i++) {
            memset(&m, 0, sizeof m);
            m.id = motion_ids[i];
            m.body.motion = (pl_aeolus_motion){.valid = 1, .timestamp_ms = 123456.5 + i, .x = 0.5f, .y = -1.25f, .z = 1013.25f};
            count += aeolus_rt(f, &m);
        }
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_TEMP;
        m.body.temp = (pl_aeolus_temp){.valid = 1, .timestamp_ms = 7.25, .celsius = -12.5f};
        count += aeolus_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_GPS;
        m.body.gps = (pl_aeolus_gps){1, 1, 9, 5000.0, 37.9375f, 23.75f, 152.5f, 41.25f};
        count += aeolus_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_ATTITUDE;
        m.body.attitude = (pl_aeolus_attitude){1, 7.0, 0.125f, -0.0625f, 1.5f, 0.03125f, -0.25f, 0.0625f, -0.03125f, 0.6875f, 0.71875f};
        count += aeolus_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_COMPASS;
        m.body.compass = (pl_aeolus_compass){.valid = 1, .calibration = -3, .has_value = 1, .calibration_percent = 40,
                                             .calibration_remaining = 12, .timestamp_ms = 99.0, .heading_deg = 271.5f,
                                             .soft_iron = {1, 2, 3}, .hard_iron = {1, 0, 0, 0, 1, 0, 0, 0, 1}};
        count += aeolus_rt(f, &m);
        m.body.compass.calibration = 7; /* an unknown status is kept */
        count += aeolus_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_WIND;
        m.body.wind = (pl_aeolus_wind){1, 1.0, 5.5f, 270.0f};
        count += aeolus_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_SETTIME;
        m.body.settime = (pl_aeolus_settime){126, 10, 24, 13, 45, 7};
        count += aeolus_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.id = PL_AEOLUS_ID_TOAST;
        m.data = (const uint8_t *)"AEOLUS on";
        m.data_len = 9;
        count += aeolus_rt(f, &m);
        m.no_crc = 1;
        count += aeolus_rt(f, &m);
        m.no_crc = 0;
        m.id = PL_AEOLUS_ID_COMMAND;
        m.data = (const uint8_t *)"a reboot";
        m.data_len = 8;
        count += aeolus_rt(f, &m);
        m.id = PL_AEOLUS_ID_CALIBINFO;
        m.data = raw;
        m.data_len = 32;
        count += aeolus_rt(f, &m);
        m.id = PL_AEOLUS_ID_DEBUGINFO;
        m.data_len = 208;
        count += aeolus_rt(f, &m);
        m.id = PL_AEOLUS_ID_LOG;
        m.data_len = 40;
        count += aeolus_rt(f, &m);
        m.id = 99; /* unknown, kept raw */
        m.data_len = 5;
        count += aeolus_rt(f, &m);
        /* A text one byte over the capacity is refused. */
        static uint8_t long_text[PL_AEOLUS_TEXT_CAPACITY + 1];
        memset(long_text, 'x', sizeof long_text);
        m.id = PL_AEOLUS_ID_TOAST;
        m.data = long_text;
        m.data_len = sizeof long_text;
        uint8_t out[PL_AEOLUS_MAX_FRAME_LEN];
        CHECK(pl_aeolus_encode(&m, out, sizeof out) == PL_E_INVALID);
    }
    fclose(f);

    for (int p = 0; p < 2; p++) {
        uint32_t profile = p ? PL_AYDP_REFERENCE : PL_AYDP_SPEC;
        f = open_out(dir, p ? "rt-aydp-reference.bin" : "rt-aydp-spec.bin");
        if (!f) return 1;
        pl_aydp_message m;
        memset(&m, 0, sizeof m);
        m.seconds = 1700000000;
        m.subsec = p ? 250000 : 250;
        if (!p) {
            m.kind = PL_AYDP_TIME_SYNC;
            count += aydp_rt(f, profile, &m);
            m.kind = PL_AYDP_HEARTBEAT;
            m.expedited = 1;
            count += aydp_rt(f, profile, &m);
            m.expedited = 0;
            m.kind = PL_AYDP_TBD;
            m.msg_type = 2;
            m.data = (const uint8_t *)"\x01\x02\x03";
            m.data_len = 3;
            count += aydp_rt(f, profile, &m);
        } else {
            m.kind = PL_AYDP_NO_OP;
            count += aydp_rt(f, profile, &m);
            m.kind = PL_AYDP_WIND_SPEED;
            m.body.value = 3.5f;
            count += aydp_rt(f, profile, &m);
            m.kind = PL_AYDP_WIND_DIRECTION;
            m.body.value = 271.25f;
            count += aydp_rt(f, profile, &m);
            /* The Reference profile has no expedited header: its encoder refuses one. */
            m.expedited = 1;
            uint8_t refused[PL_AYDP_MAX_FRAME_LEN];
            CHECK(pl_aydp_encode(profile, &m, refused, sizeof refused) == PL_E_INVALID);
            m.expedited = 0;
            m.kind = PL_AYDP_VESSEL_DATA;
            m.body.vessel = (pl_aydp_vessel){0.1f, -0.2f, 181.5f, 0.01f, 0.02f, -0.03f, 50.5, -1.25, 182.0f, 6.5f, 3, 11, 1.25f, 0.875f, 1.5f};
            count += aydp_rt(f, profile, &m);
        }
        m.kind = PL_AYDP_POSITION;
        m.body.position = (pl_aydp_position){48.35380179864062, 11.78610027105043, 1000.0f};
        count += aydp_rt(f, profile, &m);
        m.kind = PL_AYDP_FIX_QUALITY;
        m.body.fix_quality = (pl_aydp_fix_quality){3, 1.25f, 0.875f, 1.5f, 10};
        count += aydp_rt(f, profile, &m);
        /* Fix detail: count 2, then id and three uflt16 (1.0 = 0x3C00, 2.0 = 0x4000). */
        static const uint8_t fix[] = {2, 5, 0x00, 0x3C, 0x00, 0x40, 0x00, 0x3C, 9, 0x00, 0x40, 0x00, 0x3C, 0x00, 0x40};
        m.kind = PL_AYDP_FIX_DETAIL;
        m.data = fix;
        m.data_len = sizeof fix;
        count += aydp_rt(f, profile, &m);
        /* Direct output: count 1, device 1, channel 2, 10.0f. */
        static const uint8_t out[] = {1, 0, 1, 2, 0x00, 0x00, 0x20, 0x41};
        m.kind = PL_AYDP_DIRECT_OUTPUT;
        m.data = out;
        m.data_len = sizeof out;
        count += aydp_rt(f, profile, &m);
        static const uint8_t value[] = {0, 0, 0x81, 0x42};
        m.kind = PL_AYDP_SYSTEM_VALUE_UPDATE;
        m.data = NULL;
        m.data_len = 0;
        m.body.update = (pl_aydp_update){0x0110, 1, 0, value, sizeof value};
        count += aydp_rt(f, profile, &m);
        m.body.update = (pl_aydp_update){0x0120, 3, 2, value, sizeof value};
        count += aydp_rt(f, profile, &m);
        m.kind = PL_AYDP_SYSTEM_CONTROL;
        /* Expedited where the profile has that header (Spec), normal in Reference. */
        m.expedited = !p;
        m.body.control = (pl_aydp_control){1, 8};
        count += aydp_rt(f, profile, &m);
        m.body.control = (pl_aydp_control){2, 0};
        count += aydp_rt(f, profile, &m);
        m.expedited = 0;
        m.kind = PL_AYDP_USER_DEFINED;
        m.msg_type = 100;
        m.data = (const uint8_t *)"user";
        m.data_len = 4;
        count += aydp_rt(f, profile, &m);
        m.kind = PL_AYDP_UNKNOWN;
        m.msg_type = 50;
        count += aydp_rt(f, profile, &m);
        /* Out of range and invalid values are refused with their codes. */
        uint8_t buf[64];
        m.msg_type = 127;
        CHECK(pl_aydp_encode(profile, &m, buf, sizeof buf) == PL_E_OUT_OF_RANGE);
        m.kind = PL_AYDP_SYSTEM_CONTROL;
        m.body.control.command = 3;
        CHECK(pl_aydp_encode(profile, &m, buf, sizeof buf) == PL_E_INVALID);
        m.kind = PL_AYDP_FIX_DETAIL;
        m.data = fix;
        m.data_len = sizeof fix - 1;
        CHECK(pl_aydp_encode(profile, &m, buf, sizeof buf) == PL_E_INVALID);
        m.kind = 200;
        CHECK(pl_aydp_encode(profile, &m, buf, sizeof buf) == PL_E_BAD_TAG);
        CHECK(pl_aydp_encode(7, &m, buf, sizeof buf) == PL_E_BAD_TAG);
        fclose(f);
    }

    f = open_out(dir, "rt-aok-pc.bin");
    if (!f) return 1;
    for (uint8_t k = PL_AOK_DEBUG_OFF; k <= PL_AOK_EXTERNAL_CONTROL; k++) {
        pl_aok_item c;
        memset(&c, 0, sizeof c);
        c.kind = k;
        c.number = 12;
        c.value = -1500;
        c.motor = 11;
        c.motor_value = 40;
        c.waypoint = (pl_aok_waypoint){3, 237512345, 480012345, (2u << 16) | (15 + 32768), (6u << 16) | (250 + 32768)};
        c.external = (pl_aok_external){32, -32, 200, -5, 500};
        count += aok_cmd_rt(f, &c);
    }
    {
        uint8_t buf[PL_AOK_MAX_FRAME_LEN];
        pl_aok_item c;
        memset(&c, 0, sizeof c);
        c.kind = PL_AOK_MOTOR_TEST;
        c.motor = 13;
        CHECK(pl_aok_encode_command(&c, buf, sizeof buf) == PL_E_OUT_OF_RANGE);
        c.kind = PL_AOK_EXTERNAL_CONTROL;
        c.external.roll = 201;
        CHECK(pl_aok_encode_command(&c, buf, sizeof buf) == PL_E_OUT_OF_RANGE);
        c.kind = PL_AOK_READ_WAYPOINT;
        c.number = 100;
        CHECK(pl_aok_encode_command(&c, buf, sizeof buf) == PL_E_OUT_OF_RANGE);
        c.kind = 19;
        CHECK(pl_aok_encode_command(&c, buf, sizeof buf) == PL_E_BAD_TAG);
        c.kind = PL_AOK_ACK;
        c.ack = 'X';
        CHECK(pl_aok_encode_message(&c, 1, buf, sizeof buf) == PL_E_OUT_OF_RANGE);
    }
    fclose(f);

    f = open_out(dir, "rt-aok-device.bin");
    if (!f) return 1;
    {
        pl_aok_item m, asked;
        memset(&m, 0, sizeof m);
        memset(&asked, 0, sizeof asked);
        m.kind = PL_AOK_DEBUG;
        m.number = 86;
        m.value = -2;
        count += aok_msg_rt(f, &m, NULL);
        m.kind = PL_AOK_PARAMETER;
        m.number = 12;
        m.value = 1500;
        asked.kind = PL_AOK_READ_PARAMETER;
        asked.number = 12;
        count += aok_msg_rt(f, &m, &asked);
        m.kind = PL_AOK_WAYPOINT;
        m.waypoint = (pl_aok_waypoint){31, -1, 480012345, (1u << 16) | (30 + 32768), 32768};
        asked.kind = PL_AOK_READ_WAYPOINT;
        asked.number = 31;
        count += aok_msg_rt(f, &m, &asked);
        /* An ack is only read when one is expected: not written to the file. */
        m.kind = PL_AOK_ACK;
        m.ack = 'I';
        asked.kind = PL_AOK_SET_PARAMETER;
        count += aok_msg_rt(NULL, &m, &asked);
    }
    fclose(f);

    f = open_out(dir, "rt-gdl90.bin");
    if (!f) return 1;
    {
        pl_gdl90_message m;
        memset(&m, 0, sizeof m);
        m.kind = PL_GDL90_HEARTBEAT;
        m.body.heartbeat = (pl_gdl90_heartbeat){1, 0, 1, 0, 1, 0, 1, 0, 1, 1, 45296, 3, 700};
        count += gdl90_rt(f, &m);
        for (int t = 0; t < 2; t++) {
            memset(&m, 0, sizeof m);
            m.kind = t ? PL_GDL90_TRAFFIC : PL_GDL90_OWNSHIP;
            pl_gdl90_report r;
            memset(&r, 0, sizeof r);
            r.traffic_alert = (uint8_t)t;
            r.address_type = 1;
            r.address = 0xABCDEF;
            r.has_position = 1;
            r.lat_deg = 44.90708;
            r.lon_deg = -122.99488;
            r.has_pressure_altitude = 1;
            r.pressure_altitude_ft = 5000;
            r.airborne = 1;
            r.track_kind = 1;
            r.track_deg = 45.0f;
            r.nic = 10;
            r.nacp = 9;
            r.has_ground_speed = 1;
            r.ground_speed_kt = 123;
            r.has_vertical_rate = 1;
            r.vertical_rate_fpm = 64;
            r.emitter = 1;
            memcpy(r.call_sign, "N825V   ", 8);
            r.emergency = (uint8_t)t;
            m.body.report = r;
            count += gdl90_rt(f, &m);
        }
        memset(&m, 0, sizeof m);
        m.kind = PL_GDL90_GEO_ALTITUDE;
        m.body.geo_altitude = (pl_gdl90_geo_altitude){1500, 1, 1, 10};
        count += gdl90_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.kind = PL_GDL90_FOREFLIGHT_ID;
        m.body.foreflight_id.version = 1;
        m.body.foreflight_id.has_serial = 1;
        m.body.foreflight_id.serial = 12345;
        memcpy(m.body.foreflight_id.name, "AEOLUS", 6);
        memcpy(m.body.foreflight_id.long_name, "AEOLUS-SENSE box", 16);
        m.body.foreflight_id.altitude_datum = 1;
        count += gdl90_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.kind = PL_GDL90_AHRS;
        m.body.ahrs = (pl_gdl90_ahrs){1, -12.5f, 1, 3.5f, 2, 271.5f, 1, 95, 0, 0};
        count += gdl90_rt(f, &m);
        memset(&m, 0, sizeof m);
        m.kind = PL_GDL90_UNKNOWN;
        m.id = 7;
        m.data = (const uint8_t *)"\x7e\x7d\x01";
        m.data_len = 3;
        count += gdl90_rt(f, &m);
        uint8_t buf[PL_GDL90_MAX_FRAME_LEN];
        m.kind = PL_GDL90_AHRS;
        m.body.ahrs.has_roll = 1;
        m.body.ahrs.roll_deg = 1000.0f;
        /* The Rust encoder clamps a roll beyond 180 degrees (its rule, not the C face's). */
        int32_t n = pl_gdl90_encode(&m, buf, sizeof buf);
        CHECK(n > 0);
        pl_gdl90_decoder d;
        pl_gdl90_message got;
        pl_error err;
        pl_gdl90_init(&d);
        int seen = 0;
        for (int32_t i = 0; i < n; i++)
            if (BYTE(pl_gdl90_parse, &d, buf[i], &got, &err) == PL_MESSAGE) {
                seen++;
                CHECK(got.kind == PL_GDL90_AHRS && got.body.ahrs.roll_deg == 180.0f);
            }
        CHECK(seen == 1);
    }
    fclose(f);
    printf("round trips: %d messages, %d failed checks\n", count, failures);
    return failures != 0;
}
