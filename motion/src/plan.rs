//! Schedule → closed slot-by-slot plate motion, and its sampling.

use core::fmt;

use super::params::{MotionParams, ParamsError};
use super::pose::{PlateSample, Pose, Twist};
use super::profile::Profile;

/// Most slots one motion holds (fixed so that building allocates nothing):
/// the protocol's, so every explicit schedule that validates fits.
pub const MAX_SLOTS: usize = ipc_types::MAX_SLOTS;

/// One entry of a schedule: a rotation center and its intensity k (k > 0:
/// slow phase counter-clockwise, so the average push is along +R90(P − C)).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ScheduleEntry {
    pub center: [f64; 2],
    pub k: f64,
}

/// One built slot: slow half then fast half, both about `center`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Slot {
    pub center: [f64; 2],
    pub k: f64,
    /// +1: slow phase counter-clockwise; −1: clockwise.
    pub sign: f64,
    /// Peak angle A_j (rad), reached at t_s.
    pub amplitude: f64,
    /// Distance from the center to the farthest plate corner (m).
    pub r_max: f64,
    /// Duration of the slow half (s); the fast half lasts τ − t_s.
    pub t_slow: f64,
    /// Angular velocity of the slow direction (positive = slow phase),
    /// multiplied by `sign` when sampled.
    pub profile: Profile,
}

/// Why a schedule cannot be played. `slot` is the index in play order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MotionError {
    Params(ParamsError),
    TooManySlots {
        given: usize,
        capacity: usize,
    },
    /// Center index in `order` outside the centers given.
    CenterIndex {
        slot: usize,
    },
    NonFinite {
        slot: usize,
    },
    /// |k| above `MotionParams::k_max`.
    KOutOfRange {
        slot: usize,
        k: f64,
        k_max: f64,
    },
    /// A_j = displacement / r_max above the angle limit.
    AngleLimit {
        slot: usize,
        required: f64,
        limit: f64,
    },
    /// The slow half cannot sweep A_j with the allowed acceleration.
    SlowPhaseInfeasible {
        slot: usize,
    },
    /// The fast half is too short to sweep A_j back within the acceleration
    /// limit; `max_k` is the largest |k| this slot's center could play.
    FastPhaseInfeasible {
        slot: usize,
        k: f64,
        max_k: f64,
    },
    AngularVelocityLimit {
        slot: usize,
        required: f64,
        limit: f64,
    },
    PointSpeedLimit {
        slot: usize,
        required: f64,
        limit: f64,
    },
    PointAccelerationLimit {
        slot: usize,
        required: f64,
        limit: f64,
    },
}

impl fmt::Display for MotionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Params(e) => write!(f, "{e}"),
            Self::TooManySlots { given, capacity } => {
                write!(f, "schedule: {given} slots, capacity {capacity}")
            }
            Self::CenterIndex { slot } => write!(f, "schedule[{slot}]: center index out of range"),
            Self::NonFinite { slot } => write!(f, "schedule[{slot}]: non-finite center or k"),
            Self::KOutOfRange { slot, k, k_max } => {
                write!(f, "schedule[{slot}]: |k| = {} > k_max = {k_max}", k.abs())
            }
            Self::AngleLimit { slot, required, limit } => {
                write!(f, "schedule[{slot}]: angle {required:.3e} rad > limit {limit:.3e}")
            }
            Self::SlowPhaseInfeasible { slot } => {
                write!(f, "schedule[{slot}]: slow phase cannot fit its ramps")
            }
            Self::FastPhaseInfeasible { slot, k, max_k } => write!(
                f,
                "schedule[{slot}]: |k| = {:.3} needs a fast phase beyond the acceleration limit (max |k| {max_k:.3})",
                k.abs()
            ),
            Self::AngularVelocityLimit { slot, required, limit } => {
                write!(f, "schedule[{slot}]: angular velocity {required:.3e} rad/s > limit {limit:.3e}")
            }
            Self::PointSpeedLimit { slot, required, limit } => {
                write!(f, "schedule[{slot}]: plate point speed {required:.3e} m/s > limit {limit:.3e}")
            }
            Self::PointAccelerationLimit { slot, required, limit } => {
                write!(
                    f,
                    "schedule[{slot}]: plate point acceleration {required:.3e} m/s² > limit {limit:.3e}"
                )
            }
        }
    }
}

