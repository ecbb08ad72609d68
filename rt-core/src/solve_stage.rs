//! The solver thread's work: validate each message, turn a force request
//! into a closed plate motion (or take a planner's explicit schedule),
//! check it against the actuator limits, and hand it to the motor
//! wait-free. Every buffer is sized at construction; handling a message
//! allocates nothing.

use core::fmt;
use core::sync::atomic::Ordering::Relaxed;
use std::sync::Arc;

use ipc_types::{
    CoreCommand, CoreCommandError, ExplicitSchedule, ExplicitScheduleError, ForceRequest, ForceRequestError,
    MAX_CURLS, MAX_PARTS, PartStates, PartStatesError, RejectReason, RejectedKind, Rejection, Schedule,
    ScheduleSlot, ValidationLimits,
};

use super::clock::Clock;
use super::handoff::MotionWriter;
use super::inbox::{Inbound, Inbox, InboxBuffers};
use super::params::CoreParams;
use super::samples::{SolverSample, StageOutputs};
use super::shared::CoreShared;
use upm_motion::PartFriction;
use upm_motion::{MAX_SLOTS, MotionError, PlateMotion, Rig, RigError, ScheduleEntry};
use upm_motion::{PartDynamics, PartMotion, fill_entries};
use upm_solver::{
    CurlConstraint, ForceConstraint, PartShape, Problem, Solution, SolveError, Solver, SolverCapacity,
};

// Every explicit schedule the protocol can carry fits the motion.
const _: () = assert!(MAX_SLOTS >= ipc_types::MAX_SLOTS);

/// Why part states were rejected (the newest accepted ones stay in force).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PartsError {
    Invalid(PartStatesError),
    /// Older than part states already accepted.
    OutOfOrder {
        stamp_ns: u64,
        newest_ns: u64,
    },
    /// The same `seq` and stamp as the newest accepted part states.
    Duplicate {
        seq: u64,
    },
}

impl fmt::Display for PartsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invalid(e) => write!(f, "{e}"),
            Self::OutOfOrder { stamp_ns, newest_ns } => {
                write!(f, "part_states.stamp_ns {stamp_ns} is older than the newest accepted ({newest_ns})")
            }
            Self::Duplicate { seq } => write!(f, "part_states.seq {seq} repeats the newest accepted message"),
        }
    }
}

impl core::error::Error for PartsError {}

impl PartsError {
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Invalid(e) => e.reason(),
            Self::OutOfOrder { .. } => RejectReason::OutOfOrder,
            Self::Duplicate { .. } => RejectReason::Duplicate,
        }
    }
}

/// Why a request or explicit schedule was rejected (the motor keeps playing
/// the previous motion until it goes stale).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RequestError {
    Invalid(ForceRequestError),
    InvalidExplicit(ExplicitScheduleError),
    /// Older than a request (or explicit schedule) already accepted.
    OutOfOrder {
        stamp_ns: u64,
        newest_ns: u64,
    },
    /// The same `seq` and stamp as the newest accepted request.
    Duplicate {
        seq: u64,
    },
    /// A request arrived before any valid PartStates.
    NoPartStates,
    /// The request names a part id the newest PartStates does not contain.
    UnknownPart {
        id: u32,
    },
    Solve(SolveError),
    /// The schedule cannot be played within the motion limits.
    Motion(MotionError),
    /// The motion would exceed an actuator's stroke, velocity or force.
    Actuator(RigError),
}

impl fmt::Display for RequestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invalid(e) => write!(f, "{e}"),
            Self::InvalidExplicit(e) => write!(f, "{e}"),
            Self::OutOfOrder { stamp_ns, newest_ns } => {
                write!(f, "request stamp_ns {stamp_ns} is older than the newest accepted ({newest_ns})")
            }
            Self::Duplicate { seq } => write!(f, "request seq {seq} repeats the newest accepted request"),
            Self::NoPartStates => f.write_str("force_request: no valid part states received yet"),
            Self::UnknownPart { id } => {
                write!(f, "force_request: part id {id} is not in the newest part states")
            }
            Self::Solve(e) => write!(f, "solve: {e}"),
            Self::Motion(e) => write!(f, "motion: {e}"),
            Self::Actuator(e) => write!(f, "actuator limits: {e}"),
        }
    }
}

