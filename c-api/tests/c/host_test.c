/*
 * The host test of the C API, built with -fsanitize=address,undefined (c-api/tests/host.sh):
 *
 *   host_test dump PROTO FILE   decode FILE through the C API, one JSON object per event in
 *                               the shape of `protolink decode --json`, then the counters
 *                               (compare.py checks every field against protolink)
 *   host_test roundtrip DIR     encode every message type of every protocol, decode it again,
 *                               re-encode and compare the bytes; writes the frames to
 *                               DIR/rt-PROTO.bin for `dump`
 *   host_test hostile MBYTES    MBYTES of random bytes, then truncated, corrupted and oversized
 *                               frames through every decoder, byte and slice calls, plus NULL
 *                               and length checks on every function
 *   host_test misuse            every call on states their init did not set up (0x00, 0xA5,
 *                               0xFF and random fills, another protocol's state, an odd
 *                               address): PL_E_INVALID, nothing written; the header's state
 *                               sizes and ABI version against the archive's
 *
 * PROTO: aeolus, aydp-spec, aydp-reference, aok-pc (commands), aok-device (device messages),
 * gdl90. Exit status 0 on success; any failed check prints one line and exits 1.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "protolink.h"

static int failures;

#define CHECK(cond)                                                                   \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            failures++;                                                               \
        }                                                                             \
    } while (0)

/* One byte through pl_*_parse (the one-byte path), and what a rescan left queued (no bytes). */
static size_t scratch_used;
#define BYTE(PARSE, D, B, M, E) PARSE((D), &(const uint8_t){(B)}, 1, &scratch_used, (M), (E))
#define QUEUED(PARSE, D, M, E) PARSE((D), NULL, 0, &scratch_used, (M), (E))

/* ---------- JSON output ---------- */

static void hex(const uint8_t *p, size_t n) {
    putchar('"');
    for (size_t i = 0; i < n; i++) printf("%02x", p[i]);
    putchar('"');
}

static void f32(const char *name, float v, int last) { printf("\"%s\":%.9g%s", name, (double)v, last ? "" : ","); }
static void f64(const char *name, double v, int last) { printf("\"%s\":%.17g%s", name, v, last ? "" : ","); }
static void i64(const char *name, long long v, int last) { printf("\"%s\":%lld%s", name, v, last ? "" : ","); }
static void bln(const char *name, int v, int last) { printf("\"%s\":%s%s", name, v ? "true" : "false", last ? "" : ","); }

static void f32s(const char *name, const float *v, int n, int last) {
    printf("\"%s\":[", name);
    for (int i = 0; i < n; i++) printf("%.9g%s", (double)v[i], i + 1 < n ? "," : "");
    printf("]%s", last ? "" : ",");
}

static void u8s(const char *name, const uint8_t *v, int n, int last) {
    printf("\"%s\":[", name);
    for (int i = 0; i < n; i++) printf("%u%s", v[i], i + 1 < n ? "," : "");
    printf("]%s", last ? "" : ",");
}

/* A message line's start: its kind and its place in the input (offset, wire length). */
static void place(uint64_t offset, uint32_t wire_len) {
    printf("{\"kind\":\"message\",\"offset\":%" PRIu64 ",\"len\":%" PRIu32 ",", offset, wire_len);
}

static void error_line(const pl_error *e) {
    printf("{\"kind\":\"error\",\"error_kind\":%u,\"id\":%u,\"expected\":%u,\"actual\":%u,\"offset\":%" PRIu64
           ",\"len\":%" PRIu32 "}\n",
           e->kind, e->id, e->expected, e->actual, e->offset, e->wire_len);
}

/* ---------- AEOLUS ---------- */

static const char *aeolus_name(uint8_t id) {
    switch (id) {
    case PL_AEOLUS_ID_AEOLUSINFO: return "AEOLUSINFO";
    case PL_AEOLUS_ID_PRESSURE: return "PRESSURE";
    case PL_AEOLUS_ID_GYRO: return "GYRO";
    case PL_AEOLUS_ID_ACCEL: return "ACCEL";
    case PL_AEOLUS_ID_MAGNET: return "MAGNET";
    case PL_AEOLUS_ID_TEMP: return "TEMP";
    case PL_AEOLUS_ID_GPS: return "GPS";
    case PL_AEOLUS_ID_ATTITUDE: return "ATTITUDE";
    case PL_AEOLUS_ID_COMPASS: return "COMPASS";
    case PL_AEOLUS_ID_WIND: return "WIND";
    case PL_AEOLUS_ID_CALIBINFO: return "CALIBINFO";
    case PL_AEOLUS_ID_DEBUGINFO: return "DEBUGINFO";
    case PL_AEOLUS_ID_LOG: return "LOG";
    case PL_AEOLUS_ID_TOAST: return "TOAST";
    case PL_AEOLUS_ID_COMMAND: return "COMMAND";
    case PL_AEOLUS_ID_SETTIME: return "SETTIME";
    default: return "UNKNOWN";
    }
}