impl core::error::Error for MotionError {}

/// Distance from `c` to the farthest corner of the plate outline.
fn r_max(p: &MotionParams, c: [f64; 2]) -> f64 {
    let [hx, hy] = p.plate_half_extent;
    (c[0].abs() + hx).hypot(c[1].abs() + hy)
}

/// Shape one slot, or say which limit it breaks.
pub(crate) fn build_slot(p: &MotionParams, slot: usize, e: ScheduleEntry) -> Result<Slot, MotionError> {
    if !(e.center[0].is_finite() && e.center[1].is_finite() && e.k.is_finite()) {
        return Err(MotionError::NonFinite { slot });
    }
    if e.k.abs() > p.k_max {
        return Err(MotionError::KOutOfRange { slot, k: e.k, k_max: p.k_max });
    }
    let l = p;
    let r = r_max(p, e.center);
    let amp = p.displacement / r;
    if amp > l.max_angle {
        return Err(MotionError::AngleLimit { slot, required: amp, limit: l.max_angle });
    }
    let tau = p.slot_duration();
    let h = p.tick();
    let n_ticks = p.slot_ticks as i64;
    let t_s = 0.5 * tau * (1.0 + e.k.abs());
    let a_lim = p.ramp_fraction * l.max_angular_acceleration.min(l.max_point_acceleration / r);
    let up = p.ramp_up_ticks.max(1) as i64;

    // Slow half: 0 → V_s over `up` ticks, cruise, then one tick down to w1
    // at tick n1 = ⌊t_s/h⌋. The reversal is the straight segment from w1 at
    // n1 to −w2 at n1 + 1 with slope V_s/h, crossing zero at exactly t_s.
    let n1 = (t_s / h).floor() as i64;
    let n0 = n1 - 1;
    if n0 < up {
        return Err(MotionError::SlowPhaseInfeasible { slot });
    }
    let d1 = t_s - n1 as f64 * h;
    let d2 = h - d1;
    let hf = h;
    let slow_unit =
        0.5 * up as f64 * hf + (n0 - up) as f64 * hf + 0.5 * (1.0 + d1 / hf) * hf + 0.5 * d1 * d1 / hf;
    let v_s = amp / slow_unit;
    let slope = v_s / hf;
    let (w1, w2) = (slope * d1, slope * d2);
    // Fast half: ramp from −w2 to −V_f over m ticks, cruise, ramp to 0 over
    // m ticks at the slot end; V_f is what sweeps A back exactly.
    let infeasible = MotionError::FastPhaseInfeasible { slot, k: e.k, max_k: 0.0 };
    let n2 = n1 + 1;
    let left = n_ticks - n2;
    let m = (left / 4).max(1);
    if left < 2 * m {
        return Err(infeasible);
    }
    let (n3, n4) = (n2 + m, n_ticks - m);
    let head = 0.5 * w2 * d2 + 0.5 * w2 * m as f64 * hf;
    let v_f = (amp - head) / (m as f64 * hf + (n4 - n3) as f64 * hf);
    if !(v_f > 0.0) {
        return Err(infeasible);
    }
    let knots = [
        (0.0, 0.0),
        (up as f64 * hf, v_s),
        (n0 as f64 * hf, v_s),
        (n1 as f64 * hf, w1),
        (t_s, 0.0),
        (n2 as f64 * hf, -w2),
        (n3 as f64 * hf, -v_f),
        (n4 as f64 * hf, -v_f),
        (tau, 0.0),
    ];
    let profile = Profile::from_knots(&knots);
    // Rounding in the last segment: the fast half must sweep back exactly A.
    if (profile.theta[profile.n - 1]).abs() > 1e-9 * amp {
        return Err(infeasible);
    }
    let a_max = profile.max_acceleration();
    if a_max > a_lim {
        return Err(infeasible);
    }
    let w = profile.max_velocity();
    if w > l.max_angular_velocity {
        return Err(MotionError::AngularVelocityLimit { slot, required: w, limit: l.max_angular_velocity });
    }
    if w * r > l.max_point_speed {
        return Err(MotionError::PointSpeedLimit { slot, required: w * r, limit: l.max_point_speed });
    }
    let acc = r * a_max.hypot(w * w);
    if acc > l.max_point_acceleration {
        return Err(MotionError::PointAccelerationLimit {
            slot,
            required: acc,
            limit: l.max_point_acceleration,
        });
    }
    let sign = if e.k < 0.0 { -1.0 } else { 1.0 };
    Ok(Slot { center: e.center, k: e.k, sign, amplitude: amp, r_max: r, t_slow: t_s, profile })
}

