//! The LM3S6965 as QEMU's `lm3s6965evb` models it, as far as the two QEMU boards use it: the
//! blocking one (`src/board/qemu.rs`) and the async firmware's (`firmware-embassy/src/qemu/`).
//! Addresses and bits from the LM3S6965 data sheet (system control, watchdog timers, UARTs);
//! what QEMU 7.2 makes of them is said where the boards use them. Constants only, and the
//! device interrupt table as a macro ([`lm3s6965_interrupts!`](crate::lm3s6965_interrupts)):
//! the `unsafe` of touching the registers stays in the boards.

/// The PLL output SYSDIV divides, Hz: the data sheet's 400 MHz PLL after its fixed divide by
/// two. QEMU's model (`ssys_calculate_system_clock`) uses the same formula, a 5 ns period
/// times SYSDIV + 1, and ignores BYPASS.
pub const PLL_HZ: u32 = 200_000_000;

/// The core clock with RCC's SYSDIV at `sysdiv`, Hz.
pub const fn core_hz(sysdiv: u32) -> u32 {
    PLL_HZ / (sysdiv + 1)
}

/// System control.
pub mod sysctl {
    /// Raw interrupt status (bit 6: the PLL locked).
    pub const RIS: usize = 0x400F_E050;
    /// Reset cause (bit 3: the watchdog), cleared by writing 0. QEMU's model never sets it.
    pub const RESC: usize = 0x400F_E05C;
    /// Run-mode clock configuration.
    pub const RCC: usize = 0x400F_E060;
    /// Run-mode clock gating 0 (bit 3: the watchdog; QEMU ignores the gating).
    pub const RCGC0: usize = 0x400F_E100;
    /// Run-mode clock gating 1 (UART0..2 are bits 0..2).
    pub const RCGC1: usize = 0x400F_E104;
    /// RCC: where SYSDIV starts.
    pub const RCC_SYSDIV_SHIFT: u32 = 23;
    /// RCC: SYSDIV's four bits.
    pub const RCC_SYSDIV_MASK: u32 = 0xF << RCC_SYSDIV_SHIFT;
    /// RCC: divide the system clock by SYSDIV + 1.
    pub const RCC_USESYSDIV: u32 = 1 << 22;
    /// RCC: the PLL powered down.
    pub const RCC_PWRDN: u32 = 1 << 13;
    /// RCC: the PLL bypassed.
    pub const RCC_BYPASS: u32 = 1 << 11;
    /// RIS: the PLL locked.
    pub const RIS_PLLLRIS: u32 = 1 << 6;
    /// How many RIS reads the boards wait for the PLL to lock (QEMU locks at once).
    pub const PLL_LOCK_POLLS: u32 = 100_000;
    /// RCGC0: the watchdog clocked.
    pub const RCGC0_WDT: u32 = 1 << 3;
    /// RCGC1: UART0..2 clocked.
    pub const RCGC1_UARTS: u32 = 0b111;
    /// RESC: a watchdog reset.
    pub const RESC_WDT: u32 = 1 << 3;
}

/// The watchdog timer (QEMU: `luminary-watchdog`, clocked by the system clock).
pub mod wdt {
    /// WDTLOAD.
    pub const LOAD: usize = 0x4000_0000;
    /// WDTCTL.
    pub const CTL: usize = 0x4000_0008;
    /// WDTICR: any write clears the time-out interrupt and reloads the counter.
    pub const ICR: usize = 0x4000_000C;
    /// WDTCTL: INTEN (bit 0: start counting; only a reset stops it) and RESEN (bit 1: the
    /// second time-out resets).
    pub const CTL_INTEN_RESEN: u32 = 0b11;
}

