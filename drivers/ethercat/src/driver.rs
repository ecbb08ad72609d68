//! [`EthercatDriver`]: one CiA 402 drive per actuator in cyclic synchronous
//! position mode, behind the same [`PlateDriver`] as the simulator.
//!
//! Every `cycle_divisor` ticks, `advance` sends the targets (position,
//! velocity and force feed-forward) and the controlwords in one LRW and
//! reads back statuswords, positions and forces. The exchange runs on the
//! motor thread through the [`FramePump`], and completes in one poll
//! (no allocation, lock another thread holds, timer or log on any path).
//! Targets never move faster than the velocity limit, nor further from
//! the drive's actual position than three quarters of its following-error
//! window (a step the plant cannot follow is chased, not faulted); a drive
//! that is not enabled is given its own position as target, so enabling
//! it never jumps. A short working counter, a frame lost, a drive not enabled or a
//! device out of OP makes `read` report a fault: the core holds while the
//! driver walks the drives back to *operation enabled* (fault reset on a
//! rising edge) and reads turn healthy again, without a restart.
//!
//! When every drive offers distributed clocks, they latch their targets
//! on SYNC0 at the bus cycle; each exchange also carries the reference
//! drive's time to the others, and the driver asks the motor loop
//! ([`PlateDriver::clock_correction_ns`]) to shift its phase so that the
//! frame keeps reaching the reference a quarter cycle after SYNC0: the
//! motor loop follows the bus's clock, whatever the two crystals drift.

use core::pin::pin;
use core::task::{Context, Poll, Waker};
use std::sync::Arc;
use std::sync::atomic::Ordering::Relaxed;
use std::time::Duration;

use ethercrab::std::ethercat_now;
use ethercrab::subdevice_group::{DcConfiguration, HasDc, NoDc, Op};
use ethercrab::{
    DcSync, MainDevice, MainDeviceConfig, PduStorage, SubDeviceGroup, SubDevicePdi, SubDeviceRef,
    SubDeviceState, Timeouts,
};
use upm_hardware::{
    ActuatorCommand, ActuatorLimits, BusState, CommandGate, DriverHealth, DriverKind, MAX_ACTUATORS,
    PlateDriver, PlateState, ReadError, WriteError,
};
use upm_motion::{Rig, RigParams};

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
/// The PDO mapping written at start-up, entries `index << 16 | subindex
/// << 8 | bits`: RxPDO 0x1600 and TxPDO 0x1A00 as laid out above.
const RX_MAPPING: [u32; 5] = [0x6040_0010, 0x607A_0020, 0x60B1_0020, 0x60B2_0010, 0x6060_0008];
const TX_MAPPING: [u32; 4] = [0x6041_0010, 0x6064_0020, 0x6077_0010, 0x6061_0008];
/// Cyclic synchronous position (0x6060).
const MODE_CSP: u8 = 8;
/// LRW working counter per SubDevice: 1 for inputs read, 2 for outputs.
const WKC_PER_DRIVE: u16 = 3;

const FRAMES: usize = 16;
type Storage = PduStorage<FRAMES, { PduStorage::element_size(1100) }>;
const PDI_BYTES: usize = MAX_ACTUATORS * (OUTPUT_BYTES + INPUT_BYTES);
type Group<DC> = SubDeviceGroup<MAX_ACTUATORS, PDI_BYTES, ethercrab::DefaultLock, Op, DC>;
type Drive<'g> = SubDeviceRef<'g, SubDevicePdi<'g, PDI_BYTES, ethercrab::DefaultLock>>;
/// Where in the bus cycle the frame should reach the reference drive: a
/// quarter cycle after SYNC0 leaves three quarters for a late wake-up
/// before the drives latch the next SYNC0.
const SYNC0_PHASE: f64 = 0.25;
/// Share of the phase error corrected per bus cycle (a proportional loop:
/// a steady drift d per cycle leaves an error of d / gain).
const PHASE_GAIN: f64 = 0.125;

/// Targets stay within this share of the following-error window of the
/// drive's actual position.
const FOLLOWING_GUARD: f64 = 0.75;

/// SYNC0 starts this long after it is configured (ethercrab's examples'
/// figure: the bus reaches OP well within it).
const SYNC0_START_DELAY: Duration = Duration::from_millis(100);