impl core::error::Error for RequestError {}

impl RequestError {
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Invalid(e) => e.reason(),
            Self::InvalidExplicit(e) => e.reason(),
            Self::OutOfOrder { .. } => RejectReason::OutOfOrder,
            Self::Duplicate { .. } => RejectReason::Duplicate,
            Self::NoPartStates => RejectReason::NoPartStates,
            Self::UnknownPart { .. } => RejectReason::UnknownPart,
            Self::Solve(_) => RejectReason::Unsolvable,
            Self::Motion(_) => RejectReason::MotionLimits,
            Self::Actuator(_) => RejectReason::ActuatorLimits,
        }
    }
}

/// `seq` and stamp of the newest accepted message of one kind.
#[derive(Debug, Clone, Copy, Default)]
struct Newest {
    seq: u64,
    stamp_ns: u64,
    any: bool,
}

impl Newest {
    /// `Err(newest stamp)` if older, `Ok(true)` if a repeat of the newest.
    fn check(&self, seq: u64, stamp_ns: u64) -> Result<bool, u64> {
        if !self.any {
            return Ok(false);
        }
        if stamp_ns < self.stamp_ns {
            return Err(self.stamp_ns);
        }
        Ok(stamp_ns == self.stamp_ns && seq == self.seq)
    }

    fn accept(&mut self, seq: u64, stamp_ns: u64) {
        *self = Self { seq, stamp_ns, any: true };
    }
}

/// Longest the solver thread sleeps without a ring from the receiver (a
/// safety net: every message and the stop request ring it).
const IDLE_NS: u64 = 100_000_000;

/// The solver thread's state.
#[derive(Debug)]
pub struct SolveStage {
    solver: Solver,
    solution: Solution,
    centers: Vec<[f64; 2]>,
    mu_m_g: f64,
    /// Whether parts keep the outline their states carry (`CoreParams::part_shapes`).
    part_shapes: bool,
    /// Per center, the |k| it can play on this rig.
    k_bounds: Vec<f64>,
    /// The largest of them.
    k_max: f64,
    rig: Rig,
    writer: MotionWriter,
    shared: Arc<CoreShared>,
    limits: ValidationLimits,
    parts_max_age_ns: u64,
    request_max_age_ns: u64,
    newest_parts: Newest,
    newest_request: Newest,
    parts: Box<PartStates>,
    have_parts: bool,
    forces: [ForceConstraint; MAX_PARTS],
    curls: [CurlConstraint; MAX_CURLS],
    /// How each of `forces` moves, and the part each of `curls` is.
    motions: [PartMotion; MAX_PARTS],
    curl_parts: [usize; MAX_CURLS],
    dynamics: PartDynamics,
    friction: PartFriction,
    entries: [ScheduleEntry; MAX_SLOTS],
    schedule: Box<Schedule>,
    out: StageOutputs,
}

impl SolveStage {
    /// The solver thread's loop, until stop: handle whatever the receiver
    /// forwarded, then sleep on the doorbell until it rings again.
    /// `before_each` runs first in every pass (test fault injection).
    pub fn serve<I: Inbox, C: Clock>(
        &mut self,
        inbox: &mut I,
        buf: &mut InboxBuffers,
        clock: &C,
        mut before_each: impl FnMut(),
    ) {
        let shared = self.shared.clone();
        while !shared.stop.load(Relaxed) {
            before_each();
            let seen = shared.solver_doorbell.seen();
            self.drain(inbox, buf, clock);
            shared.solver_doorbell.wait(seen, IDLE_NS);
        }
    }