/// Largest |k| a slot about `center` can play under `p` (bisection; not for
/// the hot path).
pub(crate) fn max_playable_k(p: &MotionParams, center: [f64; 2]) -> f64 {
    let ok = |k: f64| build_slot(p, 0, ScheduleEntry { center, k }).is_ok();
    if !ok(0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, p.k_max);
    if ok(hi) {
        return hi;
    }
    for _ in 0..48 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) { lo = mid } else { hi = mid }
    }
    lo
}

/// A closed, periodic plate motion built from a schedule.
///
/// The slots live on the heap, allocated once in [`PlateMotion::new`]: at
/// about 170 kB a buffer, a motion held by value would fill a thread's
/// stack (a lock-step core holds several).
#[derive(Debug, Clone)]
pub struct PlateMotion {
    params: MotionParams,
    slots: Box<[Slot]>,
    /// Where [`PlateMotion::set_schedule`] builds, so a failed build keeps
    /// the motion playing; swapped with `slots` on success.
    spare: Box<[Slot]>,
    len: usize,
}

impl PlateMotion {
    /// An empty motion (the plate holds at home) with validated parameters.
    pub fn new(params: MotionParams) -> Result<Self, ParamsError> {
        params.validate()?;
        let empty = || vec![Slot::default(); MAX_SLOTS].into_boxed_slice();
        Ok(Self { params, slots: empty(), spare: empty(), len: 0 })
    }

    pub fn params(&self) -> &MotionParams {
        &self.params
    }

    /// Replace the schedule. On error the previous motion is kept. No heap
    /// allocation (the new slots are built in the spare buffer first).
    pub fn set_schedule(&mut self, entries: &[ScheduleEntry]) -> Result<(), MotionError> {
        if entries.len() > MAX_SLOTS {
            return Err(MotionError::TooManySlots { given: entries.len(), capacity: MAX_SLOTS });
        }
        for (j, e) in entries.iter().enumerate() {
            self.spare[j] = build_slot(&self.params, j, *e).map_err(|err| match err {
                MotionError::FastPhaseInfeasible { slot, k, .. } => MotionError::FastPhaseInfeasible {
                    slot,
                    k,
                    max_k: max_playable_k(&self.params, e.center),
                },
                other => other,
            })?;
        }
        core::mem::swap(&mut self.slots, &mut self.spare);
        self.len = entries.len();
        Ok(())
    }

    /// Build from a solver answer: `k` per center in input order, `order`
    /// the play order (indices into `centers`).
    pub fn set_from_solution(
        &mut self,
        centers: &[[f64; 2]],
        k: &[f64],
        order: &[u16],
    ) -> Result<(), MotionError> {
        if order.len() > MAX_SLOTS {
            return Err(MotionError::TooManySlots { given: order.len(), capacity: MAX_SLOTS });
        }
        let mut entries = [ScheduleEntry::default(); MAX_SLOTS];
        for (slot, &j) in order.iter().enumerate() {
            let j = j as usize;
            match (centers.get(j), k.get(j)) {
                (Some(&center), Some(&kj)) => entries[slot] = ScheduleEntry { center, k: kj },
                _ => return Err(MotionError::CenterIndex { slot }),
            }
        }
        self.set_schedule(&entries[..order.len()])
    }

