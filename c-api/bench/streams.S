/* The cm3-bench input streams, in flash (scripts/c-bench.sh passes their names). */
    .section .rodata.streams, "a"
    .global stream_a, stream_a_end
stream_a:
    .incbin STREAM_A
stream_a_end:
#ifdef STREAM_B
    .global stream_b, stream_b_end
stream_b:
    .incbin STREAM_B
stream_b_end:
#endif