static void print_aeolus(const pl_aeolus_message *m) {
    place(m->offset, m->wire_len);
    printf("\"name\":\"%s\",\"id\":%u,\"crc\":\"%s\",\"fields\":{", aeolus_name(m->id), m->id,
           m->no_crc ? "none" : "ok");
    const pl_aeolus_body *b = &m->body;
    switch (m->id) {
    case PL_AEOLUS_ID_AEOLUSINFO:
        i64("model", b->info.model, 0);
        u8s("firmware", b->info.firmware, 3, 0);
        u8s("mac", b->info.mac, 6, 1);
        break;
    case PL_AEOLUS_ID_PRESSURE:
        bln("valid", b->motion.valid, 0);
        f64("timestamp_ms", b->motion.timestamp_ms, 0);
        f32("static_mbar", b->motion.x, 0);
        f32("pitot_mbar", b->motion.y, 0);
        f32("airspeed_mps", b->motion.z, 1);
        break;
    case PL_AEOLUS_ID_GYRO:
    case PL_AEOLUS_ID_ACCEL:
    case PL_AEOLUS_ID_MAGNET:
        bln("valid", b->motion.valid, 0);
        f64("timestamp_ms", b->motion.timestamp_ms, 0);
        f32("x", b->motion.x, 0);
        f32("y", b->motion.y, 0);
        f32("z", b->motion.z, 1);
        break;
    case PL_AEOLUS_ID_TEMP:
        bln("valid", b->temp.valid, 0);
        f64("timestamp_ms", b->temp.timestamp_ms, 0);
        f32("celsius", b->temp.celsius, 1);
        break;
    case PL_AEOLUS_ID_GPS:
        bln("valid", b->gps.valid, 0);
        bln("has_fix", b->gps.has_fix, 0);
        i64("satellites", b->gps.satellites, 0);
        f64("timestamp_ms", b->gps.timestamp_ms, 0);
        f32("latitude_deg", b->gps.latitude_deg, 0);
        f32("longitude_deg", b->gps.longitude_deg, 0);
        f32("altitude_m", b->gps.altitude_m, 0);
        f32("ground_speed_mps", b->gps.ground_speed_mps, 1);
        break;
    case PL_AEOLUS_ID_ATTITUDE: {
        const pl_aeolus_attitude *a = &b->attitude;
        bln("valid", a->valid, 0);
        f64("timestamp_ms", a->timestamp_ms, 0);
        f32("roll_rad", a->roll_rad, 0);
        f32("pitch_rad", a->pitch_rad, 0);
        f32("yaw_rad", a->yaw_rad, 0);
        f32("slip_ball", a->slip_ball, 0);
        f32("turn_coordinator", a->turn_coordinator, 0);
        f32("qx", a->qx, 0);
        f32("qy", a->qy, 0);
        f32("qz", a->qz, 0);
        f32("qw", a->qw, 1);
        break;
    }
    case PL_AEOLUS_ID_COMPASS: {
        const pl_aeolus_compass *c = &b->compass;
        bln("valid", c->valid, 0);
        i64("calibration", c->calibration, 0);
        bln("has_value", c->has_value, 0);
        i64("calibration_percent", c->calibration_percent, 0);
        i64("calibration_remaining", c->calibration_remaining, 0);
        f64("timestamp_ms", c->timestamp_ms, 0);
        f32("heading_deg", c->heading_deg, 0);
        f32s("soft_iron", c->soft_iron, 3, 0);
        f32s("hard_iron", c->hard_iron, 9, 1);
        break;
    }
    case PL_AEOLUS_ID_WIND:
        bln("valid", b->wind.valid, 0);
        f64("timestamp_ms", b->wind.timestamp_ms, 0);
        f32("speed_mps", b->wind.speed_mps, 0);
        f32("direction_deg", b->wind.direction_deg, 1);
        break;
    case PL_AEOLUS_ID_SETTIME: {
        const pl_aeolus_settime *t = &b->settime;
        i64("year_since_1900", t->year_since_1900, 0);
        i64("month0", t->month0, 0);
        i64("day", t->day, 0);
        i64("hour", t->hour, 0);
        i64("minute", t->minute, 0);
        i64("second", t->second, 1);
        break;
    }
    case PL_AEOLUS_ID_TOAST:
    case PL_AEOLUS_ID_COMMAND:
        printf("\"text_hex\":");
        hex(m->data, m->data_len);
        break;
    default:
        printf("\"len\":%zu,\"data\":", m->data_len);
        hex(m->data, m->data_len);
        break;
    }
    printf("}}\n");
}

