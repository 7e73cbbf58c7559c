//! Logging that costs nothing where there is no log.
//!
//! `info!`, `warn!`, `error!` and `debug!` take `defmt` syntax. With the
//! `defmt` feature on a `target_os = "none"` build they are `defmt`'s macros
//! (the board picks the transport: semihosting on QEMU, RTT on the STM32).
//! Everywhere else, including every host build and test, they expand to code
//! that only borrows the arguments, so nothing is printed, nothing is linked
//! and no "unused variable" warning appears.
//!
//! ```
//! let answer = 42u32;
//! sensor_box::info!("booted, answer = {=u32}", answer);
//! sensor_box::warn!("store missing, using defaults");
//! ```

/// Logs at info level (`defmt::info!` on the target, nothing on the host).
#[cfg(all(feature = "defmt", target_os = "none"))]
#[macro_export]
macro_rules! info {
    ($($t:tt)*) => { $crate::__defmt::info!($($t)*) };
}

/// Logs at warn level (`defmt::warn!` on the target, nothing on the host).
#[cfg(all(feature = "defmt", target_os = "none"))]
#[macro_export]
macro_rules! warn {
    ($($t:tt)*) => { $crate::__defmt::warn!($($t)*) };
}

/// Logs at error level (`defmt::error!` on the target, nothing on the host).
#[cfg(all(feature = "defmt", target_os = "none"))]
#[macro_export]
macro_rules! error {
    ($($t:tt)*) => { $crate::__defmt::error!($($t)*) };
}

/// Logs at debug level (`defmt::debug!` on the target, nothing on the host).
#[cfg(all(feature = "defmt", target_os = "none"))]
#[macro_export]
macro_rules! debug {
    ($($t:tt)*) => { $crate::__defmt::debug!($($t)*) };
}

/// Logs at info level (`defmt::info!` on the target, nothing on the host).
#[cfg(not(all(feature = "defmt", target_os = "none")))]
#[macro_export]
macro_rules! info {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{ $( let _ = &$arg; )* }};
}

/// Logs at warn level (`defmt::warn!` on the target, nothing on the host).
#[cfg(not(all(feature = "defmt", target_os = "none")))]
#[macro_export]
macro_rules! warn {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{ $( let _ = &$arg; )* }};
}

/// Logs at error level (`defmt::error!` on the target, nothing on the host).
#[cfg(not(all(feature = "defmt", target_os = "none")))]
#[macro_export]
macro_rules! error {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{ $( let _ = &$arg; )* }};
}

/// Logs at debug level (`defmt::debug!` on the target, nothing on the host).
#[cfg(not(all(feature = "defmt", target_os = "none")))]
#[macro_export]
macro_rules! debug {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{ $( let _ = &$arg; )* }};
}