/// The bus in OP: drives on SYNC0 (distributed clocks), or free running.
enum Bus {
    Synced(Group<HasDc>),
    Free(Group<NoDc>),
}

impl Bus {
    fn each<'a>(&'a self, md: &'a MainDevice<'a>, mut f: impl FnMut(usize, Drive<'a>)) {
        match self {
            Self::Synced(g) => g.iter(md).enumerate().for_each(|(i, sd)| f(i, sd)),
            Self::Free(g) => g.iter(md).enumerate().for_each(|(i, sd)| f(i, sd)),
        }
    }

    /// One exchange, polled once.
    fn exchange<'a>(&'a self, md: &'a MainDevice<'a>) -> Exchanged {
        let mut cx = Context::from_waker(Waker::noop());
        let lowest = |states: &[SubDeviceState]| states.iter().map(|s| bus_state(*s)).min();
        match self {
            Self::Synced(g) => match pin!(g.tx_rx_dc(md)).poll(&mut cx) {
                Poll::Ready(Ok(r)) => Exchanged::Back {
                    working_counter: r.working_counter,
                    lowest: lowest(&r.subdevice_states),
                    dc: Some(DcCycle {
                        system_time_ns: r.extra.dc_system_time,
                        after_sync0_ns: r.extra.cycle_start_offset.as_nanos() as u64,
                    }),
                },
                Poll::Ready(Err(_)) => Exchanged::Failed,
                Poll::Pending => Exchanged::Pending,
            },
            Self::Free(g) => match pin!(g.tx_rx(md)).poll(&mut cx) {
                Poll::Ready(Ok(r)) => Exchanged::Back {
                    working_counter: r.working_counter,
                    lowest: lowest(&r.subdevice_states),
                    dc: None,
                },
                Poll::Ready(Err(_)) => Exchanged::Failed,
                Poll::Pending => Exchanged::Pending,
            },
        }
    }
}

/// How one exchange ended.
enum Exchanged {
    /// The frame came back (its working counter says how whole), with the
    /// lowest state of any device and, with distributed clocks, the
    /// reference's time and how far after SYNC0 the frame reached it.
    Back { working_counter: u16, lowest: Option<BusState>, dc: Option<DcCycle> },
    /// ethercrab refused it.
    Failed,
    /// Not complete within the poll: the frame pump failed to hand the
    /// frame back, and ethercrab's timer was reached (counted; never
    /// expected).
    Pending,
}

/// What the last exchange learnt of the distributed clocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DcCycle {
    /// The reference drive's system time (ns since 2000).
    pub system_time_ns: u64,
    /// How long after the last SYNC0 pulse the frame reached the reference.
    pub after_sync0_ns: u64,
}

