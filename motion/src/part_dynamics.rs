//! The solve stage's part-dynamics correction. The solver's rows take
//! every part at rest; a sliding part feels each slot turned by its own
//! velocity and spin, and a min-norm answer loses a fixed fraction of its
//! request to that (`motion::part_drift`). This plays the answer's cycle
//! on each part from the velocity and spin vision reports for it
//! (`PartState::vx`, `vy`, `omega`), and asks again for what it asked
//! plus what the model says it still lacks, force and own curl: a
//! fixed-point iteration on the request, the model linearized about the
//! reported state at each step.
//!
//! Cost per step: one motion sample per piece of the cycle (cycle ticks ×
//! `substeps`), then per part one pass over those pieces, once per contact
//! point (a part asked only a force as a point at its centroid; a part
//! asked a curl over its whole contact patch, 12–96 points, force and
//! spin from the same pass), and one solve. A request whose correction
//! would cost more than `max_work` point evaluations
//! ([`MAX_CORRECTION_WORK`] by default) is answered uncorrected. No allocation: the plate trace, the second
//! solution and every buffer are sized at construction.
//!
//! Guarantee: the answer kept is the step whose predicted lack (largest
//! relative gap between asked and predicted) is least, step 0 (the
//! uncorrected answer) included, so by the model's own measure the
//! correction never makes an answer worse. Limits: kinetic friction only,
//! the plate taken to follow its command exactly, one cycle ahead; a
//! shaped part asked only a force is predicted as a point at its centroid,
//! so within a few radii of a played center the gap between its patch
//! row and the point (O((R/d)²)) is taken for lack; on sparse cycles a
//! re-solve may move slots, and is then played in its own order; the
//! schedule's residual, rank and condition are those of the kept step's
//! solve (of the corrected request).

use ipc_types::{MAX_CURLS, MAX_PARTS};

use crate::part_dynamics_params::{LinearizeAbout, MAX_TRACE_PIECES, PartDynamicsError, PartDynamicsParams};

use crate::{DriftParams, MAX_SLOTS, MotionParams, PlateMotion, PlateTrace, ScheduleEntry, fill_entries};
use upm_solver::{CurlConstraint, ForceConstraint, PartShape, Problem, Solution, Solver};

impl PartDynamicsParams {
    /// Plate-trace pieces a cycle of `slots` needs; 0 when off.
    pub fn trace_pieces(&self, motion: &MotionParams, slots: usize) -> Result<usize, PartDynamicsError> {
        if self.steps == 0 {
            return Ok(0);
        }
        let pieces = self.cycle_pieces(slots, motion.slot_ticks);
        if pieces > MAX_TRACE_PIECES {
            return Err(PartDynamicsError::TraceTooLong { pieces });
        }
        Ok(pieces as usize)
    }

    /// Pieces of a cycle of `slots` slots of `slot_ticks` ticks, cut into
    /// `substeps` each.
    fn cycle_pieces(&self, slots: usize, slot_ticks: u32) -> u64 {
        (slots.min(MAX_SLOTS) as u64)
            .saturating_mul(u64::from(slot_ticks))
            .saturating_mul(u64::from(self.substeps))
    }
}

/// How a part moves now, as vision reports it, and its friction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartMotion {
    pub velocity: [f64; 2],
    pub spin: f64,
    /// The part's μ over the model's where it stands (a plate
    /// calibration's class scale times its map; 1 without one). Its
    /// request is in the model's units (the planner divided by it), but
    /// how far it slides within the cycle goes with its real friction.
    /// Anything but a finite positive value counts as 1.
    pub friction: f64,
}

impl Default for PartMotion {
    /// At rest, with the model's friction.
    fn default() -> Self {
        Self { velocity: [0.0; 2], spin: 0.0, friction: 1.0 }
    }
}

impl PartMotion {
    /// `friction` if finite and positive, else 1.
    fn friction_scale(&self) -> f64 {
        if self.friction.is_finite() && self.friction > 0.0 { self.friction } else { 1.0 }
    }
}

/// What one correction did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Correction {
    /// Solves after the first.
    pub steps: u32,
    /// The step whose answer was kept (0: the uncorrected one).
    pub kept: u32,
    /// Predicted lack of the uncorrected answer and of the one kept.
    pub lack_before: f64,
    pub lack: f64,
    /// The request would cost more than `max_work`: answered uncorrected.
    pub skipped: bool,
}

/// A corrected answer within this relative lack ends the steps early.
const TOLERANCE: f64 = 1e-3;

