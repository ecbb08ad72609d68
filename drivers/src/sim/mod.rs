//! The embedded physics simulator: the default [`PlateDriver`].
//!
//! Fixed step (one tick = `substeps` substeps), deterministic (no wall
//! clock, no hash maps, seeded noise from [`crate::rng::SplitMix64`]).
//! Parts do not push the plate back (plate mass ≫ part mass). Everything is
//! allocated in [`Simulator::new`]; `advance`, `read` and `write` allocate
//! nothing.

mod config;
mod contact;
mod disc_friction;
mod disc_lanes;
mod friction;
mod ground_truth;
mod lanes;
mod part;
mod part_capacity;
mod plate;
mod point_lanes;
mod polygon_limit;
mod pool;
mod truth;

use core::fmt;

use multiversion::multiversion;

use upm_hardware::{
    ActuatorCommand, ActuatorLimits, MAX_ACTUATORS, PlateDriver, PlateState, ReadError, WriteError,
    apply_limits,
};
use upm_motion::{Pose, Rig, RigError, Twist};

pub use config::{ActuatorKind, ActuatorModel, SimConfig, SimConfigError};
pub use part::{BodyShape, PartError, PartSpec, PartState};
pub use part_capacity::{MAX_CONTACTS, MAX_POLYGON_VERTICES};
pub use truth::{
    FRICTION_MAP_TERMS, FrictionMap, MAX_FRICTION_SCALE, MIN_FRICTION_SCALE, PlateTruth, TruthError,
    friction_scale_ok,
};

use contact::Broadphase;
use friction::Coulomb;
use ground_truth::GroundTruthSlot;
use lanes::{LaneKind, Lanes, W};
use part::Body;
use plate::{Plate, Target};
use point_lanes::PlateNow;

use crate::rng::SplitMix64;

/// Why a simulator could not be built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SimError {
    Config(SimConfigError),
    Rig(RigError),
    Part { index: usize, error: PartError },
    TooManyParts { given: usize, capacity: usize },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Config(e) => write!(f, "{e}"),
            Self::Rig(e) => write!(f, "{e}"),
            Self::Part { index, error } => write!(f, "parts[{index}]: {error:?}"),
            Self::TooManyParts { given, capacity } => write!(f, "parts: {given} given, capacity {capacity}"),
        }
    }
}

impl core::error::Error for SimError {}

/// Something that runs around the simulator and steps with it, on its
/// parts (a feed cell, `crate::feed`): called after every tick, where the
/// simulator steps, so it must not allocate.
pub trait Cell: fmt::Debug + Send + Sync {
    fn step(&mut self, sim: &mut Simulator);
    /// The id part `i` carries on the wire (its ground truth).
    fn id_of(&self, i: usize) -> u32;
    fn boxed_clone(&self) -> Box<dyn Cell>;
    fn as_any(&self) -> &dyn core::any::Any;
    fn as_any_mut(&mut self) -> &mut dyn core::any::Any;
}

impl Clone for Box<dyn Cell> {
    fn clone(&self) -> Self {
        self.boxed_clone()
    }
}

/// Most parts one simulator holds (pair indices are u16).
pub const MAX_PARTS: usize = 1024;

/// Event counters since construction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SimCounters {
    pub ticks: u64,
    pub clamped: u64,
    pub rejected: u64,
    /// Substeps with an actuator force at its limit (second-order model).
    pub force_saturated: u64,
    pub fence_hits: u64,
    pub collisions: u64,
}

#[derive(Debug, Clone)]
pub struct Simulator {
    cfg: SimConfig,
    /// The rig as the controller knows it (limits, `rig()`).
    rig: Rig,
    /// The rig as it is ([`PlateTruth::plant_rig`]): what the commands move.
    plant: Rig,
    /// 1 + each sensor's scale error.
    sensor_gain: [f64; MAX_ACTUATORS],
    /// The truth's rig differs from the model's: `read` reports what the
    /// sensors say, through the model.
    plant_differs: bool,
    /// Each part's friction scale (its class's, in the truth).
    part_friction: Vec<f64>,
    /// Some part's friction differs from the nominal μ (a map or a scale).
    friction_uneven: bool,
    limits: ActuatorLimits,
    mu: Coulomb,
    h: f64,
    plate: Plate,
    command: ActuatorCommand,
    target: Target,
    holding: bool,
    bodies: Vec<Body>,
    /// Every part's state as last copied out of `lanes` (by `parts()`).
    parts: Vec<PartState>,
    /// Every part's state, four lanes at a time.
    lanes: Lanes,
    /// Indices of the extended parts other than discs (friction summed over
    /// contact points, one part at a time).
    patches: Vec<usize>,
    /// Each part: off the plate ([`Simulator::park`]).
    parked: Vec<bool>,
    /// What runs around this simulator, if anything (a feed cell).
    cell: Option<Box<dyn Cell>>,
    broadphase: Broadphase,
    rng: SplitMix64,
    counters: SimCounters,
    ground_truth: GroundTruthSlot,
}

