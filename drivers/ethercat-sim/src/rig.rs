//! The simulated rig behind the wire: a [`Chain`] of CiA 402 drives whose
//! servo is the physics simulator's actuator model. Each frame is answered
//! by the chain; then every drive that is following moves the simulator
//! for one bus cycle (the target interpolated linearly over the cycle's
//! ticks, as a CSP drive's interpolator does, with the velocity and force
//! feed-forward), and the drives report the simulated stroke and force as
//! their actual position and torque on the next frame. A drive that is
//! not following holds its actuator where it stands (a brake).

use drivers::Simulator;
use upm_ethercat::{EthercatParams, Wire, WireError};
use upm_hardware::{ActuatorCommand, PlateDriver, PlateState};

use crate::chain::{Chain, FrameError};
use crate::cia402::Servo;
use crate::subdevice::SubDevice;

/// Where the drives' clocks take their time from.
pub enum ChainTime {
    /// The plant's own clock: one bus cycle per process-data frame
    /// (deterministic; lock-step runs).
    Plant,
    /// A clock outside (CLOCK_MONOTONIC in real runs, a test's hand-set
    /// clock): the bus then keeps time with the world, and a MainDevice
    /// that wakes late or drifts sees it against SYNC0.
    Source(Box<dyn Fn() -> u64 + Send>),
}

impl core::fmt::Debug for ChainTime {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::Plant => "Plant",
            Self::Source(_) => "Source",
        })
    }
}

#[derive(Debug)]
pub struct SimulatedRig {
    pub chain: Chain,
    pub sim: Simulator,
    counts_per_metre: f64,
    rated_force_n: f64,
    ticks_per_cycle: u32,
    command: ActuatorCommand,
    /// The targets of the cycle before, where interpolation starts.
    previous: ActuatorCommand,
    state: PlateState,
    /// The plant's clock (ns).
    time_ns: u64,
    /// The chain's time base.
    pub chain_time: ChainTime,
}

impl SimulatedRig {
    /// [`SimulatedRig::new`] with the scaling and bus cycle the driver
    /// will use.
    pub fn for_params(sim: Simulator, p: &EthercatParams) -> Self {
        Self::new(sim, p.counts_per_metre, p.rated_force_n, p.cycle_divisor)
    }

    /// One drive per actuator of `sim`'s rig, each moving its actuator;
    /// `ticks_per_cycle` simulator ticks per bus cycle.
    pub fn new(sim: Simulator, counts_per_metre: f64, rated_force_n: f64, ticks_per_cycle: u32) -> Self {
        let n = sim.rig().count();
        let devices = (0..n)
            .map(|_| {
                let mut d = SubDevice::servo_drive();
                d.drive.servo = Servo::External;
                d.drive.rated_torque = rated_force_n.round().clamp(1.0, f64::from(u32::MAX)) as u32;
                d
            })
            .collect();
        Self {
            chain: Chain::new(devices),
            sim,
            counts_per_metre,
            rated_force_n,
            ticks_per_cycle: ticks_per_cycle.max(1),
            command: ActuatorCommand::HOME,
            previous: ActuatorCommand::HOME,
            state: PlateState::default(),
            time_ns: 0,
            chain_time: ChainTime::Plant,
        }
    }

    /// One bus cycle of the plant.
    fn step(&mut self) {
        let n = self.sim.rig().count().min(self.chain.devices.len());
        let mut target = ActuatorCommand::HOME;
        for (i, d) in self.chain.devices.iter().enumerate().take(n) {
            let drive = &d.drive;
            if drive.is_following() {
                target.position[i] = f64::from(drive.target) / self.counts_per_metre;
                target.velocity[i] = f64::from(drive.velocity_offset) / self.counts_per_metre;
                target.force[i] = f64::from(drive.torque_offset) / 1000.0 * self.rated_force_n;
            } else {
                target.position[i] = self.state.actuator_position[i];
            }
        }
        let ticks = self.ticks_per_cycle;
        let span = f64::from(ticks) * self.sim.config().tick_hz.recip();
        let (a, b) = (&self.previous, &target);
        for k in 1..=ticks {
            // Cubic Hermite between the two targets and their velocities,
            // force linear: position, velocity and force stay consistent.
            let s = f64::from(k) / f64::from(ticks);
            let (s2, s3) = (s * s, s * s * s);
            let (h00, h10, h01, h11) =
                (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
            let (d00, d10, d11) = (6.0 * s2 - 6.0 * s, 3.0 * s2 - 4.0 * s + 1.0, 3.0 * s2 - 2.0 * s);
            for i in 0..n {
                let (p0, p1, v0, v1) = (a.position[i], b.position[i], a.velocity[i], b.velocity[i]);
                self.command.position[i] = h00 * p0 + h10 * span * v0 + h01 * p1 + h11 * span * v1;
                self.command.velocity[i] = (d00 * (p0 - p1)) / span + d10 * v0 + d11 * v1;
                self.command.force[i] = a.force[i] + (b.force[i] - a.force[i]) * s;
            }
            // Targets come from the drive's own limits check upstream;
            // a clamp here is counted by the simulator.
            let _ = self.sim.write(&self.command);
            self.sim.advance();
        }
        self.previous = target;
        self.time_ns += (span * 1e9).round() as u64;
        let _ = self.sim.read(&mut self.state);
        for (i, d) in self.chain.devices.iter_mut().enumerate().take(n) {
            d.drive.actual = (self.state.actuator_position[i] * self.counts_per_metre).round() as i32;
            d.drive.torque_actual =
                (self.state.actuator_force[i] / self.rated_force_n * 1000.0).round() as i16;
        }
    }
}

impl Wire for SimulatedRig {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError> {
        let cycles = |c: &Chain| c.devices.iter().map(|d| d.cycles).sum::<u64>();
        let before = cycles(&self.chain);
        let now = match &self.chain_time {
            ChainTime::Plant => self.time_ns,
            ChainTime::Source(clock) => clock(),
        };
        self.chain.set_time(now);
        let answered = self.chain.answer(frame);
        // A bus cycle passes with each process-data frame, and with each
        // lost frame (the MainDevice keeps its cycle); start-up's register
        // and mailbox frames take no plant time.
        if cycles(&self.chain) != before || answered == Err(FrameError::Lost) {
            self.step();
        }
        match answered {
            Ok(()) => Ok(()),
            Err(FrameError::Lost) => Err(WireError::Lost),
            Err(_) => Err(WireError::Refused),
        }
    }
}