/// The correction's state; every buffer sized at construction.
#[derive(Debug)]
pub struct PartDynamics {
    params: PartDynamicsParams,
    drift: DriftParams,
    probe: PlateMotion,
    trace: PlateTrace,
    entries: [ScheduleEntry; MAX_SLOTS],
    asked_forces: [ForceConstraint; MAX_PARTS],
    asked_curls: [CurlConstraint; MAX_CURLS],
    predicted_forces: [[f64; 2]; MAX_PARTS],
    predicted_curls: [Option<f64>; MAX_CURLS],
    /// What the model predicts for the kept answer.
    kept_forces: [[f64; 2]; MAX_PARTS],
    kept_curls: [Option<f64>; MAX_CURLS],
    kept_len: (usize, usize),
    /// Parts whose force came from their curl's patch pass.
    patched: [bool; MAX_PARTS],
    /// The first answer's play order and slot counts, held through the
    /// steps.
    first_order: Vec<u16>,
    first_counts: Vec<u16>,
    best: Solution,
}

impl PartDynamics {
    /// `probe` is a motion of the rig's parameters to play answers on,
    /// `slots` the longest cycle's, `spare` a solution of the solver's
    /// capacity (the kept answer is swapped through it).
    pub fn new(
        params: PartDynamicsParams,
        probe: PlateMotion,
        slots: usize,
        spare: Solution,
    ) -> Result<Self, PartDynamicsError> {
        params.validate()?;
        let pieces = params.trace_pieces(probe.params(), slots)?;
        Ok(Self {
            params,
            drift: DriftParams { follow: params.follow, substeps: u64::from(params.substeps) },
            trace: PlateTrace::with_capacity(pieces),
            probe,
            entries: [ScheduleEntry::default(); MAX_SLOTS],
            asked_forces: [ForceConstraint { position: [0.0; 2], force: None, shape: PartShape::Point };
                MAX_PARTS],
            asked_curls: [CurlConstraint { position: [0.0; 2], curl: 0.0, shape: PartShape::Point };
                MAX_CURLS],
            predicted_forces: [[0.0; 2]; MAX_PARTS],
            predicted_curls: [None; MAX_CURLS],
            kept_forces: [[0.0; 2]; MAX_PARTS],
            kept_curls: [None; MAX_CURLS],
            kept_len: (0, 0),
            patched: [false; MAX_PARTS],
            first_order: Vec::with_capacity(spare.capacity_centers()),
            first_counts: Vec::with_capacity(spare.capacity_centers()),
            best: spare,
        })
    }

    pub fn enabled(&self) -> bool {
        self.params.steps > 0
    }

    /// After [`Self::correct`]: per part, the cycle's mean force the model
    /// predicts for the kept answer (empty if off).
    pub fn predicted_forces(&self) -> &[[f64; 2]] {
        &self.kept_forces[..self.kept_len.0]
    }

    /// Per curl, the curl its patch's predicted spin-up shows (None for a
    /// point: it has no spin to predict).
    pub fn predicted_curls(&self) -> &[Option<f64>] {
        &self.kept_curls[..self.kept_len.1]
    }