impl Simulator {
    pub fn new(cfg: SimConfig, parts: &[PartSpec]) -> Result<Self, SimError> {
        cfg.validate().map_err(SimError::Config)?;
        let rig = Rig::new(cfg.rig).map_err(SimError::Rig)?;
        let plant = Rig::new(cfg.truth.plant_rig(&cfg.rig)).map_err(SimError::Rig)?;
        let sensor_gain = cfg.truth.sensor_scale_error.map(|e| 1.0 + e);
        let plant_differs = plant.params() != rig.params() || sensor_gain.iter().any(|&g| g != 1.0);
        if parts.len() > MAX_PARTS {
            return Err(SimError::TooManyParts { given: parts.len(), capacity: MAX_PARTS });
        }
        let mut bodies = Vec::with_capacity(parts.len());
        let mut states = Vec::with_capacity(parts.len());
        for (index, spec) in parts.iter().enumerate() {
            let (body, _) = Body::new(spec).map_err(|error| SimError::Part { index, error })?;
            bodies.push(body);
            states.push(PartState { position: spec.position, angle: spec.angle, ..PartState::default() });
        }
        if bodies.iter().any(|b| b.disc) {
            // Build the disc friction table now, not on the first tick.
            disc_friction::table();
        }
        let limits = ActuatorLimits::from_rig(&rig);
        let kind: Vec<LaneKind> = bodies
            .iter()
            .map(|b| match (b.extended, b.disc) {
                (false, _) => LaneKind::Point,
                (true, true) => LaneKind::Disc,
                (true, false) => LaneKind::Patch,
            })
            .collect();
        let patches = (0..bodies.len()).filter(|&i| kind[i] == LaneKind::Patch).collect();
        let fence_limits: Vec<[f64; 2]> =
            bodies.iter().map(|b| contact::fence_limits(b, cfg.plate_half_extent)).collect();
        let radius: Vec<f64> = bodies.iter().map(|b| b.radius).collect();
        let mut sim = Self {
            lanes: Lanes::new(&states, &kind, &fence_limits, &radius),
            patches,
            parked: vec![false; parts.len()],
            cell: None,
            mu: Coulomb { kinetic: cfg.mu_kinetic * cfg.gravity, stat: cfg.mu_static * cfg.gravity },
            h: 1.0 / cfg.tick_hz,
            plate: Plate::default(),
            command: ActuatorCommand::HOME,
            target: Target::default(),
            holding: false,
            broadphase: Broadphase::with_capacity(parts.len()),
            rng: SplitMix64::new(cfg.seed),
            counters: SimCounters::default(),
            ground_truth: GroundTruthSlot::default(),
            part_friction: vec![1.0; bodies.len()],
            friction_uneven: !cfg.truth.friction_map.is_flat(),
            plant,
            sensor_gain,
            plant_differs,
            bodies,
            parts: states,
            limits,
            rig,
            cfg,
        };
        sim.update_friction();
        Ok(sim)
    }

    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// Every part's state. Takes `&mut self` because the state is copied out
    /// of the lanes here, on demand, rather than on every tick;
    /// [`Simulator::part`] reads one part through `&self`.
    pub fn parts(&mut self) -> &[PartState] {
        self.lanes.mirror(&mut self.parts);
        &self.parts
    }

    /// State of part `i` (None if out of range).
    pub fn part(&self, i: usize) -> Option<PartState> {
        self.lanes.lane.get(i).map(|&l| self.lanes.load(l))
    }

    pub fn part_count(&self) -> usize {
        self.parts.len()
    }

    /// Moment of inertia of part `i` about its center (0 for points).
    pub fn part_inertia(&self, i: usize) -> Option<f64> {
        self.bodies.get(i).map(|b| b.mass * b.rho2)
    }

