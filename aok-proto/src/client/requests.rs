//! The blocking helpers: run one command to its end on a clock the caller gives.

use super::*;

impl<S: Read<u8> + Write<u8>> Client<S> {
    /// Start `command` and poll until it is over, reading the time from `now_ms`.
    ///
    /// See the type-level example.
    pub fn run(
        &mut self,
        command: Command,
        now_ms: impl FnMut() -> u32,
    ) -> Result<Outcome, ClientError> {
        self.start(command)?;
        self.wait(now_ms)
    }

    /// Poll the running operation until it is over.
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
    pub fn set_waypoint(
        &mut self,
        waypoint: Waypoint,
        now_ms: impl FnMut() -> u32,
    ) -> Result<(), ClientError> {
        self.run(Command::SetWaypoint(waypoint), now_ms).map(|_| ())
    }

    /// Send one motor-test value (no reply; repeat within 500 ms to keep the motor running).
    pub fn motor_test(
        &mut self,
        test: MotorTest,
        now_ms: impl FnMut() -> u32,
    ) -> Result<(), ClientError> {
        self.run(Command::MotorTest(test), now_ms).map(|_| ())
    }
}
