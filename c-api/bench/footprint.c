/*
 * Flash and RAM of one AEOLUS decoder from C, beside MAVLink C's mavlink_parse_char: the same
 * receive loop, built three ways with the same arm-none-eabi-gcc flags (scripts/c-bench.sh):
 *   -DDECODER=0  the loop alone (baseline: bytes read from UART0's data register, a sink)
 *   -DDECODER=1  + one pl_aeolus_decoder (libprotolink_c.a, thumbv7m): pl_aeolus_parse a byte at a time, typed parse
 *   -DDECODER=2  + MAVLink common dialect, mavlink_parse_char on channel 0 (headers generated
 *                by pymavlink's mavgen; MAVLINK_COMM_NUM_BUFFERS as the build sets it)
 * The figures are each build's size minus the baseline's.
 */
#include <stdint.h>
#include <stdlib.h>

#if DECODER == 1
#include "protolink.h"
static pl_aeolus_decoder dec;
#elif DECODER == 2
#include "common/mavlink.h"
#endif

#define UART0_DR (*(volatile uint32_t *)0x4000C000u)
#define UART0_FR (*(volatile uint32_t *)0x4000C018u)

static volatile uint32_t sink;

int main(void) {
#if DECODER == 1
    pl_aeolus_init(&dec);
    pl_aeolus_message msg;
    pl_error err;
#elif DECODER == 2
    mavlink_message_t msg;
    mavlink_status_t status;
#endif
    for (uint32_t n = 0; n < 1000; n++) {
        while (UART0_FR & 0x10u) { /* RX FIFO empty */
            if (++n >= 1000) exit(0);
        }
        uint8_t byte = (uint8_t)UART0_DR;
#if DECODER == 0
        sink = byte;
#elif DECODER == 1
        size_t used;
        if (pl_aeolus_parse(&dec, &byte, 1, &used, &msg, &err) == PL_MESSAGE) sink = msg.id;
#elif DECODER == 2
        if (mavlink_parse_char(MAVLINK_COMM_0, byte, &msg, &status)) sink = msg.msgid;
#endif
    }
    exit(0);
}