    /// Overwrite a part's state (e.g. to restart it at rest). Returns false
    /// if `i` is out of range or the state is not finite.
    pub fn set_part(&mut self, i: usize, state: PartState) -> bool {
        let finite = state.position.iter().chain(&state.velocity).all(|v| v.is_finite())
            && state.angle.is_finite()
            && state.angular_velocity.is_finite();
        match self.parts.get_mut(i) {
            Some(p) if finite => {
                *p = state;
                self.lanes.store(self.lanes.lane[i], &state);
                self.broadphase.valid = false;
                true
            }
            _ => false,
        }
    }

    /// Set part `i`'s friction scale (μ of its material over the nominal,
    /// part of the truth). Returns false if `i` is out of range or the
    /// scale outside [`MIN_FRICTION_SCALE`]..=[`MAX_FRICTION_SCALE`].
    pub fn set_part_friction(&mut self, i: usize, scale: f64) -> bool {
        match self.part_friction.get_mut(i) {
            Some(s) if friction_scale_ok(scale) => {
                *s = scale;
                self.friction_uneven |= scale != 1.0;
                self.update_friction();
                true
            }
            _ => false,
        }
    }

    /// Every live lane's μ scale: its part's, times the map where it is.
    fn update_friction(&mut self) {
        let (half, map) = (self.cfg.plate_half_extent, self.cfg.truth.friction_map);
        let (px, py) = (self.plate.pose.x, self.plate.pose.y);
        for (i, &l) in self.lanes.lane.iter().enumerate() {
            let (g, k) = (&mut self.lanes.groups[l / W], l % W);
            g.mu_scale[k] = self.part_friction[i] * map.scale_at(half, g.x[k] - px, g.y[k] - py);
        }
    }

    /// The true plate pose (the simulator's own; a controller sees the
    /// sensors, through `read`).
    pub fn plate_pose(&self) -> Pose {
        self.plate.pose
    }

    pub fn plate_velocity(&self) -> Twist {
        self.plate.vel
    }

    pub fn counters(&self) -> SimCounters {
        SimCounters { force_saturated: self.plate.saturated, ..self.counters }
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.counters.ticks as f64 * self.h
    }

    /// One tick: `substeps` × (plate acceleration → friction on every part →
    /// plate and parts integrate), then contacts and fence.
    pub fn step(&mut self) {
        step_tick(self);
        if let Some(mut cell) = self.cell.take() {
            cell.step(self);
            self.cell = Some(cell);
        }
        self.publish_ground_truth_if_due();
    }

    /// What runs around this simulator, if anything.
    pub fn cell(&self) -> Option<&dyn Cell> {
        self.cell.as_deref()
    }

    pub fn cell_mut(&mut self) -> Option<&mut (dyn Cell + 'static)> {
        self.cell.as_deref_mut()
    }

    /// Build-time only (it allocates).
    pub fn attach_cell(&mut self, cell: Box<dyn Cell>) {
        self.cell = Some(cell);
    }

