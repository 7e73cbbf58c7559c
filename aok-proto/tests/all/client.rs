//! The client against a scripted in-memory device (serial traits implemented on a test double).

use crate::watchdog;

use std::collections::VecDeque;

use aok_proto::{
    Ack, Action, ActionWord, Client, ClientError, Command, CommandDecoder, Config, DebugValue,
    ExternalControl, FirmwareVersion, Message, Motor, MotorTest, Outcome, ParameterValue,
    ReplyForm, SerialError, Stick, Waypoint, WaypointNumber, WaypointSlot,
};
use aok_proto::{Decode, Expect};
use embedded_hal_nb::serial::{ErrorKind, ErrorType, Read, Write};

/// A device on the other end of the wire, driven only by what the client writes and reads.
struct Device {
    to_pc: VecDeque<u8>,
    from_pc: Vec<u8>,
    decoder: CommandDecoder,
    form: ReplyForm,
    debug_on: bool,
    /// Debug frames still sent after debug-off (in flight).
    late_debug: usize,
    /// Whether it answers requests at all.
    answers: bool,
    /// The ack to `73` / `77`.
    ack: Ack,
    params: [i32; 256],
    waypoint: Option<Waypoint>,
    /// Debug frames pushed into the middle of a bulk reply.
    debug_inside_bulk: bool,
    /// Every other write returns WouldBlock.
    slow_writes: bool,
    write_calls: u32,
    counter: i32,
}

impl Device {
    fn new(form: ReplyForm) -> Self {
        let mut params = [0i32; 256];
        for (i, p) in params.iter_mut().enumerate() {
            *p = i as i32 * 100 - 5000;
        }
        Self {
            to_pc: VecDeque::new(),
            from_pc: Vec::new(),
            decoder: CommandDecoder::new(),
            form,
            debug_on: true,
            late_debug: 2,
            answers: true,
            ack: Ack::Ok,
            params,
            waypoint: None,
            debug_inside_bulk: false,
            slow_writes: false,
            write_calls: 0,
            counter: 0,
        }
    }

    fn send(&mut self, m: Message) {
        let mut buf = [0u8; 19];
        let n = m.emit(&mut buf, self.form).unwrap();
        self.to_pc.extend(&buf[..n]);
    }

    fn send_debug(&mut self) {
        self.counter += 1;
        self.send(Message::Debug(DebugValue {
            number: 86,
            value: self.counter,
        }));
    }

    fn on_command(&mut self, cmd: Command) {
        match cmd {
            Command::DebugOff => {
                self.debug_on = false;
                for _ in 0..self.late_debug {
                    self.send_debug();
                }
            }
            Command::DebugOn => self.debug_on = true,
            _ if !self.answers => {}
            Command::ReadParameter(n) => {
                let value = self.params[usize::from(n)];
                self.send(Message::Parameter(ParameterValue { number: n, value }));
            }
            Command::BulkRead(first) => {
                for i in 0..16u8 {
                    let number = first.wrapping_add(i);
                    let value = self.params[usize::from(number)];
                    self.send(Message::Parameter(ParameterValue { number, value }));
                    if self.debug_inside_bulk && i % 5 == 2 {
                        self.send_debug();
                    }
                }
            }
            Command::SetParameter(p) => {
                if self.ack == Ack::Ok {
                    self.params[usize::from(p.number)] = p.value;
                }
                self.send(Message::Ack(self.ack));
            }
            Command::SetWaypoint(w) => {
                self.waypoint = Some(w);
                self.send(Message::Ack(self.ack));
            }
            Command::ReadWaypoint(s) => {
                if let Some(w) = self.waypoint.filter(|w| w.slot == s) {
                    self.send(Message::Waypoint(w));
                }
            }
            _ => {}
        }
    }
}

impl ErrorType for Device {
    type Error = ErrorKind;
}

impl Read<u8> for Device {
    fn read(&mut self) -> nb::Result<u8, ErrorKind> {
        if self.to_pc.is_empty() && self.debug_on {
            self.send_debug();
        }
        self.to_pc.pop_front().ok_or(nb::Error::WouldBlock)
    }
}

impl Write<u8> for Device {
    fn write(&mut self, byte: u8) -> nb::Result<(), ErrorKind> {
        self.write_calls += 1;
        if self.slow_writes && self.write_calls % 2 == 1 {
            return Err(nb::Error::WouldBlock);
        }
        self.from_pc.push(byte);
        let mut cmds = Vec::new();
        self.decoder.feed(&[byte], |c| cmds.push(c));
        for c in cmds {
            self.on_command(c.expect("the client sent a bad frame"));
        }
        Ok(())
    }
    fn flush(&mut self) -> nb::Result<(), ErrorKind> {
        Ok(())
    }
}