/* ---------- AYDP ---------- */

static const char *aydp_name(uint8_t kind) {
    static const char *names[] = {"TIME_SYNC",     "HEARTBEAT",      "NO_OP",       "POSITION",
                                  "FIX_QUALITY",   "FIX_DETAIL",     "DIRECT_OUTPUT", "SYSTEM_VALUE_UPDATE",
                                  "SYSTEM_CONTROL", "WIND_SPEED",    "WIND_DIRECTION", "VESSEL_DATA",
                                  "TBD",           "USER_DEFINED",   "UNKNOWN"};
    return kind < sizeof names / sizeof names[0] ? names[kind] : "?";
}

static void print_aydp(const pl_aydp_message *m) {
    place(m->offset, m->wire_len);
    printf("\"name\":\"%s\",\"type\":%u,\"expedited\":%s,", aydp_name(m->kind), m->msg_type,
           m->expedited ? "true" : "false");
    if (!m->expedited) printf("\"time\":{\"seconds\":%" PRId64 ",\"subsec\":%" PRId64 "},", m->seconds, m->subsec);
    printf("\"fields\":{");
    const pl_aydp_body *b = &m->body;
    switch (m->kind) {
    case PL_AYDP_POSITION:
        f64("latitude", b->position.latitude, 0);
        f64("longitude", b->position.longitude, 0);
        f32("altitude", b->position.altitude, 1);
        break;
    case PL_AYDP_FIX_QUALITY:
        i64("fix_type", b->fix_quality.fix_type, 0);
        f32("mean_dop", b->fix_quality.mean_dop, 0);
        f32("hdop", b->fix_quality.hdop, 0);
        f32("vdop", b->fix_quality.vdop, 0);
        i64("satellites", b->fix_quality.satellites, 1);
        break;
    case PL_AYDP_FIX_DETAIL: {
        printf("\"satellites\":[");
        pl_aydp_satellite s;
        for (uint32_t i = 0; pl_aydp_satellite_at(m, i, &s) == 0; i++) {
            printf("%s{", i ? "," : "");
            i64("id", s.id, 0);
            f32("azimuth", s.azimuth, 0);
            f32("elevation", s.elevation, 0);
            f32("snr", s.snr, 1);
            printf("}");
        }
        printf("]");
        break;
    }
    case PL_AYDP_DIRECT_OUTPUT: {
        printf("\"entries\":[");
        pl_aydp_output_entry e;
        uint32_t i = 0;
        for (; pl_aydp_output_entry_at(m, i, &e) == 0; i++) {
            printf("%s{", i ? "," : "");
            i64("device", e.device, 0);
            i64("channel", e.channel, 0);
            f32("value", e.value, 1);
            printf("}");
        }
        CHECK(i == b->count);
        printf("]");
        break;
    }
    case PL_AYDP_SYSTEM_VALUE_UPDATE:
        i64("address", b->update.address, 0);
        i64("mode_code", b->update.mode, 0);
        i64("mode_field", b->update.field, 0);
        printf("\"data\":");
        hex(b->update.value, b->update.value_len);
        break;
    case PL_AYDP_SYSTEM_CONTROL:
        if (b->control.command == 1)
            printf("\"command\":\"RequestData\",\"address\":%u", b->control.address);
        else
            printf("\"command\":\"StoreConfiguration\"");
        break;
    case PL_AYDP_WIND_SPEED:
    case PL_AYDP_WIND_DIRECTION:
        f32("value", b->value, 1);
        break;
    case PL_AYDP_VESSEL_DATA: {
        const pl_aydp_vessel *v = &b->vessel;
        f32("roll", v->roll, 0);
        f32("pitch", v->pitch, 0);
        f32("heading", v->heading, 0);
        f32("roll_rate", v->roll_rate, 0);
        f32("pitch_rate", v->pitch_rate, 0);
        f32("heading_rate", v->heading_rate, 0);
        f64("latitude", v->latitude, 0);
        f64("longitude", v->longitude, 0);
        f32("track", v->track, 0);
        f32("speed_over_ground", v->speed_over_ground, 0);
        i64("fix_type", v->fix_type, 0);
        i64("satellites", v->satellites, 0);
        f32("mean_dop", v->mean_dop, 0);
        f32("hdop", v->hdop, 0);
        f32("vdop", v->vdop, 1);
        break;
    }
    case PL_AYDP_TBD:
    case PL_AYDP_USER_DEFINED:
    case PL_AYDP_UNKNOWN:
        i64("msg_type", m->msg_type, 0);
        printf("\"data\":");
        hex(m->data, m->data_len);
        break;
    default:
        break;
    }
    printf("}}\n");
}