    /// Empty the schedule: the plate holds at home.
    pub fn clear(&mut self) {
        self.len = 0;
    }

    pub fn slots(&self) -> &[Slot] {
        &self.slots[..self.len]
    }

    /// Largest |k| a slot about `center` could play with these parameters.
    pub fn max_playable_k(&self, center: [f64; 2]) -> f64 {
        max_playable_k(&self.params, center)
    }

    pub fn slot_ticks(&self) -> u64 {
        self.params.slot_ticks as u64
    }

    /// Ticks per cycle (0 for an empty motion).
    pub fn cycle_ticks(&self) -> u64 {
        self.len as u64 * self.slot_ticks()
    }

    /// Cycle duration T = N·τ (s).
    pub fn cycle_duration(&self) -> f64 {
        self.len as f64 * self.params.slot_duration()
    }

    /// The motion at motor tick `tick` (tick 0 = start of a cycle).
    /// Allocation-free, panic-free, O(1).
    #[inline(always)]
    pub fn sample_tick(&self, tick: u64) -> PlateSample {
        let n = self.slot_ticks();
        let cycle = self.cycle_ticks();
        if cycle == 0 {
            return PlateSample { cycle_start: true, ..PlateSample::default() };
        }
        // 32-bit division where it fits (the first 5 days at 10 kHz): a
        // 64-bit divide costs several times more on common x86 cores.
        let (within, slot, local) = match (u32::try_from(tick), u32::try_from(cycle), u32::try_from(n)) {
            (Ok(t), Ok(c), Ok(n)) => {
                let w = t % c;
                (w as u64, (w / n) as usize, (w % n) as u64)
            }
            _ => {
                let w = tick % cycle;
                (w, (w / n) as usize, w % n)
            }
        };
        let local = local as f64 * self.params.tick();
        let mut s = self.eval_slot(slot, local);
        s.cycle_start = within == 0;
        s
    }

    /// The motion at time `t` (s) since a cycle start; non-finite or
    /// negative times give home.
    pub fn sample(&self, t: f64) -> PlateSample {
        if self.len == 0 || !t.is_finite() || t < 0.0 {
            return PlateSample { cycle_start: true, ..PlateSample::default() };
        }
        let tau = self.params.slot_duration();
        let within = t % self.cycle_duration();
        let slot = ((within / tau) as usize).min(self.len - 1);
        let mut s = self.eval_slot(slot, within - slot as f64 * tau);
        s.cycle_start = within == 0.0;
        s
    }

    #[inline(always)]
    fn eval_slot(&self, slot: usize, t: f64) -> PlateSample {
        let Some(s) = self.slots.get(slot) else {
            return PlateSample::default();
        };
        let p = s.profile.eval(t);
        let (theta, omega, alpha) = (s.sign * p.theta, s.sign * p.omega, s.sign * p.alpha);
        // Rotation by theta about C from home: O = C − R(θ)C.
        let [cx, cy] = s.center;
        let (sn, cs) = super::pose::sin_cos(theta);
        let ox = cx - (cs * cx - sn * cy);
        let oy = cy - (sn * cx + cs * cy);
        let (dx, dy) = (ox - cx, oy - cy);
        PlateSample {
            pose: Pose { x: ox, y: oy, theta },
            velocity: Twist { x: -omega * dy, y: omega * dx, theta: omega },
            acceleration: Twist {
                x: -alpha * dy - omega * omega * dx,
                y: alpha * dx - omega * omega * dy,
                theta: alpha,
            },
            slot: slot as u16,
            cycle_start: false,
        }
    }
}