    /// Handle every pending message; returns how many were handled.
    /// Part states go first within a poll so a request sees the newest poses.
    pub fn drain<I: Inbox, C: Clock>(&mut self, inbox: &mut I, buf: &mut InboxBuffers, clock: &C) -> usize {
        let mut handled = 0;
        while let Some(kind) = inbox.next(buf) {
            let now = clock.now_ns();
            let received = if buf.received_ns == 0 { now } else { buf.received_ns.min(now) };
            // Rejections are counted inside the stage; the reason is not needed here.
            let _ = match kind {
                Inbound::PartStates => self.on_part_states(&buf.parts, received, now).map_err(|_| ()),
                Inbound::Request => self.on_request(&buf.request, now, &|| clock.now_ns()).map_err(|_| ()),
                Inbound::Explicit => self.on_explicit(&buf.explicit, now).map_err(|_| ()),
                Inbound::Command => self.on_command(&buf.command, now).map_err(|_| ()),
            };
            handled += 1;
        }
        handled
    }

    /// Build with every buffer the stage will ever use. `k_bounds` holds
    /// each center's bound on |k| ([`CoreParams::playable_k_bounds`]: the
    /// smaller of `k_max` and what it can play within the motion and
    /// actuator limits), so a solved schedule is always playable; computed
    /// once at start-up by the caller, which also announces them.
    pub fn new(
        params: &CoreParams,
        rig: Rig,
        k_bounds: Vec<f64>,
        writer: MotionWriter,
        shared: Arc<CoreShared>,
        out: StageOutputs,
    ) -> Result<Self, super::params::CoreParamsError> {
        params.validate()?;
        let k_max = k_bounds.iter().fold(0.0, |a: f64, &k| a.max(k));
        let cap = SolverCapacity { parts: MAX_PARTS, curls: MAX_CURLS, centers: params.plate.centers.len() };
        let mut solver = Solver::new(cap, super::rig_info::stage_solver_params(params));
        // Touch every buffer page and resolve every SIMD dispatch now, not
        // on the first frame.
        solver.warm_up();
        let solution = solver.new_solution();
        let probe = PlateMotion::new(params.motion).map_err(super::params::CoreParamsError::Motion)?;
        let dynamics = PartDynamics::new(
            params.motion.part_dynamics,
            probe,
            params.longest_cycle(),
            solver.new_solution(),
        )
        .map_err(|e| super::params::CoreParamsError::Motion(upm_motion::ParamsError::PartDynamics(e)))?;
        let limits = super::rig_info::stage_limits(params, k_max);
        Ok(Self {
            solver,
            solution,
            centers: params.plate.centers.clone(),
            mu_m_g: params.plate.mu_m_g,
            part_shapes: params.motion.part_shapes,
            k_bounds,
            k_max,
            rig,
            writer,
            shared,
            limits,
            parts_max_age_ns: params.safety.parts_max_age_ns,
            request_max_age_ns: params.safety.request_max_age_ns,
            newest_parts: Newest::default(),
            newest_request: Newest::default(),
            parts: Box::new(PartStates::new()),
            have_parts: false,
            forces: [ForceConstraint { position: [0.0; 2], force: None, shape: PartShape::Point }; MAX_PARTS],
            curls: [CurlConstraint { position: [0.0; 2], curl: 0.0, shape: PartShape::Point }; MAX_CURLS],
            motions: [PartMotion::default(); MAX_PARTS],
            curl_parts: [0; MAX_CURLS],
            dynamics,
            friction: params.part_friction,
            entries: [ScheduleEntry::default(); MAX_SLOTS],
            schedule: Box::new(Schedule::new()),
            out,
        })
    }

    /// The largest |k| any center can play (schedules are solved under
    /// [`Self::k_bounds`]).
    pub fn k_max(&self) -> f64 {
        self.k_max
    }

    /// Per center, the |k| it can play on this rig.
    pub fn k_bounds(&self) -> &[f64] {
        &self.k_bounds
    }