    #[inline(always)]
    fn step_body(&mut self) {
        let n = self.cfg.substeps;
        let s = self.h / n as f64;
        if self.friction_uneven {
            // Parts move micrometres in a tick: the map is read once per tick.
            self.update_friction();
        }
        let mut force_sum = [0.0; MAX_ACTUATORS];
        for sub in 0..n {
            self.plate.plan_substep(
                self.cfg.actuator_model(),
                &self.plant,
                &self.target,
                s,
                n - sub,
                sub as f64 / n as f64,
                self.cfg.force_noise,
                &mut self.rng,
            );
            let (pose, vel, acc) = (self.plate.pose, self.plate.vel, self.plate.acc);
            let now = PlateNow { x: pose.x, y: pose.y, vel, acc };
            let (points, rest) = self.lanes.groups.split_at_mut(self.lanes.point_groups);
            point_lanes::step_points(&now, points, s, self.mu);
            if self.lanes.disc_groups > 0 {
                let first = self.lanes.point_groups * W;
                disc_lanes::step_discs(
                    &now,
                    &mut rest[..self.lanes.disc_groups],
                    &self.lanes.part_of[first..],
                    &self.bodies,
                    s,
                    self.mu,
                    disc_friction::table(),
                );
            }
            for &i in &self.patches {
                if self.parked[i] {
                    continue;
                }
                let l = self.lanes.lane[i];
                let (g, k) = (&mut self.lanes.groups[l / W], l % W);
                let (a, xi) = disc_lanes::relative_twist(&now, [g.x[k], g.y[k]], [g.vx[k], g.vy[k]], g.w[k]);
                let mu = self.mu.scaled(g.mu_scale[k]);
                disc_lanes::step_lane(g, k, &self.bodies[i], a, xi, s, mu);
            }
            for (a, f) in force_sum.iter_mut().zip(&self.plate.force) {
                *a += f;
            }
            self.plate.integrate(s);
        }
        // A drive reports the force it applied over the tick; one substep's
        // is that force itself, bit for bit.
        self.plate.tick_force = if n == 1 { self.plate.force } else { force_sum.map(|f| f / n as f64) };
        // The reference has reached this tick's setpoint.
        self.target.advance();
        if self.cfg.actuator == ActuatorKind::Ideal {
            // Land exactly on the command (keeps closed motions exactly closed).
            self.plate.set_pose(self.target.pose);
            self.plate.vel = self.target.vel;
        }
        if self.cfg.collisions && self.parts.len() > 1 {
            self.counters.collisions += contact::collide(
                &mut self.broadphase,
                &self.bodies,
                &mut self.lanes,
                self.cfg.part_restitution,
            );
        }
        if self.cfg.fence {
            self.counters.fence_hits += contact::fence_groups(
                &mut self.lanes.groups,
                &self.plate.pose,
                self.plate.sc,
                &self.plate.vel,
                self.cfg.fence_restitution,
            );
        }
        self.counters.ticks += 1;
    }
}

/// [`Simulator::step`], with an AVX2 clone where the CPU has it (nothing is
/// fused, so both clones give the same bits).
#[multiversion(targets("x86_64+avx2"))]
fn step_tick(sim: &mut Simulator) {
    sim.step_body();
}

/// [`PlateDriver::write`], with an AVX2 clone like [`step_tick`].
#[multiversion(targets("x86_64+avx2"))]
fn write_command(sim: &mut Simulator, command: &ActuatorCommand) -> Result<(), WriteError> {
    match apply_limits(&sim.limits, command, &mut sim.command) {
        Ok(clamped) => {
            sim.counters.clamped += clamped as u64;
            // The servos drive the sensor readings to the command.
            let mut sensed = sim.command;
            for i in 0..MAX_ACTUATORS {
                sensed.position[i] /= sim.sensor_gain[i];
                sensed.velocity[i] /= sim.sensor_gain[i];
            }
            sim.target.accept(sim.cfg.actuator_model(), &sim.plant, &sensed);
            sim.holding = false;
            Ok(())
        }
        Err(e) => {
            sim.counters.rejected += 1;
            Err(e)
        }
    }
}

impl PlateDriver for Simulator {
    fn limits(&self) -> ActuatorLimits {
        self.limits
    }

    fn tick_period(&self) -> f64 {
        self.h
    }

    fn read(&mut self, state: &mut PlateState) -> Result<(), ReadError> {
        state.tick = self.counters.ticks;
        state.time = self.time();
        self.plant.actuator_positions_sc(&self.plate.pose, self.plate.sc, &mut state.actuator_position);
        if self.plant_differs {
            let mut rate = [0.0; MAX_ACTUATORS];
            self.plant.actuator_velocities_sc(self.plate.sc, &self.plate.vel, &mut rate);
            for i in 0..MAX_ACTUATORS {
                state.actuator_position[i] *= self.sensor_gain[i];
                rate[i] *= self.sensor_gain[i];
            }
            state.pose = self.rig.pose_from_actuators(&state.actuator_position);
            state.velocity = self.rig.twist_from_actuators(&state.pose, &rate);
        } else {
            state.pose = self.plate.pose;
            state.velocity = self.plate.vel;
        }
        state.actuator_force = self.plate.tick_force;
        state.clamped = self.counters.clamped;
        state.rejected = self.counters.rejected;
        state.holding = self.holding;
        Ok(())
    }

    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError> {
        write_command(self, command)
    }

    fn hold(&mut self) {
        self.command = ActuatorCommand::HOME;
        self.target.accept(self.cfg.actuator_model(), &self.plant, &ActuatorCommand::HOME);
        self.holding = true;
    }

    fn advance(&mut self) {
        self.step();
    }
}