    /// Correct `solution`, the solver's answer to `problem`, in place.
    /// `motions[i]` is how `problem.parts[i]` moves; `curl_parts[c]` the
    /// part whose own curl `problem.curls[c]` is. A failed re-solve ends
    /// the steps (the best answer so far is kept).
    pub fn correct(
        &mut self,
        solver: &mut Solver,
        problem: &Problem<'_>,
        motions: &[PartMotion],
        curl_parts: &[usize],
        solution: &mut Solution,
    ) -> Correction {
        let (np, nc) = (problem.parts.len().min(MAX_PARTS), problem.curls.len().min(MAX_CURLS));
        let mut out = Correction::default();
        self.kept_len = (0, 0);
        if !self.enabled() || motions.len() < np || curl_parts.len() < nc {
            return out;
        }
        if self.work(problem, solution) > self.params.max_work {
            out.skipped = true;
            return out;
        }
        self.asked_forces[..np].copy_from_slice(&problem.parts[..np]);
        self.asked_curls[..nc].copy_from_slice(&problem.curls[..nc]);
        let mut best_lack = f64::INFINITY;
        for step in 0..=self.params.steps {
            let lack = self.predict(problem, motions, curl_parts, solution);
            if step == 0 {
                out.lack_before = lack;
                // Within capacity: both are the solver's.
                self.first_order.clear();
                self.first_order.extend_from_slice(solution.order());
                self.first_counts.clear();
                self.first_counts.extend_from_slice(solution.counts());
            }
            if step == 0 || lack < best_lack {
                core::mem::swap(solution, &mut self.best);
                (best_lack, out.kept) = (lack, step);
                self.kept_forces[..np].copy_from_slice(&self.predicted_forces[..np]);
                self.kept_curls[..nc].copy_from_slice(&self.predicted_curls[..nc]);
                self.kept_len = (np, nc);
            }
            if !lack.is_finite() {
                // Not playable or not finite: nothing to ask from it.
                if step == 0 {
                    self.kept_len = (0, 0);
                }
                break;
            }
            if lack <= TOLERANCE || step == self.params.steps {
                break;
            }
            for i in 0..np {
                if let (Some(f), Some(w)) = (self.asked_forces[i].force.as_mut(), problem.parts[i].force) {
                    let got = self.predicted_forces[i];
                    *f = [f[0] + w[0] - got[0], f[1] + w[1] - got[1]];
                }
            }
            for c in 0..nc {
                if let Some(got) = self.predicted_curls[c] {
                    self.asked_curls[c].curl += problem.curls[c].curl - got;
                }
            }
            let asked =
                Problem { parts: &self.asked_forces[..np], curls: &self.asked_curls[..nc], ..*problem };
            if solver.solve(&asked, solution).is_err() {
                break;
            }
            out.steps = step + 1;
            // The first answer's play order, held where the answer plays
            // the same slots (always on the paper's cycle): with the order
            // free the model being corrected changes from step to step and
            // the steps wander. A sparse answer that moved its slots plays
            // as the solver ordered it.
            if solution.counts() == self.first_counts.as_slice() {
                solution.hold_order(&self.first_order);
            }
        }
        core::mem::swap(solution, &mut self.best);
        out.lack = best_lack;
        out
    }

    /// Play `solution`'s cycle on every part; the largest relative lack
    /// (∞ if the cycle cannot be played or a prediction is not finite).
    fn predict(
        &mut self,
        problem: &Problem<'_>,
        motions: &[PartMotion],
        curl_parts: &[usize],
        solution: &Solution,
    ) -> f64 {
        let n = fill_entries(solution, problem.centers, &mut self.entries);
        if self.probe.set_schedule(&self.entries[..n]).is_err()
            || self.trace.record(&self.probe, self.drift).is_err()
        {
            return f64::INFINITY;
        }
        let (mu_g, mass) = (self.params.mu_g, problem.mu_m_g / self.params.mu_g);
        let mut lack = 0.0f64;
        let np = problem.parts.len().min(MAX_PARTS);
        self.patched[..np].fill(false);
        // Parts asked a curl: over their patch, spin and force at once.
        for (c, curl) in problem.curls.iter().enumerate().take(MAX_CURLS) {
            let patch = curl.shape.patch_points();
            if patch.rho2 <= 0.0 {
                // A point has no spin to predict: its curl stays as asked.
                self.predicted_curls[c] = None;
                continue;
            }
            let i = curl_parts.get(c).copied().unwrap_or(usize::MAX);
            let m = self.start(motions.get(i).copied().unwrap_or_default());
            let s = m.friction_scale();
            let at = [curl.position[0] + patch.centroid[0], curl.position[1] + patch.centroid[1]];
            let (a, alpha) = self.trace.mean_twist(at, &patch, m.velocity, m.spin, s * mu_g);
            // In the model's units: the real push over the part's friction.
            let mass = mass / s;
            // The curl whose torque gives this spin-up: 2τ/(mρ²) = 2α·m.
            let got = 2.0 * alpha * mass;
            self.predicted_curls[c] = Some(got);
            // A curl asked as zero is met within 1e-6 μmg per metre.
            let gap = (curl.curl - got).abs() / (curl.curl.abs() + 1e-6 * problem.mu_m_g);
            lack = lack.max(nan_is_infinite(gap));
            let own =
                problem.parts.get(i).is_some_and(|p| p.position == curl.position && p.shape == curl.shape);
            if own && i < np {
                self.predicted_forces[i] = [a[0] * mass, a[1] * mass];
                self.patched[i] = true;
            }
        }
        for (i, part) in problem.parts.iter().enumerate().take(np) {
            if !self.patched[i] {
                let shaped = part.shape.patch_points();
                let at = [part.position[0] + shaped.centroid[0], part.position[1] + shaped.centroid[1]];
                // Unless asked otherwise, a part asked only a force as a
                // point at its centroid (a patch costs its point count).
                let patch = if self.params.patch_forces { shaped } else { PartShape::Point.patch_points() };
                let m = self.start(motions[i]);
                let s = m.friction_scale();
                let (a, _) = self.trace.mean_twist(at, &patch, m.velocity, m.spin, s * mu_g);
                self.predicted_forces[i] = [a[0] * mass / s, a[1] * mass / s];
            }
            if let Some(want) = part.force {
                let got = self.predicted_forces[i];
                lack = lack.max(nan_is_infinite(relative_force_error(want, got, problem.mu_m_g)));
            }
        }
        lack
    }
}