/* ---------- AOK ---------- */

static void print_waypoint(const pl_aok_waypoint *w) {
    i64("slot_wire", w->slot, 0);
    i64("longitude", w->longitude, 0);
    i64("latitude", w->latitude, 0);
    i64("action1_raw", w->action1, 0);
    i64("action2_raw", w->action2, 1);
}

static void print_aok(const pl_aok_item *it) {
    static const char *names[] = {"DEBUG_OFF",     "DEBUG_ON",       "RESET",        "SAVE_WAYPOINTS",
                                  "LOAD_WAYPOINTS", "LOAD_SET",      "SAVE_SET",     "START_SET",
                                  "SET_PARAMETER", "READ_PARAMETER", "BULK_READ",    "MOTOR_TEST",
                                  "SET_WAYPOINT",  "READ_WAYPOINT",  "EXTERNAL_CONTROL"};
    const char *name = it->kind < 15                 ? names[it->kind]
                       : it->kind == PL_AOK_DEBUG     ? "DEBUG"
                       : it->kind == PL_AOK_ACK       ? "ACK"
                       : it->kind == PL_AOK_PARAMETER ? "PARAMETER"
                       : it->kind == PL_AOK_WAYPOINT  ? "WAYPOINT"
                                                      : "?";
    place(it->offset, it->wire_len);
    printf("\"name\":\"%s\",\"fields\":{", name);
    switch (it->kind) {
    case PL_AOK_LOAD_SET:
    case PL_AOK_SAVE_SET:
    case PL_AOK_START_SET: i64("set", it->number, 1); break;
    case PL_AOK_READ_PARAMETER: i64("number", it->number, 1); break;
    case PL_AOK_BULK_READ: i64("first", it->number, 1); break;
    case PL_AOK_READ_WAYPOINT: i64("slot_wire", it->number, 1); break;
    case PL_AOK_SET_PARAMETER:
    case PL_AOK_DEBUG:
    case PL_AOK_PARAMETER:
        i64("number", it->number, 0);
        i64("value", it->value, 1);
        break;
    case PL_AOK_MOTOR_TEST:
        i64("motor", it->motor, 0);
        i64("value", it->motor_value, 1);
        break;
    case PL_AOK_SET_WAYPOINT:
    case PL_AOK_WAYPOINT: print_waypoint(&it->waypoint); break;
    case PL_AOK_EXTERNAL_CONTROL:
        i64("roll", it->external.roll, 0);
        i64("nick", it->external.nick, 0);
        i64("yaw", it->external.yaw, 0);
        i64("pitch", it->external.pitch, 0);
        i64("expiry_ms", it->external.expiry_ms, 1);
        break;
    case PL_AOK_ACK: i64("ack", it->ack, 1); break;
    default: break;
    }
    printf("}}\n");
}

/* ---------- GDL90 ---------- */

static void print_report(const pl_gdl90_report *r) {
    bln("traffic_alert", r->traffic_alert, 0);
    i64("address_type", r->address_type, 0);
    i64("address", r->address, 0);
    if (r->has_position)
        printf("\"position\":{\"lat_deg\":%.17g,\"lon_deg\":%.17g},", r->lat_deg, r->lon_deg);
    else
        printf("\"position\":null,");
    if (r->has_pressure_altitude)
        i64("pressure_altitude_ft", r->pressure_altitude_ft, 0);
    else
        printf("\"pressure_altitude_ft\":null,");
    bln("airborne", r->airborne, 0);
    bln("extrapolated", r->extrapolated, 0);
    i64("track_kind", r->track_kind, 0);
    f32("track_deg", r->track_deg, 0);
    i64("nic", r->nic, 0);
    i64("nacp", r->nacp, 0);
    if (r->has_ground_speed)
        i64("ground_speed_kt", r->ground_speed_kt, 0);
    else
        printf("\"ground_speed_kt\":null,");
    if (r->has_vertical_rate)
        i64("vertical_rate_fpm", r->vertical_rate_fpm, 0);
    else
        printf("\"vertical_rate_fpm\":null,");
    i64("emitter", r->emitter, 0);
    printf("\"call_sign_hex\":");
    hex(r->call_sign, 8);
    printf(",");
    i64("emergency", r->emergency, 1);
}