/// A fake millisecond clock: every reading is one ms later. No real time involved.
fn clock() -> impl FnMut() -> u32 {
    let mut t = 0u32;
    move || {
        t = t.wrapping_add(1);
        t
    }
}

fn client(dev: Device, fw: FirmwareVersion) -> Client<Device> {
    Client::new(dev, Config::new(fw))
}

/// A client that has written `ReadParameter(number)` to a device that sends nothing by itself
/// (no debug values, no answers): the test scripts what comes back.
fn asking_a_scripted_device(number: u8) -> Client<Device> {
    let mut dev = Device::new(ReplyForm::Headed);
    dev.debug_on = false;
    dev.answers = false;
    let mut cfg = Config::new(FirmwareVersion::LATEST);
    cfg.debug_on = false;
    let mut c = Client::new(dev, cfg);
    c.start(Command::ReadParameter(number)).unwrap();
    assert_eq!(c.poll(0), Err(nb::Error::WouldBlock)); // request written
    c
}

#[test]
fn read_parameter_with_late_debug_frames() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.late_debug = 3;
    let mut c = client(dev, FirmwareVersion::LATEST);
    assert_eq!(c.read_parameter(12, clock()), Ok(12 * 100 - 5000));
    assert!(c.debug_enabled());
    let dev = c.serial_mut();
    assert_eq!(dev.from_pc, [0x63, 0x01, 0x67, 0x0c, 0x63, 0x02]);
    assert!(dev.debug_on);
    // The debug values seen (including the late ones) are queued, newest last.
    let mut n = 0;
    let mut last = 0;
    while let Some(d) = c.next_debug() {
        assert_eq!(d.number, 86);
        assert!(d.value > last);
        last = d.value;
        n += 1;
    }
    assert!(n >= 3, "saw {n} debug values");
    assert_eq!(c.stats().stray, 0);
}

#[test]
fn read_parameter_headerless_firmware_with_late_debug() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headerless);
    dev.params[9] = 0x1c00_00aa; // the reply starts with 1C, like a debug frame
    let mut c = client(dev, FirmwareVersion::new(0, 30));
    assert_eq!(c.read_parameter(9, clock()), Ok(0x1c00_00aa));
    assert_eq!(c.read_parameter(10, clock()), Ok(-4000));
}

#[test]
fn late_debug_frame_after_the_request_is_tolerated() {
    let _watchdog = watchdog::arm();
    // A device that is slow to obey debug-off: a debug frame arrives between the request and the
    // reply. The 1/256 ambiguity of the headerless form does not hit this frame (checked).
    for (fw, form) in [
        (FirmwareVersion::LATEST, ReplyForm::Headed),
        (FirmwareVersion::new(0, 30), ReplyForm::Headerless),
    ] {
        let mut dev = Device::new(form);
        dev.debug_on = false;
        dev.answers = false;
        let mut cfg = Config::new(fw);
        cfg.debug_on = false;
        let mut c = Client::new(dev, cfg);
        c.start(Command::ReadParameter(40)).unwrap();
        let mut now = clock();
        assert_eq!(c.poll(now()), Err(nb::Error::WouldBlock)); // request written
        let dev = c.serial_mut();
        dev.send(Message::Debug(DebugValue {
            number: 86,
            value: 0x0102_0304,
        }));
        dev.send(Message::Parameter(ParameterValue {
            number: 40,
            value: 77,
        }));
        let got = c.wait(now);
        assert_eq!(
            got,
            Ok(Outcome::Parameter(ParameterValue {
                number: 40,
                value: 77
            }))
        );
        assert_eq!(c.next_debug().map(|d| d.value), Some(0x0102_0304));
    }
}

#[test]
fn a_reply_hidden_behind_a_false_start_is_found_when_the_line_goes_quiet() {
    let _watchdog = watchdog::arm();
    // A stray 0x77 (a waypoint frame's start, 19 bytes) right before the reply: the decoder
    // waits for 19 bytes that never come; once the line is quiet it gives the false start up
    // and finds the reply behind it, long before the timeout.
    let quiet = Config::new(FirmwareVersion::LATEST).quiet_ms;
    let mut c = asking_a_scripted_device(40);
    let dev = c.serial_mut();
    dev.to_pc.push_back(0x77);
    dev.send(Message::Parameter(ParameterValue {
        number: 40,
        value: 77,
    }));
    for _ in 0..8 {
        assert_eq!(c.poll(1), Err(nb::Error::WouldBlock));
    }
    assert_eq!(c.poll(quiet), Err(nb::Error::WouldBlock));
    let want = Outcome::Parameter(ParameterValue {
        number: 40,
        value: 77,
    });
    assert_eq!(c.poll(1 + quiet), Ok(want));
}

#[test]
fn a_waypoint_of_another_slot_is_not_the_answer() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.debug_on = false;
    let mut cfg = Config::new(FirmwareVersion::LATEST);
    cfg.debug_on = false;
    let mut c = Client::new(dev, cfg);
    let asked = WaypointSlot::Waypoint(WaypointNumber::new(3).unwrap());
    c.start(Command::ReadWaypoint(asked)).unwrap();
    assert_eq!(c.poll(0), Err(nb::Error::WouldBlock)); // request written
    let other = Waypoint {
        slot: WaypointSlot::Waypoint(WaypointNumber::new(4).unwrap()),
        longitude: 1,
        latitude: 2,
        action1: ActionWord::NONE,
        action2: ActionWord::NONE,
    };
    c.serial_mut().send(Message::Waypoint(other));
    assert_eq!(c.wait(clock()), Err(ClientError::Timeout));
}

#[test]
fn the_first_answer_counts_and_a_second_one_is_ignored() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.debug_on = false;
    dev.answers = false;
    let mut cfg = Config::new(FirmwareVersion::LATEST);
    cfg.debug_on = false;
    let mut c = Client::new(dev, cfg);
    c.start(Command::ReadParameter(40)).unwrap();
    assert_eq!(c.poll(0), Err(nb::Error::WouldBlock)); // request written
    for value in [77, 88] {
        c.serial_mut()
            .send(Message::Parameter(ParameterValue { number: 40, value }));
    }
    let want = Outcome::Parameter(ParameterValue {
        number: 40,
        value: 77,
    });
    assert_eq!(c.wait(clock()), Ok(want));
}

#[test]
fn device_that_never_answers_times_out_and_debug_is_restored() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.answers = false;
    let mut c = client(dev, FirmwareVersion::LATEST);
    assert_eq!(c.read_parameter(12, clock()), Err(ClientError::Timeout));
    assert!(c.is_idle());
    assert!(c.debug_enabled());
    assert_eq!(c.serial_mut().from_pc, [0x63, 0x01, 0x67, 0x0c, 0x63, 0x02]);
    assert!(c.serial_mut().debug_on);
    // The client is usable again once the device answers.
    c.serial_mut().answers = true;
    assert_eq!(c.read_parameter(1, clock()), Ok(-4900));
}

#[test]
fn timeout_is_measured_on_the_callers_clock() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.answers = false;
    dev.debug_on = false;
    let mut cfg = Config::new(FirmwareVersion::LATEST);
    cfg.debug_on = false;
    cfg.timeout_ms = 300;
    let mut c = Client::new(dev, cfg);
    c.start(Command::ReadParameter(3)).unwrap();
    assert_eq!(c.poll(1000), Err(nb::Error::WouldBlock));
    assert_eq!(c.poll(1299), Err(nb::Error::WouldBlock));
    assert_eq!(c.poll(1300), Err(nb::Error::Other(ClientError::Timeout)));
    assert!(c.is_idle());
}

#[test]
fn bulk_read_of_sixteen_with_debug_frames_inside() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.debug_inside_bulk = true;
    let mut c = client(dev, FirmwareVersion::LATEST);
    let values = c.bulk_read(20, clock()).unwrap();
    let want: Vec<i32> = (20..36).map(|i| i * 100 - 5000).collect();
    assert_eq!(values.to_vec(), want);
    assert_eq!(c.serial_mut().from_pc, [0x63, 0x01, 0x47, 20, 0x63, 0x02]);
}

#[test]
fn bulk_read_needs_firmware_035() {
    let _watchdog = watchdog::arm();
    let mut c = client(Device::new(ReplyForm::Headed), FirmwareVersion::new(0, 34));
    assert_eq!(c.start(Command::BulkRead(0)), Err(ClientError::Unsupported));
    assert!(c.is_idle());
}

#[test]
fn set_parameter_acks() {
    let _watchdog = watchdog::arm();
    for (ack, want) in [
        (Ack::Ok, Ok(())),
        (Ack::Error, Err(ClientError::Rejected)),
        (Ack::InFlight, Err(ClientError::RefusedInFlight)),
    ] {
        let mut dev = Device::new(ReplyForm::Headed);
        dev.ack = ack;
        let mut c = client(dev, FirmwareVersion::LATEST);
        assert_eq!(c.set_parameter(12, 1500, clock()), want);
        let dev = c.serial_mut();
        assert_eq!(
            dev.from_pc,
            [
                0x63, 0x01, 0x73, 0x0c, 0x00, 0x00, 0x05, 0xdc, 0xd5, 0x63, 0x02
            ]
        );
        assert_eq!(dev.params[12] == 1500, ack == Ack::Ok);
    }
}

#[test]
fn waypoint_set_and_read_back() {
    let _watchdog = watchdog::arm();
    let w = Waypoint {
        slot: WaypointSlot::Waypoint(WaypointNumber::new(4).unwrap()),
        longitude: 1,
        latitude: -2,
        action1: ActionWord::new(Action::Pause, 10),
        action2: ActionWord::NONE,
    };
    let mut c = client(Device::new(ReplyForm::Headed), FirmwareVersion::LATEST);
    assert_eq!(c.set_waypoint(w, clock()), Ok(()));
    assert_eq!(c.read_waypoint(w.slot, clock()), Ok(w));
    // A slot the device does not answer for times out.
    assert_eq!(
        c.read_waypoint(WaypointSlot::FbcTarget, clock()),
        Err(ClientError::Timeout)
    );
}

#[test]
fn fire_and_forget_commands_skip_the_debug_dance() {
    let _watchdog = watchdog::arm();
    let mut c = client(Device::new(ReplyForm::Headed), FirmwareVersion::LATEST);
    let test = MotorTest {
        motor: Motor::new(3).unwrap(),
        value: 40,
    };
    assert_eq!(c.motor_test(test, clock()), Ok(()));
    let ec = ExternalControl {
        roll: Stick::new(32).unwrap(),
        nick: Stick::new(-32).unwrap(),
        yaw: Stick::CENTER,
        pitch: 0,
        expiry_ms: 500,
    };
    assert_eq!(
        c.run(Command::ExternalControl(ec), clock()),
        Ok(Outcome::Sent)
    );
    assert_eq!(c.run(Command::SaveSet(2), clock()), Ok(Outcome::Sent));
    assert_eq!(
        c.serial_mut().from_pc,
        [
            0x33, 0x28, 0x1b, 0x53, 0x20, 0x00, 0xe0, 0xff, 0x00, 0x00, 0x00, 0x00, 0xf4, 0x01,
            0xca, 0x63, 0x04, 0x02
        ]
    );
    assert!(c.debug_enabled());
}

#[test]
fn debug_off_on_and_reset_track_the_debug_state() {
    let _watchdog = watchdog::arm();
    let mut c = client(Device::new(ReplyForm::Headed), FirmwareVersion::LATEST);
    assert_eq!(c.run(Command::DebugOff, clock()), Ok(Outcome::Sent));
    assert!(!c.debug_enabled());
    // Debug is off: a read goes straight out, with no off/on around it.
    c.serial_mut().from_pc.clear();
    assert_eq!(c.read_parameter(2, clock()), Ok(-4800));
    assert_eq!(c.serial_mut().from_pc, [0x67, 0x02]);
    assert_eq!(c.run(Command::DebugOn, clock()), Ok(Outcome::Sent));
    assert!(c.debug_enabled());
    // Reset is preceded by debug-off and not followed by debug-on (the device restarts).
    c.serial_mut().from_pc.clear();
    assert_eq!(c.run(Command::Reset, clock()), Ok(Outcome::Sent));
    assert_eq!(c.serial_mut().from_pc, [0x63, 0x01, 0x63, 0x07]);
}

#[test]
fn busy_while_running_and_custom_expectation() {
    let _watchdog = watchdog::arm();
    let mut c = client(Device::new(ReplyForm::Headed), FirmwareVersion::LATEST);
    c.start(Command::ReadParameter(1)).unwrap();
    assert_eq!(c.start(Command::ReadParameter(2)), Err(ClientError::Busy));
    assert_eq!(
        c.wait(clock()),
        Ok(Outcome::Parameter(ParameterValue {
            number: 1,
            value: -4900
        }))
    );
    // A firmware that acks save-set can be waited on explicitly (this device does not: timeout).
    c.start_expecting(Command::SaveSet(1), Expect::Ack).unwrap();
    assert_eq!(c.wait(clock()), Err(ClientError::Timeout));
}

#[test]
fn slow_serial_writes_still_complete() {
    let _watchdog = watchdog::arm();
    let mut dev = Device::new(ReplyForm::Headed);
    dev.slow_writes = true;
    let mut c = client(dev, FirmwareVersion::LATEST);
    assert_eq!(c.read_parameter(7, clock()), Ok(-4300));
    assert_eq!(c.serial_mut().from_pc, [0x63, 0x01, 0x67, 0x07, 0x63, 0x02]);
}