impl PartDynamics {
    /// Contact-point evaluations this request's correction would cost at
    /// most (every prediction on a cycle as long as `solution`'s).
    fn work(&self, problem: &Problem<'_>, solution: &Solution) -> u64 {
        let points = |shape: &PartShape| match shape {
            PartShape::Point => 1,
            _ => shape.patch_points().count as u64,
        };
        let forces: u64 =
            problem.parts.iter().map(|p| if self.params.patch_forces { points(&p.shape) } else { 1 }).sum();
        let curls: u64 = problem.curls.iter().map(|c| points(&c.shape)).sum();
        let pieces = self.params.cycle_pieces(solution.slots(), self.probe.params().slot_ticks);
        pieces.saturating_mul(forces + curls).saturating_mul(u64::from(self.params.steps) + 1)
    }

    fn start(&self, reported: PartMotion) -> PartMotion {
        match self.params.about {
            LinearizeAbout::Reported => reported,
            LinearizeAbout::Rest => PartMotion { friction: reported.friction, ..PartMotion::default() },
        }
    }
}

fn nan_is_infinite(x: f64) -> f64 {
    if x.is_nan() { f64::INFINITY } else { x }
}

/// A force's error as issue 25 measures it: |got − asked| over |asked| +
/// 0.005 μmg (the small requests' floor).
pub fn relative_force_error(asked: [f64; 2], got: [f64; 2], mu_m_g: f64) -> f64 {
    (got[0] - asked[0]).hypot(got[1] - asked[1]) / (asked[0].hypot(asked[1]) + 0.005 * mu_m_g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MAX_DYNAMICS_STEPS;
    use crate::cycle_mean_twist;
    use upm_solver::{SolverCapacity, SolverParams};

    const CENTERS: [[f64; 2]; 6] =
        [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5], [0.0, 0.6], [0.0, -0.6]];
    const MU_M_G: f64 = 0.1;

    /// Each part's force error (issue 25's measure) under `solution`,
    /// played finely (32 substeps) from `start`, with its friction.
    fn played_errors(
        problem: &Problem<'_>,
        solution: &Solution,
        start: &[PartMotion],
        mu_g: f64,
    ) -> Vec<f64> {
        let mut entries = [ScheduleEntry::default(); MAX_SLOTS];
        let n = fill_entries(solution, problem.centers, &mut entries);
        let mut motion = PlateMotion::new(MotionParams::default()).expect("motion");
        motion.set_schedule(&entries[..n]).expect("playable");
        let point = PartShape::Point.patch_points();
        problem
            .parts
            .iter()
            .zip(start)
            .map(|(p, m)| {
                let (a, _) = cycle_mean_twist(
                    &motion,
                    DriftParams::default(),
                    p.position,
                    &point,
                    m.velocity,
                    m.spin,
                    m.friction * mu_g,
                );
                // In the model's units, as the request is.
                let mass = MU_M_G / mu_g / m.friction;
                relative_force_error(p.force.expect("asked"), [a[0] * mass, a[1] * mass], MU_M_G)
            })
            .collect()
    }

    fn corrected(about: LinearizeAbout, start: &[PartMotion]) -> (Vec<f64>, Vec<f64>, Correction) {
        let (before, after, c, _) = corrected_then_played(about, start, start);
        (before, after, c)
    }

    /// Corrected believing `start`, played on `start` and on `real`.
    fn corrected_then_played(
        about: LinearizeAbout,
        start: &[PartMotion],
        real: &[PartMotion],
    ) -> (Vec<f64>, Vec<f64>, Correction, Vec<f64>) {
        let parts = [
            ForceConstraint { position: [0.5, 0.0], force: Some([0.003, 0.003]), shape: PartShape::Point },
            ForceConstraint { position: [-0.6, 0.2], force: Some([-0.003, 0.0012]), shape: PartShape::Point },
        ];
        let problem = Problem {
            mu_m_g: MU_M_G,
            k_max: 0.5,
            centers: &CENTERS,
            parts: &parts,
            curls: &[],
            k_bounds: &[],
        };
        let cap = SolverCapacity { parts: MAX_PARTS, curls: MAX_CURLS, centers: CENTERS.len() };
        let mut solver = Solver::new(cap, SolverParams::default());
        let mut solution = solver.new_solution();
        solver.solve(&problem, &mut solution).expect("solves");
        let params = PartDynamicsParams { steps: 3, about, ..PartDynamicsParams::default() };
        let probe = PlateMotion::new(MotionParams::default()).expect("motion");
        let mut dynamics =
            PartDynamics::new(params, probe, CENTERS.len(), solver.new_solution()).expect("params");
        let before = played_errors(&problem, &solution, start, params.mu_g);
        let c = dynamics.correct(&mut solver, &problem, start, &[], &mut solution);
        let on_real = played_errors(&problem, &solution, real, params.mu_g);
        (before, played_errors(&problem, &solution, start, params.mu_g), c, on_real)
    }

    #[test]
    fn the_correction_delivers_what_was_asked_when_played_finely() {
        // From rest: the paper's parts lose a fixed fraction of their
        // request to their own motion within the cycle; corrected, the
        // finely played cycle gives what they asked.
        let rest = [PartMotion::default(); 2];
        let (before, after, c) = corrected(LinearizeAbout::Rest, &rest);
        let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        assert!(worst(&before) > 0.05, "the uncorrected answer is off: {before:?}");
        assert!(worst(&after) < 0.3 * worst(&before), "{before:?} → {after:?} ({c:?})");
        assert!(c.kept > 0 && c.lack < c.lack_before, "{c:?}");
        // Sliding as vision reports: the answer is for the part as it moves.
        let sliding = [PartMotion { velocity: [0.004, -0.003], ..PartMotion::default() }; 2];
        let (before, after, c) = corrected(LinearizeAbout::Reported, &sliding);
        assert!(worst(&after) < worst(&before), "{before:?} → {after:?} ({c:?})");
        // From rest it would not have been: the reported state matters.
        let (_, at_rest, _) = corrected(LinearizeAbout::Rest, &sliding);
        assert!(worst(&after) < worst(&at_rest), "{after:?} vs {at_rest:?}");
    }

    #[test]
    fn a_part_that_grips_harder_is_corrected_for_its_own_friction() {
        // Requests in the model's units (the planner divided by the
        // friction), played on parts that grip 1.3 and 0.75 × the model.
        let real = [
            PartMotion { friction: 1.3, ..PartMotion::default() },
            PartMotion { friction: 0.75, ..PartMotion::default() },
        ];
        let (_, told, _) = corrected(LinearizeAbout::Rest, &real);
        // The same correction believing both parts have the model's μ,
        // judged on the real parts.
        let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let (_, _, _, unaware) =
            corrected_then_played(LinearizeAbout::Rest, &[PartMotion::default(); 2], &real);
        assert!(worst(&told) < 0.6 * worst(&unaware), "{told:?} against {unaware:?}");
        // Sliding as vision reports, the same.
        let moving = |friction| {
            [
                PartMotion { velocity: [0.004, -0.003], friction, ..PartMotion::default() },
                PartMotion { velocity: [-0.002, 0.003], friction, ..PartMotion::default() },
            ]
        };
        let real = moving(1.3);
        let (_, told, _) = corrected(LinearizeAbout::Reported, &real);
        let (_, _, _, unaware) = corrected_then_played(LinearizeAbout::Reported, &moving(1.0), &real);
        assert!(worst(&told) < worst(&unaware), "reported: {told:?} against {unaware:?}");
        // A friction that is not a finite positive scale counts as 1.
        let bad = [PartMotion { friction: f64::NAN, ..PartMotion::default() }; 2];
        let (_, _, c_bad) = corrected(LinearizeAbout::Rest, &bad);
        let (_, _, c_one) = corrected(LinearizeAbout::Rest, &[PartMotion::default(); 2]);
        assert_eq!(c_bad, c_one);
    }

    #[test]
    fn a_disc_asked_a_curl_spins_up_with_its_own_friction() {
        // The kept answer's predicted curl and force are the disc's, slid
        // with 1.3 × the model's μ, in the model's units (over 1.3).
        let disc = PartShape::Disc { radius: 0.05 };
        let at = [0.4, 0.1];
        let parts = [ForceConstraint { position: at, force: Some([0.002, 0.0]), shape: disc }];
        let curls = [CurlConstraint { position: at, curl: 0.003, shape: disc }];
        let problem = Problem {
            mu_m_g: MU_M_G,
            k_max: 0.5,
            centers: &CENTERS,
            parts: &parts,
            curls: &curls,
            k_bounds: &[],
        };
        let cap = SolverCapacity { parts: MAX_PARTS, curls: MAX_CURLS, centers: CENTERS.len() };
        let mut solver = Solver::new(cap, SolverParams::default());
        let mut solution = solver.new_solution();
        solver.solve(&problem, &mut solution).expect("solves");
        let params =
            PartDynamicsParams { steps: 2, about: LinearizeAbout::Rest, ..PartDynamicsParams::default() };
        let probe = PlateMotion::new(MotionParams::default()).expect("motion");
        let mut dynamics =
            PartDynamics::new(params, probe, CENTERS.len(), solver.new_solution()).expect("params");
        let grips = [PartMotion { friction: 1.3, ..PartMotion::default() }];
        dynamics.correct(&mut solver, &problem, &grips, &[0], &mut solution);
        let mut entries = [ScheduleEntry::default(); MAX_SLOTS];
        let n = fill_entries(&solution, &CENTERS, &mut entries);
        let mut motion = PlateMotion::new(MotionParams::default()).expect("motion");
        motion.set_schedule(&entries[..n]).expect("playable");
        let drift = DriftParams { follow: params.follow, substeps: u64::from(params.substeps) };
        let patch = disc.patch_points();
        let centroid = [at[0] + patch.centroid[0], at[1] + patch.centroid[1]];
        let (a, alpha) = cycle_mean_twist(&motion, drift, centroid, &patch, [0.0; 2], 0.0, 1.3 * params.mu_g);
        let mass = MU_M_G / params.mu_g / 1.3;
        let curl = dynamics.predicted_curls()[0].expect("a disc's curl");
        assert!(
            (curl - 2.0 * alpha * mass).abs() <= 1e-12 * curl.abs(),
            "{curl} against {}",
            2.0 * alpha * mass
        );
        let force = dynamics.predicted_forces()[0];
        for d in 0..2 {
            assert!((force[d] - a[d] * mass).abs() <= 1e-12 * MU_M_G, "{force:?} against {a:?}·{mass}");
        }
    }

    #[test]
    fn off_leaves_the_answer_and_bad_params_are_named() {
        let params = PartDynamicsParams::default();
        assert_eq!(params.steps, 0);
        let probe = PlateMotion::new(MotionParams::default()).expect("motion");
        let cap = SolverCapacity { parts: 4, curls: 1, centers: 4 };
        let mut solver = Solver::new(cap, SolverParams::default());
        let mut dynamics = PartDynamics::new(params, probe, 4, solver.new_solution()).expect("params");
        assert!(!dynamics.enabled());
        let mut solution = solver.new_solution();
        let problem = Problem {
            mu_m_g: MU_M_G,
            k_max: 0.5,
            centers: &CENTERS[..4],
            parts: &[],
            curls: &[],
            k_bounds: &[],
        };
        assert_eq!(dynamics.correct(&mut solver, &problem, &[], &[], &mut solution), Correction::default());
        for (bad, want) in [
            (PartDynamicsParams { steps: MAX_DYNAMICS_STEPS + 1, ..params }, PartDynamicsError::Steps),
            (PartDynamicsParams { mu_g: f64::NAN, ..params }, PartDynamicsError::MuG),
            (PartDynamicsParams { mu_g: 0.0, ..params }, PartDynamicsError::MuG),
            (PartDynamicsParams { substeps: 0, ..params }, PartDynamicsError::Substeps),
        ] {
            assert_eq!(bad.validate(), Err(want));
            assert!(want.to_string().starts_with("motion.part_dynamics."), "{want}");
        }
        let on = PartDynamicsParams { steps: 1, substeps: 32, ..params };
        let long = MotionParams { slot_ticks: 1000, ..MotionParams::default() };
        assert_eq!(on.trace_pieces(&long, 24), Err(PartDynamicsError::TraceTooLong { pieces: 768_000 }));
        assert_eq!(on.trace_pieces(&MotionParams::default(), 24), Ok(30_720));
    }
}