    /// Validate and keep the newest part states. `received_ns` is when the
    /// core received them, `now_ns` the core's clock now. A rejection is
    /// counted by reason.
    pub fn on_part_states(
        &mut self,
        msg: &PartStates,
        received_ns: u64,
        now_ns: u64,
    ) -> Result<(), PartsError> {
        let r = self.take_part_states(msg, received_ns, now_ns);
        if let Err(e) = r {
            self.shared.rejected_parts.fetch_add(1, Relaxed);
            self.reject(RejectedKind::PartStates, msg.seq, msg.stamp_ns, now_ns, e.reason(), &e);
        }
        r
    }

    fn take_part_states(
        &mut self,
        msg: &PartStates,
        received_ns: u64,
        now_ns: u64,
    ) -> Result<(), PartsError> {
        self.limits.now_ns = now_ns;
        self.limits.max_age_ns = self.parts_max_age_ns;
        msg.validate(&self.limits).map_err(PartsError::Invalid)?;
        match self.newest_parts.check(msg.seq, msg.stamp_ns) {
            Err(newest_ns) => return Err(PartsError::OutOfOrder { stamp_ns: msg.stamp_ns, newest_ns }),
            Ok(true) => return Err(PartsError::Duplicate { seq: msg.seq }),
            Ok(false) => {}
        }
        self.newest_parts.accept(msg.seq, msg.stamp_ns);
        *self.parts = *msg;
        self.have_parts = true;
        self.shared.parts_stamp_ns.store(msg.stamp_ns.max(1), Relaxed);
        let _ = self.out.samples.push(SolverSample {
            solve_ns: 0,
            ipc_ns: received_ns.saturating_sub(msg.stamp_ns).max(1),
            pickup_ns: now_ns.saturating_sub(received_ns).max(1),
        });
        Ok(())
    }

    /// Validate a force request, solve it against the newest part states,
    /// and hand the motion to the motor. `clock_ns` times the solve.
    pub fn on_request(
        &mut self,
        msg: &ForceRequest,
        now_ns: u64,
        clock_ns: &dyn Fn() -> u64,
    ) -> Result<(), RequestError> {
        let r = self.solve_request(msg, now_ns, clock_ns);
        self.account(r, RejectedKind::ForceRequest, (msg.seq, msg.stamp_ns, msg.deadline_ns), now_ns)
    }

    /// Validate an explicit schedule and hand it to the motor.
    pub fn on_explicit(&mut self, msg: &ExplicitSchedule, now_ns: u64) -> Result<(), RequestError> {
        let r = self.take_explicit(msg, now_ns);
        self.account(r, RejectedKind::ExplicitSchedule, (msg.seq, msg.stamp_ns, u64::MAX), now_ns)
    }

    /// Validate an operator's command and pass it to the motor.
    pub fn on_command(&mut self, msg: &CoreCommand, now_ns: u64) -> Result<(), CoreCommandError> {
        self.limits.now_ns = now_ns;
        self.limits.max_age_ns = self.request_max_age_ns;
        if let Err(e) = msg.validate(&self.limits) {
            self.shared.rejected_requests.fetch_add(1, Relaxed);
            self.reject(RejectedKind::CoreCommand, msg.seq, msg.stamp_ns, now_ns, e.reason(), &e);
            return Err(e);
        }
        match msg.command {
            CoreCommand::STOP => self.shared.operator_stop.store(true, Relaxed),
            CoreCommand::START => self.shared.operator_stop.store(false, Relaxed),
            // RESUME: validate() lets no other command through.
            _ => self.shared.resume_requested.store(true, Relaxed),
        }
        Ok(())
    }

    /// Count a rejection by reason and answer its sender (through the io
    /// thread, on `upm/rejection`). Formats into a fixed buffer: no
    /// allocation.
    fn reject(
        &mut self,
        kind: RejectedKind,
        seq: u64,
        message_stamp_ns: u64,
        now_ns: u64,
        reason: RejectReason,
        why: &dyn fmt::Display,
    ) {
        self.shared.count_reject(reason);
        let mut answer = Rejection::new(kind, seq, message_stamp_ns, now_ns, reason, format_args!("{why}"));
        if self.have_parts {
            answer.parts_seq = self.parts.seq;
            answer.parts_stamp_ns = self.parts.stamp_ns;
        }
        // Dropped (still counted) if the io thread is a full ring behind.
        let _ = self.out.rejections.push(answer);
    }

