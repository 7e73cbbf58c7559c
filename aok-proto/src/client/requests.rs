//! The blocking helpers: run one command to its end on a clock the caller gives.

use super::*;

impl<S: Read<u8> + Write<u8>> Client<S> {
    /// Start `command` and poll until it is over, reading the time from `now_ms`.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, ClientError, Command, Config, FirmwareVersion, Outcome,
    ///                 ParameterValue};
    /// // A fake device (hidden here) where parameter n holds n * 10.
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// // On hardware, `now_ms` reads a timer; `fake_clock` moves 1 ms a call.
    /// let outcome = client.run(Command::ReadParameter(12), fake_clock());
    /// assert_eq!(outcome, Ok(Outcome::Parameter(ParameterValue { number: 12, value: 120 })));
    /// // Debug output off, the request, debug output on.
    /// assert_eq!(client.serial_mut().take_sent(), [0x63, 0x01, 0x67, 0x0C, 0x63, 0x02]);
    /// // An unplugged port fails the operation.
    /// client.serial_mut().unplug();
    /// let failed = client.run(Command::SaveSet(1), fake_clock());
    /// assert_eq!(failed, Err(ClientError::Serial(aok_proto::SerialError::Other)));
    /// # }
    /// ```
    pub fn run(
        &mut self,
        command: Command,
        now_ms: impl FnMut() -> u32,
    ) -> Result<Outcome, ClientError> {
        self.start(command)?;
        self.wait(now_ms)
    }

    /// Poll the running operation until it is over. With no operation running it returns
    /// [`ClientError::Timeout`] at once.
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, ClientError, Command, Config, FirmwareVersion, Outcome};
    /// // A fake device (hidden here).
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// client.start(Command::SaveSet(2)).unwrap();
    /// assert_eq!(client.wait(fake_clock()), Ok(Outcome::Sent));
    /// // Nothing left to wait for.
    /// assert_eq!(client.wait(fake_clock()), Err(ClientError::Timeout));
    /// # }
    /// ```
    pub fn wait(&mut self, mut now_ms: impl FnMut() -> u32) -> Result<Outcome, ClientError> {
        if self.phase == Phase::Idle {
            return Err(ClientError::Timeout);
        }
        loop {
            match self.poll(now_ms()) {
                Ok(o) => return Ok(o),
                Err(nb::Error::Other(e)) => return Err(e),
                Err(nb::Error::WouldBlock) => {}
            }
        }
    }

    /// Read one parameter (blocking helper).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion};
    /// // A fake device (hidden here) with firmware 0.30, whose reply has no header: the client
    /// // knows which parameter it asked for.
    /// let mut device = FakeDevice::new();
    /// device.firmware = FirmwareVersion::new(0, 30);
    /// device.params[12] = -1500;
    /// let mut client = Client::new(device, Config::new(FirmwareVersion::new(0, 30)));
    /// assert_eq!(client.read_parameter(12, fake_clock()), Ok(-1500));
    /// assert_eq!(client.read_parameter(13, fake_clock()), Ok(130));
    /// # }
    /// ```
    pub fn read_parameter(
        &mut self,
        number: u8,
        now_ms: impl FnMut() -> u32,
    ) -> Result<i32, ClientError> {
        match self.run(Command::ReadParameter(number), now_ms)? {
            Outcome::Parameter(p) => Ok(p.value),
            _ => Err(ClientError::Timeout),
        }
    }

    /// Read parameters `first..first+16` with one bulk read (firmware >= 0.35; blocking helper).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, ClientError, Config, FirmwareVersion};
    /// // A fake device (hidden here) where parameter n holds n * 10.
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// let values = client.bulk_read(32, fake_clock()).unwrap();
    /// assert_eq!((values[0], values[15]), (320, 470));
    /// // One request for the 16 values, between debug off and on.
    /// assert_eq!(client.serial_mut().take_sent(), [0x63, 0x01, 0x47, 0x20, 0x63, 0x02]);
    ///
    /// let mut old = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::new(0, 34)));
    /// assert_eq!(old.bulk_read(32, fake_clock()), Err(ClientError::Unsupported));
    /// # }
    /// ```
    pub fn bulk_read(
        &mut self,
        first: u8,
        now_ms: impl FnMut() -> u32,
    ) -> Result<[i32; 16], ClientError> {
        match self.run(Command::BulkRead(first), now_ms)? {
            Outcome::Bulk(b) => Ok(b.values),
            _ => Err(ClientError::Timeout),
        }
    }

    /// Read a waypoint (blocking helper).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Action, ActionWord, Client, ClientError, Config, FirmwareVersion, Waypoint,
    ///                 WaypointNumber, WaypointSlot};
    /// // A fake device (hidden here) holding waypoint 1.
    /// let first = WaypointSlot::Waypoint(WaypointNumber::new(1).unwrap());
    /// let hold = ActionWord::new(Action::HoldAndClimb, 10);
    /// let waypoint = Waypoint { slot: first, longitude: 8_000_000, latitude: 47_000_000,
    ///                           action1: hold, action2: ActionWord::NONE };
    /// let mut device = FakeDevice::new();
    /// device.waypoints.push(waypoint);
    /// let mut client = Client::new(device, Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.read_waypoint(first, fake_clock()), Ok(waypoint));
    /// // Nothing in slot 2: this device does not answer, and the read times out.
    /// let second = WaypointSlot::Waypoint(WaypointNumber::new(2).unwrap());
    /// assert_eq!(client.read_waypoint(second, fake_clock()), Err(ClientError::Timeout));
    /// # }
    /// ```
    pub fn read_waypoint(
        &mut self,
        slot: WaypointSlot,
        now_ms: impl FnMut() -> u32,
    ) -> Result<Waypoint, ClientError> {
        match self.run(Command::ReadWaypoint(slot), now_ms)? {
            Outcome::Waypoint(w) => Ok(w),
            _ => Err(ClientError::Timeout),
        }
    }

    /// Set a parameter and wait for the ack (blocking helper). 'E' and 'I' come back as
    /// [`ClientError::Rejected`] and [`ClientError::RefusedInFlight`].
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Ack, Client, ClientError, Config, FirmwareVersion};
    /// // A fake device (hidden here).
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// assert_eq!(client.set_parameter(12, 1500, fake_clock()), Ok(()));
    /// assert_eq!(client.read_parameter(12, fake_clock()), Ok(1500));
    /// // In flight, the device refuses with 'I'.
    /// client.serial_mut().ack = Ack::InFlight;
    /// let refused = client.set_parameter(12, 0, fake_clock());
    /// assert_eq!(refused, Err(ClientError::RefusedInFlight));
    /// client.serial_mut().ack = Ack::Error;
    /// assert_eq!(client.set_parameter(12, 0, fake_clock()), Err(ClientError::Rejected));
    /// assert_eq!(client.release().params[12], 1500);
    /// # }
    /// ```
    pub fn set_parameter(
        &mut self,
        number: u8,
        value: i32,
        now_ms: impl FnMut() -> u32,
    ) -> Result<(), ClientError> {
        let cmd = Command::SetParameter(ParameterValue { number, value });
        self.run(cmd, now_ms).map(|_| ())
    }

    /// Set a waypoint and wait for the ack (blocking helper).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{ActionWord, Client, Config, FirmwareVersion, Waypoint, WaypointSlot};
    /// // A fake device (hidden here).
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// let target = Waypoint { slot: WaypointSlot::FbcTarget, longitude: 8_000_000,
    ///                         latitude: 47_000_000, action1: ActionWord::NONE,
    ///                         action2: ActionWord::NONE };
    /// assert_eq!(client.set_waypoint(target, fake_clock()), Ok(()));
    /// // The 19-byte `77` frame went out between debug off and on.
    /// let sent = client.serial_mut().take_sent();
    /// assert_eq!((sent.len(), sent[2], sent[3]), (2 + 19 + 2, 0x77, 255));
    /// assert_eq!(client.read_waypoint(WaypointSlot::FbcTarget, fake_clock()), Ok(target));
    /// # }
    /// ```
    pub fn set_waypoint(
        &mut self,
        waypoint: Waypoint,
        now_ms: impl FnMut() -> u32,
    ) -> Result<(), ClientError> {
        self.run(Command::SetWaypoint(waypoint), now_ms).map(|_| ())
    }

    /// Send one motor-test value (no reply; repeat within 500 ms to keep the motor running).
    ///
    /// ```
    /// # include!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/client/doc_device.rs"));
    /// # fn main() {
    /// use aok_proto::{Client, Config, FirmwareVersion, Motor, MotorTest};
    /// // A fake device (hidden here).
    /// let mut client = Client::new(FakeDevice::new(), Config::new(FirmwareVersion::LATEST));
    /// let test = MotorTest { motor: Motor::new(3).unwrap(), value: 40 };
    /// assert_eq!(client.motor_test(test, fake_clock()), Ok(()));
    /// // No reply to wait for, so no debug off and on around it: motor 3's byte, the value,
    /// // the XOR.
    /// assert_eq!(client.serial_mut().take_sent(), [0x33, 0x28, 0x1B]);
    /// # }
    /// ```
    pub fn motor_test(
        &mut self,
        test: MotorTest,
        now_ms: impl FnMut() -> u32,
    ) -> Result<(), ClientError> {
        self.run(Command::MotorTest(test), now_ms).map(|_| ())
    }
}