static void print_gdl90(const pl_gdl90_message *m) {
    static const char *names[] = {"HEARTBEAT", "OWNSHIP", "GEO_ALTITUDE", "TRAFFIC", "FOREFLIGHT_ID", "FOREFLIGHT_AHRS", "UNKNOWN"};
    place(m->offset, m->wire_len);
    printf("\"name\":\"%s\",\"id\":%u,\"fields\":{", m->kind < 7 ? names[m->kind] : "?", m->id);
    const pl_gdl90_body *b = &m->body;
    switch (m->kind) {
    case PL_GDL90_HEARTBEAT: {
        const pl_gdl90_heartbeat *h = &b->heartbeat;
        bln("gps_position_valid", h->gps_position_valid, 0);
        bln("maintenance_required", h->maintenance_required, 0);
        bln("ident", h->ident, 0);
        bln("address_talkback", h->address_talkback, 0);
        bln("gps_battery_low", h->gps_battery_low, 0);
        bln("atc_services", h->atc_services, 0);
        bln("uat_initialized", h->uat_initialized, 0);
        bln("csa_requested", h->csa_requested, 0);
        bln("csa_not_available", h->csa_not_available, 0);
        bln("utc_ok", h->utc_ok, 0);
        i64("seconds_since_midnight", h->seconds_since_midnight, 0);
        i64("uplink_messages", h->uplink_messages, 0);
        i64("basic_long_messages", h->basic_long_messages, 1);
        break;
    }
    case PL_GDL90_OWNSHIP:
    case PL_GDL90_TRAFFIC: print_report(&b->report); break;
    case PL_GDL90_GEO_ALTITUDE:
        i64("altitude_ft", b->geo_altitude.altitude_ft, 0);
        bln("vertical_warning", b->geo_altitude.vertical_warning, 0);
        if (b->geo_altitude.has_vfom)
            i64("vfom_m", b->geo_altitude.vfom_m, 1);
        else
            printf("\"vfom_m\":null");
        break;
    case PL_GDL90_FOREFLIGHT_ID: {
        const pl_gdl90_foreflight_id *f = &b->foreflight_id;
        i64("version", f->version, 0);
        if (f->has_serial)
            printf("\"serial\":%" PRIu64 ",", f->serial);
        else
            printf("\"serial\":null,");
        printf("\"name_hex\":");
        hex(f->name, 8);
        printf(",\"long_name_hex\":");
        hex(f->long_name, 16);
        printf(",");
        i64("altitude_datum", f->altitude_datum, 0);
        i64("other_capabilities", f->other_capabilities, 1);
        break;
    }
    case PL_GDL90_AHRS: {
        const pl_gdl90_ahrs *a = &b->ahrs;
        if (a->has_roll) f32("roll_deg", a->roll_deg, 0); else printf("\"roll_deg\":null,");
        if (a->has_pitch) f32("pitch_deg", a->pitch_deg, 0); else printf("\"pitch_deg\":null,");
        i64("heading_kind", a->heading_kind, 0);
        f32("heading_deg", a->heading_deg, 0);
        if (a->has_indicated_airspeed) i64("indicated_airspeed_kt", a->indicated_airspeed_kt, 0);
        else printf("\"indicated_airspeed_kt\":null,");
        if (a->has_true_airspeed) i64("true_airspeed_kt", a->true_airspeed_kt, 1);
        else printf("\"true_airspeed_kt\":null");
        break;
    }
    default:
        printf("\"data\":");
        hex(m->data, m->data_len);
        break;
    }
    printf("}}\n");
}

/* ---------- dump ---------- */

static uint8_t *read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    uint8_t *buf = malloc(cap);
    size_t r;
    while (buf && (r = fread(buf + n, 1, cap - n, f)) > 0) {
        n += r;
        if (n == cap) {
            uint8_t *more = realloc(buf, cap *= 2);
            if (!more) { free(buf); buf = NULL; }
            buf = more;
        }
    }
    fclose(f);
    *len = n;
    return buf;
}

