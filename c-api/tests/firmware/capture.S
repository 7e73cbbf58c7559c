/* The three UART captures of testdata/, built into the image (read-only data). */
    .section .rodata.captures, "a"
    .global aeolus_capture, aeolus_capture_end
aeolus_capture:
    .incbin "qemu-uart0-aeolus.bin"
aeolus_capture_end:
    .global aydp_capture, aydp_capture_end
aydp_capture:
    .incbin "qemu-uart1-aydp.bin"
aydp_capture_end:
    .global aok_capture, aok_capture_end
aok_capture:
    .incbin "qemu-uart2-aok.bin"
aok_capture_end:
