//! [`EthercatDriver`]: one CiA 402 drive per actuator in cyclic synchronous
//! position mode, behind the same [`PlateDriver`] as the simulator.
//!
//! Every `cycle_divisor` ticks, `advance` sends the targets (position,
//! velocity and force feed-forward) and the controlwords in one LRW and
//! reads back statuswords, positions and forces. The exchange runs on the
//! motor thread through the [`FramePump`], and completes in one poll
//! (no allocation, lock another thread holds, timer or log on any path).
//! Targets never move faster than the velocity limit; a drive that is not
//! enabled is given its own position as target, so enabling it never
//! jumps. A short working counter, a frame lost, a drive not enabled or a
//! device out of OP makes `read` report a fault: the core holds while the
//! driver walks the drives back to *operation enabled* (fault reset on a
//! rising edge) and reads turn healthy again, without a restart.

use core::pin::pin;
use core::task::{Context, Poll, Waker};
use std::sync::Arc;
use std::sync::atomic::Ordering::Relaxed;
use std::time::Duration;

use ethercrab::std::ethercat_now;
use ethercrab::subdevice_group::Op;
use ethercrab::{MainDevice, MainDeviceConfig, PduStorage, SubDeviceGroup, SubDeviceState, Timeouts};
use rt_core::driver::{
    ActuatorCommand, ActuatorLimits, BusState, DriverHealth, DriverKind, MAX_ACTUATORS, PlateDriver,
    PlateState, ReadError, WriteError, apply_limits,
};
use rt_core::motion::{Rig, RigParams};

use crate::cia402_axis::{Cia402Axis, PowerState};
use crate::frame_pump::FramePump;
use crate::params::EthercatParams;
use crate::start_error::StartError;
use crate::wire::Wire;

/// Output image: controlword u16, target i32, velocity offset i32, torque
/// offset i16, mode i8 (0x1600); input image: statusword u16, actual i32,
/// torque actual i16, mode display i8 (0x1A00).
pub const OUTPUT_BYTES: usize = 13;
pub const INPUT_BYTES: usize = 9;
/// Cyclic synchronous position (0x6060).
const MODE_CSP: u8 = 8;
/// LRW working counter per SubDevice: 1 for inputs read, 2 for outputs.
const WKC_PER_DRIVE: u16 = 3;

const FRAMES: usize = 16;
type Storage = PduStorage<FRAMES, { PduStorage::element_size(1100) }>;
const PDI_BYTES: usize = MAX_ACTUATORS * (OUTPUT_BYTES + INPUT_BYTES);
type Group = SubDeviceGroup<MAX_ACTUATORS, PDI_BYTES, ethercrab::DefaultLock, Op>;

pub struct EthercatDriver<W: Wire> {
    maindevice: MainDevice<'static>,
    group: Group,
    pump: Arc<FramePump<W>>,
    rig: Rig,
    limits: ActuatorLimits,
    params: EthercatParams,
    tick_s: f64,
    cycle_s: f64,
    axes: [Cia402Axis; MAX_ACTUATORS],
    statusword: [u16; MAX_ACTUATORS],
    /// The accepted command (limited); home while holding.
    command: ActuatorCommand,
    /// Position targets sent (m).
    target: [f64; MAX_ACTUATORS],
    actual: [f64; MAX_ACTUATORS],
    speed: [f64; MAX_ACTUATORS],
    force: [f64; MAX_ACTUATORS],
    tick: u64,
    clamped: u64,
    rejected: u64,
    holding: bool,
    /// The last exchange came back whole with every device in OP.
    link_ok: bool,
    health: DriverHealth,
}

impl<W: Wire> core::fmt::Debug for EthercatDriver<W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("EthercatDriver")
            .field("params", &self.params)
            .field("health", &self.health)
            .field("pump", &self.pump)
            .finish_non_exhaustive()
    }
}

fn counts(metres: f64, per_metre: f64) -> i32 {
    // `as` saturates; NaN cannot reach here (commands are checked).
    (metres * per_metre).round() as i32
}

fn per_mille(force: f64, rated: f64) -> i16 {
    (force / rated * 1000.0).round() as i16
}

fn bus_state(s: SubDeviceState) -> BusState {
    match s {
        SubDeviceState::Op => BusState::Op,
        SubDeviceState::SafeOp => BusState::SafeOp,
        SubDeviceState::PreOp | SubDeviceState::Bootstrap => BusState::PreOp,
        SubDeviceState::Init => BusState::Init,
        _ => BusState::Fault,
    }
}

impl<W: Wire> EthercatDriver<W> {
    /// Scan the bus over `wire`, check every SubDevice against
    /// `params.expected`, map and configure the drives (CSP, following
    /// error window), bring the bus to OP and enable every drive.
    /// Allocates (once); call before the motor thread starts.
    pub fn start(wire: W, params: EthercatParams, rig: RigParams) -> Result<Self, StartError> {
        params.validate().map_err(StartError::Params)?;
        let rig = Rig::new(rig).map_err(|_| StartError::RigCount { rig: rig.count, drives: params.count })?;
        if rig.count() != params.count {
            return Err(StartError::RigCount { rig: rig.count(), drives: params.count });
        }
        // The PDU storage lives as long as the process (ethercrab borrows it
        // for 'static); one per driver started.
        let storage: &'static Storage = Box::leak(Box::new(Storage::new()));
        let (tx, rx, pdu_loop) =
            storage.try_split().map_err(|()| StartError::Bus(ethercrab::error::Error::Internal))?;
        let pump = FramePump::start(tx, rx, wire);
        let maindevice = MainDevice::new(
            pdu_loop,
            Timeouts { pdu: Duration::from_millis(params.startup_pdu_timeout_ms), ..Timeouts::default() },
            MainDeviceConfig { dc_static_sync_iterations: 0, ..MainDeviceConfig::default() },
        );
        let group = futures_lite::future::block_on(bring_up(&maindevice, &params))?;
        let limits = ActuatorLimits::from_rig(&rig);
        let mut driver = Self {
            maindevice,
            group,
            pump,
            rig,
            limits,
            tick_s: 1.0 / params.tick_hz,
            cycle_s: 1.0 / params.cycle_hz(),
            params,
            axes: [Cia402Axis::default(); MAX_ACTUATORS],
            statusword: [0; MAX_ACTUATORS],
            command: ActuatorCommand::HOME,
            target: [0.0; MAX_ACTUATORS],
            actual: [0.0; MAX_ACTUATORS],
            speed: [0.0; MAX_ACTUATORS],
            force: [0.0; MAX_ACTUATORS],
            tick: 0,
            clamped: 0,
            rejected: 0,
            holding: false,
            link_ok: false,
            health: DriverHealth {
                kind: DriverKind::Ethercat,
                state: BusState::Op,
                ..DriverHealth::SIMULATED
            },
        };
        for _ in 0..params.enable_cycles {
            driver.exchange();
            if driver.all_enabled() && driver.link_ok {
                // Start from rest: speeds estimated across the enabling
                // cycles are not motion.
                driver.speed = [0.0; MAX_ACTUATORS];
                return Ok(driver);
            }
        }
        let position = (0..driver.params.count).find(|&i| !driver.enabled(i)).unwrap_or(0);
        Err(StartError::Enable { position, statusword: driver.statusword[position] })
    }

    /// Run `f` on the wire (a simulated chain: inject faults, read the
    /// plant). `None` if the wire is in use, which only an exchange on
    /// another thread could cause.
    pub fn with_wire<R>(&self, f: impl FnOnce(&mut W) -> R) -> Option<R> {
        self.pump.with_wire(f)
    }

    /// Frames carried, lost, refused by ethercrab.
    pub fn wire_counters(&self) -> (u64, u64, u64) {
        let c = &self.pump.counters;
        (c.frames.load(Relaxed), c.lost.load(Relaxed), c.bad.load(Relaxed))
    }

    fn enabled(&self, i: usize) -> bool {
        PowerState::from_statusword(self.statusword[i]) == PowerState::OperationEnabled
    }

    fn all_enabled(&self) -> bool {
        (0..self.params.count).all(|i| self.enabled(i))
    }