/* Decodes with the slice call, in chunks of `chunk` bytes (0: the whole input at once), and
 * prints each event when `print` is set; returns the number of events. */
#define SLICE_LOOP(PARSE, DEC, MSG, PRINT_MSG)                                                  \
    do {                                                                                        \
        size_t off = 0;                                                                         \
        for (;;) {                                                                              \
            size_t n = chunk && len - off > chunk ? chunk : len - off, used = 0;                \
            st = PARSE(&DEC, buf + off, n, &used, &MSG, &err);                                  \
            CHECK(st >= 0 && used <= n);                                                        \
            if (st < 0) break;                                                                  \
            off += used;                                                                        \
            if (st == PL_MESSAGE) { events++; if (print) PRINT_MSG(&MSG); }                     \
            if (st == PL_ERROR) { events++; if (print) error_line(&err); }                      \
            if (st == PL_NOTHING && off >= len) break;                                          \
        }                                                                                       \
    } while (0)

static int dump(const char *proto, const uint8_t *buf, size_t len, size_t chunk, int print) {
    pl_error err;
    int events = 0, st;
    if (!strcmp(proto, "aeolus")) {
        pl_aeolus_decoder d;
        pl_aeolus_message m;
        pl_aeolus_stats s;
        CHECK(pl_aeolus_init(&d) == 0);
        SLICE_LOOP(pl_aeolus_parse, d, m, print_aeolus);
        while ((st = pl_aeolus_finish(&d, &m, &err)) > 0) { events++; if (print) error_line(&err); }
        pl_aeolus_get_stats(&d, &s);
        if (print)
            printf("{\"kind\":\"summary\",\"counters\":{\"frames_ok\":%u,\"frames_no_crc\":%u,\"checksum_errors\":%u,"
                   "\"missing_crc\":%u,\"overflows\":%u,\"too_short\":%u,\"bad_escapes\":%u,\"bytes_discarded\":%u,"
                   "\"frame_bytes\":%u,\"flags\":%u}}\n",
                   s.frames_ok, s.frames_no_crc, s.checksum_errors, s.missing_crc, s.overflows, s.too_short,
                   s.bad_escapes, s.bytes_discarded, s.frame_bytes, s.flags);
    } else if (!strncmp(proto, "aydp-", 5)) {
        pl_aydp_decoder d;
        pl_aydp_message m;
        pl_aydp_stats s;
        CHECK(pl_aydp_init(&d, strcmp(proto, "aydp-reference") ? PL_AYDP_SPEC : PL_AYDP_REFERENCE) == 0);
        SLICE_LOOP(pl_aydp_parse, d, m, print_aydp);
        while ((st = pl_aydp_finish(&d, &m, &err)) > 0) {
            events++;
            if (print) { if (st == PL_MESSAGE) print_aydp(&m); else error_line(&err); }
        }
        pl_aydp_get_stats(&d, &s);
        if (print)
            printf("{\"kind\":\"summary\",\"counters\":{\"frames_ok\":%u,\"checksum_errors\":%u,\"length_errors\":%u,"
                   "\"bytes_discarded\":%u}}\n",
                   s.frames_ok, s.checksum_errors, s.length_errors, s.bytes_discarded);
    } else if (!strcmp(proto, "aok-pc") || !strcmp(proto, "aok-device")) {
        pl_aok_item it;
        pl_aok_stats s;
        if (!strcmp(proto, "aok-pc")) {
            pl_aok_device_decoder d;
            CHECK(pl_aok_device_init(&d) == 0);
            SLICE_LOOP(pl_aok_device_parse, d, it, print_aok);
            while ((st = pl_aok_device_finish(&d, &it, &err)) > 0) {
                events++;
                if (print) { if (st == PL_MESSAGE) print_aok(&it); else error_line(&err); }
            }
            pl_aok_device_get_stats(&d, &s);
        } else {
            pl_aok_pc_decoder d;
            CHECK(pl_aok_pc_init(&d, 0, 35) == 0);
            SLICE_LOOP(pl_aok_pc_parse, d, it, print_aok);
            while ((st = pl_aok_pc_finish(&d, &it, &err)) > 0) {
                events++;
                if (print) { if (st == PL_MESSAGE) print_aok(&it); else error_line(&err); }
            }
            pl_aok_pc_get_stats(&d, &s);
        }
        if (print)
            printf("{\"kind\":\"summary\",\"counters\":{\"frames_ok\":%u,\"checksum_errors\":%u,\"unknown_bytes\":%u,"
                   "\"invalid\":%u,\"abandoned\":%u,\"bytes_discarded\":%u}}\n",
                   s.frames_ok, s.checksum_errors, s.unknown_bytes, s.invalid, s.abandoned, s.bytes_discarded);
    } else if (!strcmp(proto, "gdl90")) {
        pl_gdl90_decoder d;
        pl_gdl90_message m;
        pl_gdl90_stats s;
        CHECK(pl_gdl90_init(&d) == 0);
        SLICE_LOOP(pl_gdl90_parse, d, m, print_gdl90);
        while ((st = pl_gdl90_finish(&d, &m, &err)) > 0) {
            events++;
            if (print) { if (st == PL_MESSAGE) print_gdl90(&m); else error_line(&err); }
        }
        pl_gdl90_get_stats(&d, &s);
        if (print)
            printf("{\"kind\":\"summary\",\"counters\":{\"frames_ok\":%u,\"invalid\":%u,\"checksum_errors\":%u,"
                   "\"overflows\":%u,\"too_short\":%u,\"bad_escapes\":%u,\"bytes_discarded\":%u,\"frame_bytes\":%u,"
                   "\"flags\":%u}}\n",
                   s.frames_ok, s.invalid, s.checksum_errors, s.overflows, s.too_short, s.bad_escapes,
                   s.bytes_discarded, s.frame_bytes, s.flags);
    } else {
        fprintf(stderr, "unknown protocol %s\n", proto);
        failures++;
    }
    return events;
}