    /// `message` is the (seq, stamp_ns, deadline_ns) of what was handled.
    fn account(
        &mut self,
        r: Result<(), RequestError>,
        kind: RejectedKind,
        message: (u64, u64, u64),
        now_ns: u64,
    ) -> Result<(), RequestError> {
        let (seq, stamp_ns, deadline_ns) = message;
        match r {
            Ok(()) => {
                self.newest_request.accept(seq, stamp_ns);
                self.shared.request_stamp_ns.store(stamp_ns.max(1), Relaxed);
                self.shared.request_deadline_ns.store(deadline_ns, Relaxed);
                // Dropped (not blocked on) if the io thread is a full ring behind.
                let _ = self.out.schedules.push(*self.schedule);
                Ok(())
            }
            Err(e) => {
                self.shared.rejected_requests.fetch_add(1, Relaxed);
                self.reject(kind, seq, stamp_ns, now_ns, e.reason(), &e);
                Err(e)
            }
        }
    }

    /// Requests and explicit schedules share one order: the newest wins.
    fn check_order(&self, seq: u64, stamp_ns: u64) -> Result<(), RequestError> {
        match self.newest_request.check(seq, stamp_ns) {
            Err(newest_ns) => Err(RequestError::OutOfOrder { stamp_ns, newest_ns }),
            Ok(true) => Err(RequestError::Duplicate { seq }),
            Ok(false) => Ok(()),
        }
    }

    fn solve_request(
        &mut self,
        msg: &ForceRequest,
        now_ns: u64,
        clock_ns: &dyn Fn() -> u64,
    ) -> Result<(), RequestError> {
        self.limits.now_ns = now_ns;
        self.limits.max_age_ns = self.request_max_age_ns;
        msg.validate(&self.limits).map_err(RequestError::Invalid)?;
        self.check_order(msg.seq, msg.stamp_ns)?;
        if !self.have_parts {
            return Err(RequestError::NoPartStates);
        }
        let started = clock_ns();
        let (mut np, mut nc) = (0, 0);
        for e in msg.entries() {
            let Some(p) = self.parts.parts().iter().find(|p| p.id == e.part_id) else {
                return Err(RequestError::UnknownPart { id: e.part_id });
            };
            let position = [p.x, p.y];
            let shape = if self.part_shapes { PartShape::from_wire(p) } else { PartShape::Point };
            self.forces[np] = ForceConstraint { position, force: e.requested_force(), shape };
            self.motions[np] = PartMotion {
                velocity: [p.vx, p.vy],
                spin: p.omega,
                // Read only by the correction.
                friction: if self.dynamics.enabled() { self.friction.scale(p.class, p.x, p.y) } else { 1.0 },
            };
            if let Some(curl) = e.requested_curl() {
                // validate() caps curl entries at MAX_CURLS.
                self.curls[nc] = CurlConstraint { position, curl, shape };
                self.curl_parts[nc] = np;
                nc += 1;
            }
            np += 1;
        }
        let problem = Problem {
            mu_m_g: self.mu_m_g,
            k_max: self.k_max,
            centers: &self.centers,
            parts: &self.forces[..np],
            curls: &self.curls[..nc],
            k_bounds: &self.k_bounds,
        };
        self.solver.solve(&problem, &mut self.solution).map_err(RequestError::Solve)?;
        if self.dynamics.enabled() {
            let (motions, curl_parts) = (&self.motions[..np], &self.curl_parts[..nc]);
            self.dynamics.correct(&mut self.solver, &problem, motions, curl_parts, &mut self.solution);
        }
        // A center fills counts[j] consecutive slots (1 each in the paper's
        // cycle); the solver keeps the total within the entries' capacity.
        let n = fill_entries(&self.solution, &self.centers, &mut self.entries);
        self.stage_motion(n, msg.seq, self.parts.stamp_ns)?;
        let solve_ns = clock_ns().saturating_sub(started).max(1);
        let s = &self.solution;
        let m = &mut *self.schedule;
        m.clear();
        m.seq = msg.seq;
        m.stamp_ns = now_ns;
        m.cycle = self.shared.cycle.load(Relaxed) + 1;
        m.solve_time_ns = solve_ns;
        m.parts_seq = self.parts.seq;
        m.parts_stamp_ns = self.parts.stamp_ns;
        m.request_stamp_ns = msg.stamp_ns;
        m.residual = s.residual;
        m.condition = s.condition;
        m.rank = s.rank as u32;
        m.saturated = u32::from(s.saturated);
        // At most the centers' count, which fits MAX_CENTERS.
        m.at_bound = s.at_bound as u32;
        for &j in s.order() {
            let j = usize::from(j);
            for _ in 0..s.counts()[j] {
                // Capacity equals MAX_SLOTS, as the entries'.
                let _ = m.push(ScheduleSlot::new(j as u32, self.centers[j], s.k()[j]));
            }
        }
        let _ = self.out.samples.push(SolverSample { solve_ns, ipc_ns: 0, pickup_ns: 0 });
        Ok(())
    }