/// The three PL011 UARTs: where they are, their interrupt lines, their registers (offsets
/// from a base) and bits.
pub mod uart {
    /// UART0, UART1, UART2.
    pub const BASE: [usize; 3] = [0x4000_C000, 0x4000_D000, 0x4000_E000];
    /// Their interrupt lines.
    pub const IRQ: [u16; 3] = [5, 6, 33];
    /// Data (a read: the byte and its error bits).
    pub const DR: usize = 0x000;
    /// Flags.
    pub const FR: usize = 0x018;
    /// Integer baud divisor.
    pub const IBRD: usize = 0x024;
    /// Fractional baud divisor (64ths).
    pub const FBRD: usize = 0x028;
    /// Line control.
    pub const LCRH: usize = 0x02C;
    /// Control.
    pub const CTL: usize = 0x030;
    /// FIFO interrupt levels.
    pub const IFLS: usize = 0x034;
    /// Interrupt mask.
    pub const IMSC: usize = 0x038;
    /// Masked interrupt status.
    pub const MIS: usize = 0x040;
    /// Interrupt clear.
    pub const ICR: usize = 0x044;
    /// FR: the receive FIFO is empty.
    pub const FR_RXFE: u32 = 1 << 4;
    /// FR: the transmit FIFO is full.
    pub const FR_TXFF: u32 = 1 << 5;
    /// FR: the transmit FIFO is empty.
    pub const FR_TXFE: u32 = 1 << 7;
    /// DR's error bits: overrun, break, parity, framing.
    pub const DR_ERRORS: u32 = 0xF00;
    /// Interrupt bits: receive.
    pub const INT_RX: u32 = 1 << 4;
    /// Interrupt bits: transmit.
    pub const INT_TX: u32 = 1 << 5;
    /// Interrupt bits: receive timeout.
    pub const INT_RT: u32 = 1 << 6;
    /// Interrupt bits: all of them.
    pub const INT_ALL: u32 = 0x7FF;
    /// IFLS: RX at half full (the receive-timeout interrupt takes the rest of a burst), TX at
    /// one-eighth full. QEMU's PL011 ignores the levels (RX at the first byte, TX at once).
    pub const IFLS_RX_HALF_TX_EIGHTH: u32 = 0b010 << 3;
    /// LCRH: 8 data bits, FIFOs on.
    pub const LCRH_WLEN8_FEN: u32 = 0x70;
    /// CTL: the UART, its transmitter and its receiver on.
    pub const CTL_UARTEN_TXE_RXE: u32 = (1 << 0) | (1 << 8) | (1 << 9);
    /// Bytes each FIFO holds.
    pub const FIFO: usize = 16;

    /// The baud divisor in 64ths for `baud` from `core_hz`: core clock / (16 x baud), rounded
    /// (IBRD is its quotient by 64, FBRD the rest).
    pub const fn baud_div_64ths(core_hz: u32, baud: u32) -> u32 {
        (core_hz * 4 + baud / 2) / baud
    }
}

/// Defines the LM3S6965's device interrupt table, `__INTERRUPTS` (vectors 0..=33, which
/// cortex-m-rt's `device` feature expects a board to provide): `DefaultHandler` everywhere but
/// UART0, UART1 and UART2, which get the three `unsafe extern "C" fn()` handlers given.
#[macro_export]
macro_rules! lm3s6965_interrupts {
    ($uart0:path, $uart1:path, $uart2:path $(,)?) => {
        /// One entry of the device interrupt table.
        #[derive(Clone, Copy)]
        #[repr(C)]
        pub union Vector {
            handler: unsafe extern "C" fn(),
            reserved: usize,
        }

        unsafe extern "C" {
            fn DefaultHandler();
        }

        /// The LM3S6965's interrupt vectors 0..=33.
        #[unsafe(link_section = ".vector_table.interrupts")]
        #[unsafe(no_mangle)]
        pub static __INTERRUPTS: [Vector; 34] = {
            let mut v = [Vector {
                handler: DefaultHandler,
            }; 34];
            let irq = $crate::lm3s6965::uart::IRQ;
            v[irq[0] as usize] = Vector { handler: $uart0 };
            v[irq[1] as usize] = Vector { handler: $uart1 };
            v[irq[2] as usize] = Vector { handler: $uart2 };
            v
        };
    };
}