/* Byte calls (with poll where the protocol has it) give the same number of events as the
 * slice call. */
static int count_bytewise(const char *proto, const uint8_t *buf, size_t len) {
    pl_error err;
    int events = 0, st;
    if (!strcmp(proto, "aeolus")) {
        pl_aeolus_decoder d;
        pl_aeolus_message m;
        pl_aeolus_init(&d);
        for (size_t i = 0; i < len; i++) events += BYTE(pl_aeolus_parse, &d, buf[i], &m, &err) > 0;
        while (pl_aeolus_finish(&d, &m, &err) > 0) events++;
    } else if (!strncmp(proto, "aydp-", 5)) {
        pl_aydp_decoder d;
        pl_aydp_message m;
        pl_aydp_init(&d, strcmp(proto, "aydp-reference") ? PL_AYDP_SPEC : PL_AYDP_REFERENCE);
        for (size_t i = 0; i < len; i++)
            for (st = BYTE(pl_aydp_parse, &d, buf[i], &m, &err); st > 0; st = QUEUED(pl_aydp_parse, &d, &m, &err)) events++;
        while (pl_aydp_finish(&d, &m, &err) > 0) events++;
    } else if (!strcmp(proto, "aok-pc")) {
        pl_aok_device_decoder d;
        pl_aok_item it;
        pl_aok_device_init(&d);
        for (size_t i = 0; i < len; i++)
            for (st = BYTE(pl_aok_device_parse, &d, buf[i], &it, &err); st > 0; st = QUEUED(pl_aok_device_parse, &d, &it, &err))
                events++;
        while (pl_aok_device_finish(&d, &it, &err) > 0) events++;
    } else if (!strcmp(proto, "aok-device")) {
        pl_aok_pc_decoder d;
        pl_aok_item it;
        pl_aok_pc_init(&d, 0, 35);
        for (size_t i = 0; i < len; i++)
            for (st = BYTE(pl_aok_pc_parse, &d, buf[i], &it, &err); st > 0; st = QUEUED(pl_aok_pc_parse, &d, &it, &err)) events++;
        while (pl_aok_pc_finish(&d, &it, &err) > 0) events++;
    } else {
        pl_gdl90_decoder d;
        pl_gdl90_message m;
        pl_gdl90_init(&d);
        for (size_t i = 0; i < len; i++) events += BYTE(pl_gdl90_parse, &d, buf[i], &m, &err) > 0;
        while (pl_gdl90_finish(&d, &m, &err) > 0) events++;
    }
    return events;
}

/* The feed calls: every event through a callback that counts it (and checks its status). */
struct counter {
    int events;
};
static void count_aeolus(void *ctx, int32_t st, const pl_aeolus_message *m, const pl_error *e) {
    CHECK((st == PL_MESSAGE || st == PL_ERROR) && m && e);
    ((struct counter *)ctx)->events++;
}
static void count_aydp(void *ctx, int32_t st, const pl_aydp_message *m, const pl_error *e) {
    CHECK((st == PL_MESSAGE || st == PL_ERROR) && m && e);
    ((struct counter *)ctx)->events++;
}
static void count_aok(void *ctx, int32_t st, const pl_aok_item *m, const pl_error *e) {
    CHECK((st == PL_MESSAGE || st == PL_ERROR) && m && e);
    ((struct counter *)ctx)->events++;
}
static void count_gdl90(void *ctx, int32_t st, const pl_gdl90_message *m, const pl_error *e) {
    CHECK((st == PL_MESSAGE || st == PL_ERROR) && m && e);
    ((struct counter *)ctx)->events++;
}

