//! The logging macros.

#[test]
fn log_macros_compile_to_nothing_on_the_host() {
    let x = 5u32;
    sensor_box::info!("x = {=u32}", x);
    sensor_box::warn!("warn");
    sensor_box::error!("e {} {}", x, x + 1);
    sensor_box::debug!("d {=u32}", x,);
}
