/* The root README's "Use it from C" examples, compiled as printed and run (c-api/tests/readme_c.py
 * extracts them into readme_receive.c and readme_encode.c): the receive loop over a capture
 * served in pieces of 1 to 64 bytes, then the encode, whose frame must decode back to the same
 * command. What the examples leave to the application (uart_read, uart_write, on_rates,
 * count_error) is defined here; the output, one line per GYRO's rates and a last line of
 * counts, is compared with `protolink decode --json` by the script.
 *
 *   readme CAPTURE
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "protolink.h"

size_t uart_read(uint8_t *buf, size_t cap);
void uart_write(const uint8_t *buf, size_t len);
void on_rates(float x, float y, float z);
void count_error(uint32_t kind);

#include "readme_receive.c"

static void readme_encode(void) {
#include "readme_encode.c"
}

static uint8_t *input;
static size_t input_len, input_off;
static unsigned long gyros, errors, reads;
static uint8_t written[2 * PL_AEOLUS_MAX_FRAME_LEN];
static size_t written_len;

void on_rates(float x, float y, float z) {
    gyros++;
    printf("gyro %.9g %.9g %.9g\n", (double)x, (double)y, (double)z);
}

void count_error(uint32_t kind) {
    errors++;
    printf("error %u\n", (unsigned)kind);
}

void uart_write(const uint8_t *buf, size_t len) {
    if (len > sizeof written - written_len) {
        fprintf(stderr, "uart_write: %zu bytes do not fit\n", len);
        exit(1);
    }
    memcpy(written + written_len, buf, len);
    written_len += len;
}

/* The encode example's frame, decoded by a fresh decoder: one COMMAND "a reboot", nothing
 * else. */
static int encode_decodes_back(void) {
    pl_aeolus_decoder d;
    pl_aeolus_message msg;
    pl_error err;
    size_t off = 0, used;
    int messages = 0, ok = 0;
    readme_encode();
    if (written_len == 0 || pl_aeolus_init(&d) != 0)
        return 0;
    for (;;) {
        int st = pl_aeolus_parse(&d, written + off, written_len - off, &used, &msg, &err);
        off += used;
        if (st == PL_NOTHING || st < 0)
            break;
        if (st != PL_MESSAGE)
            return 0;
        messages++;
        ok = msg.id == PL_AEOLUS_ID_COMMAND && msg.data_len == 8 && memcmp(msg.data, "a reboot", 8) == 0;
    }
    return messages == 1 && ok && off == written_len;
}

/* The capture in pieces of 1 to `cap` bytes; at its end, the counts and the encode check, and
 * the process ends (the README's loop does not). */
size_t uart_read(uint8_t *buf, size_t cap) {
    if (input_off == input_len) {
        int encoded = encode_decodes_back();
        printf("end gyros %lu errors %lu reads %lu encode %s\n", gyros, errors, reads,
               encoded ? "ok" : "FAILED");
        free(input);
        exit(encoded ? 0 : 1);
    }
    reads++;
    size_t n = 1 + (size_t)((reads * 37u) % cap);
    if (n > input_len - input_off)
        n = input_len - input_off;
    memcpy(buf, input + input_off, n);
    input_off += n;
    return n;
}

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: readme CAPTURE\n");
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    if (!f) {
        perror(argv[1]);
        return 2;
    }
    size_t cap = 1 << 20;
    input = malloc(cap);
    if (!input)
        return 2;
    input_len = fread(input, 1, cap, f);
    fclose(f);
    uart_task();
    return 1; /* the README's loop never returns */
}