/* Events of the feed calls over buf in chunks of `chunk` bytes (0: all at once), end of input
 * included as in dump(). */
static int count_feed(const char *proto, const uint8_t *buf, size_t len, size_t chunk) {
    struct counter c = {0};
    pl_error err;
    size_t off = 0;
#define FEED_LOOP(FEED, DEC, CB)                                                   \
    do {                                                                           \
        do {                                                                       \
            size_t n = chunk && len - off > chunk ? chunk : len - off;             \
            CHECK(FEED(&DEC, len ? buf + off : NULL, n, CB, &c) == PL_NOTHING);    \
            off += n;                                                              \
        } while (off < len);                                                       \
    } while (0)
    if (!strcmp(proto, "aeolus")) {
        pl_aeolus_decoder d;
        pl_aeolus_init(&d);
        pl_aeolus_message m;
        FEED_LOOP(pl_aeolus_feed, d, count_aeolus);
        while (pl_aeolus_finish(&d, &m, &err) > 0) c.events++;
    } else if (!strncmp(proto, "aydp-", 5)) {
        pl_aydp_decoder d;
        pl_aydp_message m;
        pl_aydp_init(&d, strcmp(proto, "aydp-reference") ? PL_AYDP_SPEC : PL_AYDP_REFERENCE);
        FEED_LOOP(pl_aydp_feed, d, count_aydp);
        while (pl_aydp_finish(&d, &m, &err) > 0) c.events++;
    } else if (!strcmp(proto, "aok-pc")) {
        pl_aok_device_decoder d;
        pl_aok_item it;
        pl_aok_device_init(&d);
        FEED_LOOP(pl_aok_device_feed, d, count_aok);
        while (pl_aok_device_finish(&d, &it, &err) > 0) c.events++;
    } else if (!strcmp(proto, "aok-device")) {
        pl_aok_pc_decoder d;
        pl_aok_item it;
        pl_aok_pc_init(&d, 0, 35);
        FEED_LOOP(pl_aok_pc_feed, d, count_aok);
        while (pl_aok_pc_finish(&d, &it, &err) > 0) c.events++;
    } else {
        pl_gdl90_decoder d;
        pl_gdl90_init(&d);
        pl_gdl90_message m;
        FEED_LOOP(pl_gdl90_feed, d, count_gdl90);
        while (pl_gdl90_finish(&d, &m, &err) > 0) c.events++;
    }
#undef FEED_LOOP
    return c.events;
}

static int cmd_dump(const char *proto, const char *path) {
    size_t len = 0;
    uint8_t *buf = read_file(path, &len);
    if (!buf) {
        fprintf(stderr, "cannot read %s\n", path);
        return 1;
    }
    size_t chunk = 0;
    int events = dump(proto, buf, len, chunk, 1);
    /* Every chunk size gives the same events as the whole buffer, and as the byte calls. */
    for (chunk = 1; chunk <= 64; chunk = chunk * 2 + 1) CHECK(dump(proto, buf, len, chunk, 0) == events);
    CHECK(count_bytewise(proto, buf, len) == events);
    for (chunk = 0; chunk <= 64; chunk = chunk * 2 + 1) CHECK(count_feed(proto, buf, len, chunk) == events);
    free(buf);
    return failures != 0;
}

#include "host_roundtrip.h"
#include "host_hostile.h"
#include "host_misuse.h"

int main(int argc, char **argv) {
    if (argc == 4 && !strcmp(argv[1], "dump")) return cmd_dump(argv[2], argv[3]);
    if (argc == 3 && !strcmp(argv[1], "roundtrip")) return cmd_roundtrip(argv[2]);
    if (argc == 3 && !strcmp(argv[1], "hostile")) return cmd_hostile(atoi(argv[2]));
    if (argc == 2 && !strcmp(argv[1], "misuse")) return cmd_misuse();
    fprintf(stderr, "usage: host_test dump PROTO FILE | roundtrip DIR | hostile MBYTES | misuse\n");
    return 2;
}