    /// One process-data exchange: outputs out, inputs in.
    fn exchange(&mut self) {
        let p = &self.params;
        for (i, sd) in self.group.iter(&self.maindevice).enumerate().take(p.count) {
            let controlword = self.axes[i].controlword(self.statusword[i]);
            let live = self.link_ok && self.enabled(i);
            let (speed, force) = if live {
                let step = self.limits.velocity[i] * self.cycle_s;
                let want = self.command.position[i] - self.target[i];
                let moved = want.clamp(-step, step);
                if moved != want && !self.holding {
                    self.clamped += 1;
                }
                self.target[i] += moved;
                (self.command.velocity[i], self.command.force[i])
            } else {
                // Enabling takes the drive where it stands.
                self.target[i] = self.actual[i];
                (0.0, 0.0)
            };
            let mut out = sd.outputs_raw_mut();
            if let Some(o) = out.get_mut(..OUTPUT_BYTES) {
                o[0..2].copy_from_slice(&controlword.to_le_bytes());
                o[2..6].copy_from_slice(&counts(self.target[i], p.counts_per_metre).to_le_bytes());
                o[6..10].copy_from_slice(&counts(speed, p.counts_per_metre).to_le_bytes());
                o[10..12].copy_from_slice(&per_mille(force, p.rated_force_n).to_le_bytes());
                o[12] = MODE_CSP;
            }
        }
        let expected = WKC_PER_DRIVE * p.count as u16;
        let exchanged = pin!(self.group.tx_rx(&self.maindevice));
        let outcome = exchanged.poll(&mut Context::from_waker(Waker::noop()));
        self.link_ok = match outcome {
            Poll::Ready(Ok(r)) => {
                let lowest = r.subdevice_states.iter().map(|s| bus_state(*s)).min();
                self.health.state = match lowest {
                    _ if r.working_counter != expected => BusState::Fault,
                    Some(s) => s,
                    None => BusState::Fault,
                };
                r.working_counter == expected && self.health.state == BusState::Op
            }
            // Not answered in the poll (a wire that answers later), or
            // malformed: either way the frame is lost.
            Poll::Ready(Err(_)) | Poll::Pending => {
                self.health.state = BusState::Fault;
                false
            }
        };
        self.health.bad_frames = self.pump.counters.bad.load(Relaxed);
        if !self.link_ok {
            self.health.lost_frames += 1;
            return;
        }
        for (i, sd) in self.group.iter(&self.maindevice).enumerate().take(p.count) {
            let inputs = sd.inputs_raw();
            let Some(b) = inputs.get(..INPUT_BYTES) else { continue };
            self.statusword[i] = u16::from_le_bytes([b[0], b[1]]);
            self.axes[i].observe(self.statusword[i]);
            let actual = f64::from(i32::from_le_bytes([b[2], b[3], b[4], b[5]])) / p.counts_per_metre;
            self.speed[i] = (actual - self.actual[i]) / self.cycle_s;
            self.actual[i] = actual;
            self.force[i] = f64::from(i16::from_le_bytes([b[6], b[7]])) / 1000.0 * p.rated_force_n;
        }
        for i in 0..p.count {
            self.health.faults[i] = self.axes[i].faults;
        }
        if !self.all_enabled() {
            self.health.state = BusState::Fault;
        }
    }
}

async fn bring_up(md: &MainDevice<'static>, p: &EthercatParams) -> Result<Group, StartError> {
    let group =
        md.init_single_group::<MAX_ACTUATORS, PDI_BYTES>(ethercat_now).await.map_err(StartError::Bus)?;
    for (position, sd) in group.iter(md).enumerate() {
        let id = sd.identity();
        let fits = p.expected[..p.count]
            .get(position)
            .is_some_and(|e| (e.vendor, e.product) == (id.vendor_id, id.product_id));
        if !fits {
            return Err(StartError::Unexpected { position, vendor: id.vendor_id, product: id.product_id });
        }
    }
    if group.len() < p.count {
        return Err(StartError::Missing { position: group.len(), expected: p.expected[group.len()] });
    }
    let window = (p.following_error_m * p.counts_per_metre).round() as u32;
    for (position, sd) in group.iter(md).enumerate() {
        let sdo = |index| move |error| StartError::Sdo { position, index, error };
        sd.sdo_write(0x6060, 0, MODE_CSP as i8).await.map_err(sdo(0x6060))?;
        sd.sdo_write(0x6065, 0, window).await.map_err(sdo(0x6065))?;
    }
    let group = group.into_op(md).await.map_err(StartError::Bus)?;
    for (position, sd) in group.iter(md).enumerate() {
        let io = sd.io_raw();
        let (inputs, outputs) = (io.inputs().len(), io.outputs().len());
        if (inputs, outputs) != (INPUT_BYTES, OUTPUT_BYTES) {
            return Err(StartError::ProcessImage { position, inputs, outputs });
        }
    }
    Ok(group)
}

impl<W: Wire> PlateDriver for EthercatDriver<W> {
    fn limits(&self) -> ActuatorLimits {
        self.limits
    }

    fn tick_period(&self) -> f64 {
        self.tick_s
    }

    fn read(&mut self, state: &mut PlateState) -> Result<(), ReadError> {
        state.tick = self.tick;
        state.time = self.tick as f64 * self.tick_s;
        state.actuator_position = self.actual;
        state.actuator_force = self.force;
        state.pose = self.rig.pose_from_actuators(&self.actual);
        state.velocity = self.rig.twist_from_actuators(&state.pose, &self.speed);
        state.clamped = self.clamped;
        state.rejected = self.rejected;
        state.holding = self.holding;
        if self.link_ok && self.all_enabled() { Ok(()) } else { Err(ReadError::Fault) }
    }

    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError> {
        match apply_limits(&self.limits, command, &mut self.command) {
            Ok(c) => {
                self.clamped += c as u64;
                self.holding = false;
                Ok(())
            }
            Err(e) => {
                self.rejected += 1;
                Err(e)
            }
        }
    }

    fn hold(&mut self) {
        self.command = ActuatorCommand::HOME;
        self.holding = true;
    }

    fn advance(&mut self) {
        self.tick += 1;
        if self.tick.is_multiple_of(u64::from(self.params.cycle_divisor)) {
            self.exchange();
        }
    }

    fn health(&self) -> DriverHealth {
        self.health
    }
}
