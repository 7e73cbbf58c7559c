//! The logging macros on the host: they print nothing, but evaluate each argument exactly
//! once, as `defmt`'s do on the target, so code with a side effect in a log argument behaves
//! the same in the host tests as in the firmware.

use std::cell::Cell;

#[test]
fn log_macros_evaluate_each_argument_once_on_the_host() {
    let calls = Cell::new(0u32);
    let next = || {
        calls.set(calls.get() + 1);
        calls.get()
    };
    sensor_box::info!("x = {=u32}", next());
    assert_eq!(calls.get(), 1);
    sensor_box::warn!("warn");
    assert_eq!(calls.get(), 1);
    sensor_box::error!("e {} {}", next(), next());
    assert_eq!(calls.get(), 3);
    sensor_box::debug!("d {=u32}", next(),);
    assert_eq!(calls.get(), 4);
}