pub struct EthercatDriver<W: Wire> {
    maindevice: MainDevice<'static>,
    bus: Bus,
    pump: Arc<FramePump<W>>,
    rig: Rig,
    limits: ActuatorLimits,
    params: EthercatParams,
    tick_s: f64,
    cycle_s: f64,
    axes: [Cia402Axis; MAX_ACTUATORS],
    statusword: [u16; MAX_ACTUATORS],
    /// The accepted command (limited); home while holding.
    gate: CommandGate,
    /// Position targets sent (m).
    target: [f64; MAX_ACTUATORS],
    actual: [f64; MAX_ACTUATORS],
    speed: [f64; MAX_ACTUATORS],
    force: [f64; MAX_ACTUATORS],
    tick: u64,
    /// The last exchange came back whole with every device in OP.
    link_ok: bool,
    /// Distributed clocks, as the last exchange saw them.
    dc: Option<DcCycle>,
    /// Phase correction for the motor loop, not yet taken.
    correction_ns: i64,
    /// Exchanges that did not complete within their poll.
    unfinished: u64,
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
        let bus = futures_lite::future::block_on(bring_up(&maindevice, &params))?;
        let limits = ActuatorLimits::from_rig(&rig);
        let mut driver = Self {
            maindevice,
            bus,
            pump,
            rig,
            limits,
            tick_s: 1.0 / params.tick_hz,
            cycle_s: 1.0 / params.cycle_hz(),
            params,
            axes: [Cia402Axis::default(); MAX_ACTUATORS],
            statusword: [0; MAX_ACTUATORS],
            gate: CommandGate::default(),
            target: [0.0; MAX_ACTUATORS],
            actual: [0.0; MAX_ACTUATORS],
            speed: [0.0; MAX_ACTUATORS],
            force: [0.0; MAX_ACTUATORS],
            tick: 0,
            link_ok: false,
            dc: None,
            correction_ns: 0,
            unfinished: 0,
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

    /// Exchanges that did not complete within their poll (each reached
    /// ethercrab's timer: a syscall and maybe a lock on the motor thread).
    /// Zero on every path the tests drive, garbage from the wire included.
    pub fn unfinished_exchanges(&self) -> u64 {
        self.unfinished
    }

    /// Distributed clocks as the last exchange saw them; `None` when the
    /// drives run free.
    pub fn distributed_clocks(&self) -> Option<DcCycle> {
        self.dc
    }

    /// The motor loop's shift that brings the frame back to
    /// [`SYNC0_PHASE`] of the cycle, at most a twentieth of a tick.
    fn phase_correction(&self, dc: DcCycle) -> i64 {
        let period = (self.cycle_s * 1e9).round() as i64;
        let target = (period as f64 * SYNC0_PHASE) as i64;
        let mut error = (dc.after_sync0_ns as i64 - target).rem_euclid(period.max(1));
        if error >= period / 2 {
            error -= period;
        }
        let most = (self.tick_s * 1e9 / 20.0) as i64;
        ((-(error as f64) * PHASE_GAIN) as i64).clamp(-most, most)
    }

    /// One process-data exchange: outputs out, inputs in.
    fn exchange(&mut self) {
        let p = self.params;
        let mut outputs = [[0u8; OUTPUT_BYTES]; MAX_ACTUATORS];
        for (i, o) in outputs.iter_mut().enumerate().take(p.count) {
            let controlword = self.axes[i].controlword(self.statusword[i]);
            let live = self.link_ok && self.enabled(i);
            let (speed, force) = if live {
                let step = self.limits.velocity[i] * self.cycle_s;
                let want = self.gate.command.position[i] - self.target[i];
                let moved = want.clamp(-step, step);
                // Never further from where the drive stands (its last
                // reading, a cycle on) than it may follow: a command the
                // plant cannot keep up with (a step) is chased, not turned
                // into a following-error fault.
                let reach = FOLLOWING_GUARD * p.following_error_m;
                let stands = self.actual[i] + self.speed[i] * self.cycle_s;
                let next = (self.target[i] + moved).clamp(stands - reach, stands + reach);
                if next != self.target[i] + want && !self.gate.holding {
                    self.gate.clamped += 1;
                }
                self.target[i] = next;
                (self.gate.command.velocity[i], self.gate.command.force[i])
            } else {
                // Enabling takes the drive where it stands.
                self.target[i] = self.actual[i];
                (0.0, 0.0)
            };
            o[0..2].copy_from_slice(&controlword.to_le_bytes());
            o[2..6].copy_from_slice(&counts(self.target[i], p.counts_per_metre).to_le_bytes());
            o[6..10].copy_from_slice(&counts(speed, p.counts_per_metre).to_le_bytes());
            o[10..12].copy_from_slice(&per_mille(force, p.rated_force_n).to_le_bytes());
            o[12] = MODE_CSP;
        }
        self.bus.each(&self.maindevice, |i, sd| {
            if let (Some(o), Some(src)) = (sd.outputs_raw_mut().get_mut(..OUTPUT_BYTES), outputs.get(i)) {
                o.copy_from_slice(src);
            }
        });
        let expected = WKC_PER_DRIVE * p.count as u16;
        // Not whole, refused, or not back within the poll: the frame is
        // lost.
        let outcome = self.bus.exchange(&self.maindevice);
        self.link_ok = match outcome {
            Exchanged::Back { working_counter, lowest, dc } => {
                self.health.state = match lowest {
                    _ if working_counter != expected => BusState::Fault,
                    Some(s) => s,
                    None => BusState::Fault,
                };
                let whole = working_counter == expected && self.health.state == BusState::Op;
                // A lost frame comes back with the reference's time zeroed:
                // neither a clock reading nor a reason to move the loop.
                if whole {
                    self.dc = dc;
                    if let Some(dc) = dc {
                        self.correction_ns = self.phase_correction(dc);
                    }
                    self.health.sync0_phase_ns = dc.map(|d| d.after_sync0_ns);
                }
                whole
            }
            Exchanged::Failed | Exchanged::Pending => {
                self.unfinished += u64::from(matches!(outcome, Exchanged::Pending));
                self.health.state = BusState::Fault;
                false
            }
        };
        self.health.bad_frames = self.pump.counters.bad.load(Relaxed);
        if !self.link_ok {
            self.health.lost_frames += 1;
            return;
        }
        let mut inputs = [[0u8; INPUT_BYTES]; MAX_ACTUATORS];
        let mut got = [false; MAX_ACTUATORS];
        self.bus.each(&self.maindevice, |i, sd| {
            if let (Some(b), Some(dst)) = (sd.inputs_raw().get(..INPUT_BYTES), inputs.get_mut(i)) {
                dst.copy_from_slice(b);
                got[i] = true;
            }
        });
        for i in (0..p.count).filter(|&i| got[i]) {
            let b = &inputs[i];
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

async fn bring_up(md: &MainDevice<'static>, p: &EthercatParams) -> Result<Bus, StartError> {
    let mut group =
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
        // The PDO mapping, whatever the drive's default: assignment off,
        // mapping emptied, entries, count, assignment back on.
        for (assign, pdo, entries) in [(0x1C12, 0x1600, &RX_MAPPING[..]), (0x1C13, 0x1A00, &TX_MAPPING[..])] {
            sd.sdo_write(assign, 0, 0u8).await.map_err(sdo(assign))?;
            sd.sdo_write(pdo, 0, 0u8).await.map_err(sdo(pdo))?;
            for (k, entry) in entries.iter().enumerate() {
                sd.sdo_write(pdo, k as u8 + 1, *entry).await.map_err(sdo(pdo))?;
            }
            sd.sdo_write(pdo, 0, entries.len() as u8).await.map_err(sdo(pdo))?;
            sd.sdo_write(assign, 1, pdo).await.map_err(sdo(assign))?;
            sd.sdo_write(assign, 0, 1u8).await.map_err(sdo(assign))?;
        }
        sd.sdo_write(0x6060, 0, MODE_CSP as i8).await.map_err(sdo(0x6060))?;
        sd.sdo_write(0x6065, 0, window).await.map_err(sdo(0x6065))?;
    }
    let bus = if p.distributed_clocks && group.iter(md).all(|sd| sd.dc_support().any()) {
        for mut sd in group.iter_mut(md) {
            sd.set_dc_sync(DcSync::Sync0);
        }
        let sync0 = DcConfiguration {
            start_delay: SYNC0_START_DELAY,
            sync0_period: Duration::from_secs_f64(1.0 / p.cycle_hz()),
            sync0_shift: Duration::ZERO,
        };
        let group = group.into_pre_op_pdi(md).await.map_err(StartError::Bus)?;
        let group = group.configure_dc_sync(md, sync0).await.map_err(StartError::Bus)?;
        let group = group.into_safe_op(md).await.map_err(StartError::Bus)?;
        Bus::Synced(group.into_op(md).await.map_err(StartError::Bus)?)
    } else {
        Bus::Free(group.into_op(md).await.map_err(StartError::Bus)?)
    };
    let mut image = Ok(());
    bus.each(md, |position, sd| {
        let io = sd.io_raw();
        let (inputs, outputs) = (io.inputs().len(), io.outputs().len());
        if image.is_ok() && (inputs, outputs) != (INPUT_BYTES, OUTPUT_BYTES) {
            image = Err(StartError::ProcessImage { position, inputs, outputs });
        }
    });
    image.map(|()| bus)
}

impl<W: Wire> Drop for EthercatDriver<W> {
    fn drop(&mut self) {
        // Lets the wire (a socket, a simulated chain) go with the driver.
        self.pump.release();
    }
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
        self.gate.report(state);
        if self.link_ok && self.all_enabled() { Ok(()) } else { Err(ReadError::Fault) }
    }

    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError> {
        self.gate.write(&self.limits, command)
    }

    fn hold(&mut self) {
        self.gate.hold();
    }

    fn advance(&mut self) {
        self.tick += 1;
        if self.tick.is_multiple_of(u64::from(self.params.cycle_divisor)) {
            self.exchange();
        }
    }

    fn clock_correction_ns(&mut self) -> i64 {
        core::mem::take(&mut self.correction_ns)
    }

    fn health(&self) -> DriverHealth {
        self.health
    }
}