/// A port whose writes fail: the error comes back typed, and the client is idle again.
struct Broken;
impl ErrorType for Broken {
    type Error = ErrorKind;
}
impl Read<u8> for Broken {
    fn read(&mut self) -> nb::Result<u8, ErrorKind> {
        Err(nb::Error::Other(ErrorKind::Overrun))
    }
}
impl Write<u8> for Broken {
    fn write(&mut self, _: u8) -> nb::Result<(), ErrorKind> {
        Err(nb::Error::Other(ErrorKind::Noise))
    }
    fn flush(&mut self) -> nb::Result<(), ErrorKind> {
        Ok(())
    }
}

#[test]
fn serial_errors_are_reported() {
    let _watchdog = watchdog::arm();
    let mut c = Client::new(Broken, Config::new(FirmwareVersion::LATEST));
    assert_eq!(
        c.read_parameter(1, clock()),
        Err(ClientError::Serial(SerialError::Noise))
    );
    assert!(c.is_idle());
    assert!(c.stats().read_errors > 0);
}

#[test]
fn the_client_is_busy_from_start_to_outcome_and_idle_after() {
    let _watchdog = watchdog::arm();
    let mut c = client(Device::new(ReplyForm::Headed), FirmwareVersion::LATEST);
    assert!(c.is_idle());
    c.start(Command::ReadParameter(12)).unwrap();
    assert!(!c.is_idle());
    // A second operation is refused while the first runs.
    assert!(c.start(Command::ReadParameter(13)).is_err());
    let mut now = clock();
    // Bounded: a client that never concludes fails here instead of hanging the test.
    let mut outcome = None;
    for _ in 0..10_000 {
        match c.poll(now()) {
            Ok(o) => {
                outcome = Some(o);
                break;
            }
            Err(nb::Error::WouldBlock) => assert!(!c.is_idle()),
            Err(nb::Error::Other(e)) => panic!("{e:?}"),
        }
    }
    let outcome = outcome.expect("no outcome in 10,000 polls");
    assert!(matches!(outcome, Outcome::Parameter(p) if p.number == 12));
    assert!(c.is_idle());
}

#[test]
fn a_full_debug_queue_drops_the_oldest_and_keeps_the_order() {
    let _watchdog = watchdog::arm();
    use aok_proto::client::DEBUG_QUEUE;
    let mut dev = Device::new(ReplyForm::Headed);
    dev.debug_on = false; // only the frames queued below
    let mut c = client(dev, FirmwareVersion::LATEST);
    let extra = 3;
    for _ in 0..DEBUG_QUEUE + extra {
        c.serial_mut().send_debug(); // values 1, 2, 3, ...
    }
    // Idle, the client still reads the line (at most MAX_READS_PER_POLL bytes a poll).
    for t in 0..20 {
        assert_eq!(c.poll(t), Err(nb::Error::WouldBlock));
    }
    assert!(c.serial_mut().to_pc.is_empty());
    let got: Vec<i32> = std::iter::from_fn(|| c.next_debug())
        .map(|d| d.value)
        .collect();
    let want: Vec<i32> = (1 + extra as i32..=(DEBUG_QUEUE + extra) as i32).collect();
    assert_eq!(got, want);
    assert_eq!(c.stats().debug_values, (DEBUG_QUEUE + extra) as u32);
    assert_eq!(c.stats().debug_dropped, extra as u32);
    // The ring goes on from where it wrapped: two more come out in order.
    c.serial_mut().send_debug();
    c.serial_mut().send_debug();
    assert_eq!(c.poll(20), Err(nb::Error::WouldBlock));
    assert_eq!(c.next_debug().map(|d| d.value), Some(20));
    assert_eq!(c.next_debug().map(|d| d.value), Some(21));
    assert_eq!(c.next_debug(), None);
}

#[test]
fn a_parameter_reply_of_another_number_is_not_the_answer() {
    let _watchdog = watchdog::arm();
    let mut c = asking_a_scripted_device(40);
    let dev = c.serial_mut();
    dev.send(Message::Parameter(ParameterValue {
        number: 41,
        value: -1,
    }));
    dev.send(Message::Parameter(ParameterValue {
        number: 40,
        value: 77,
    }));
    let want = Outcome::Parameter(ParameterValue {
        number: 40,
        value: 77,
    });
    assert_eq!(c.poll(1), Ok(want));
    assert_eq!(c.stats().stray, 1);
}