    fn take_explicit(&mut self, msg: &ExplicitSchedule, now_ns: u64) -> Result<(), RequestError> {
        self.limits.now_ns = now_ns;
        self.limits.max_age_ns = self.request_max_age_ns;
        msg.validate(&self.limits).map_err(RequestError::InvalidExplicit)?;
        self.check_order(msg.seq, msg.stamp_ns)?;
        let n = msg.slots().len();
        // entries has room for every slot (asserted at compile time) and
        // validate() checked every center index; get() keeps a future gap
        // between the two a rejection, not a panic.
        for (index, (entry, e)) in self.entries.iter_mut().zip(msg.slots()).enumerate() {
            let center = *self.centers.get(e.center_index as usize).ok_or(RequestError::InvalidExplicit(
                ExplicitScheduleError::UnknownCenter { index, center_index: e.center_index },
            ))?;
            // Beyond what this center can play: refused here, by name,
            // rather than by the motion or actuator check below.
            if self.k_bounds.get(e.center_index as usize).is_none_or(|&u| e.k.abs() > u) {
                return Err(RequestError::InvalidExplicit(ExplicitScheduleError::KOutOfRange { index }));
            }
            *entry = ScheduleEntry { center, k: e.k };
        }
        self.stage_motion(n, msg.seq, 0)?;
        let m = &mut *self.schedule;
        m.clear();
        m.seq = msg.seq;
        m.stamp_ns = now_ns;
        m.cycle = self.shared.cycle.load(Relaxed) + 1;
        m.solve_time_ns = 0;
        m.parts_seq = 0;
        m.parts_stamp_ns = 0;
        m.request_stamp_ns = msg.stamp_ns;
        m.residual = 0.0;
        m.condition = 0.0;
        m.rank = 0;
        m.saturated = 0;
        m.at_bound = 0;
        for (e, entry) in msg.slots().iter().zip(&self.entries) {
            let _ = m.push(ScheduleSlot::new(e.center_index, entry.center, e.k));
        }
        Ok(())
    }

    /// Build the motion for `entries[..n]` in the back buffer, check it, and
    /// publish it. On error nothing is published.
    fn stage_motion(&mut self, n: usize, seq: u64, frame_stamp_ns: u64) -> Result<(), RequestError> {
        let staged = self.writer.staging();
        staged.motion.set_schedule(&self.entries[..n]).map_err(RequestError::Motion)?;
        self.rig.check_motion(&staged.motion).map_err(RequestError::Actuator)?;
        staged.request_seq = seq;
        staged.frame_stamp_ns = frame_stamp_ns;
        self.writer.publish();
        Ok(())
    }
}
