//! The excitation: pairs of bursts, each burst one slot about one center
//! played over and over (an `ExplicitSchedule` of one slot), +k then −k, so
//! parts go out and come back. The excited centers are a spread subset of
//! the rig's (farthest-point order). Every frame of part states is kept;
//! [`Exciter::observations`] turns each part's track in each burst into a
//! fitted acceleration (a parabola through its positions) and each pair
//! into one [`Observation`].

use ipc_types::{ExplicitSchedule, ExplicitSlot, PartStates};
use upm_motion::{MotionParams, PlateFollow};

use crate::CalibrateError;
use crate::fit::{BurstMotion, FitCounts, Observation, RigModel};

/// Tunables, with defaults that fit in 60 s of rig time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExciteParams {
    /// Centers excited (spread over the rig's).
    pub centers: usize,
    /// Pairs of bursts.
    pub pairs: usize,
    /// |k| of every burst (lowered to 90 % of a center's playable bound).
    pub k: f64,
    pub burst_s: f64,
    /// Frames this soon after a burst starts are not used (latency, and the
    /// core swaps the motion at a cycle boundary).
    pub settle_s: f64,
    /// Fewest parts the fit accepts.
    pub min_parts: usize,
    /// A part this close to the plate's edge is at the fence (m).
    pub fence_margin: f64,
    /// A part this close to another may touch it (m).
    pub neighbour: f64,
    /// A part unseen this long has vanished (s).
    pub vanish_s: f64,
}

impl ExciteParams {
    /// Rig time the excitation takes (s).
    pub fn rig_seconds(&self) -> f64 {
        2.0 * self.pairs as f64 * self.burst_s
    }
}

impl Default for ExciteParams {
    /// Long, gentle bursts: the camera's 0.5 mm noise turns a 0.3 s burst's
    /// push by about 3° (its acceleration goes as the burst's length
    /// squared), and a line fitted through such pushes misplaces a center
    /// 1.2 m away by centimetres. Measured on a nominal plate (lock-step,
    /// the `calibrate` scenario's parts, the plate at 64 substeps): 80
    /// pairs of 0.3 s at k 0.35 fitted a twist map 6.9 % off the identity,
    /// 48 pairs of 0.6 s at k 0.2 1.1 %.
    /// The part's own speed is then large, and the fit's model reads it.
    fn default() -> Self {
        Self {
            centers: 8,
            pairs: 48,
            k: 0.2,
            burst_s: 0.6,
            settle_s: 0.06,
            min_parts: 3,
            fence_margin: 0.03,
            neighbour: 0.04,
            vanish_s: 0.5,
        }
    }
}

/// The rig as the controller knows it, and the tunables.
#[derive(Debug, Clone)]
pub struct CalibrateSetup {
    pub centers: Vec<[f64; 2]>,
    /// Per center, the |k| it can play (the core's bounds).
    pub k_bounds: Vec<f64>,
    pub motion: MotionParams,
    pub mu_m_g: f64,
    /// The model's μ·g (m/s²).
    pub mu_g: f64,
    pub plate_half_extent: [f64; 2],
    pub actuators: u32,
    /// Position gain α of vision's tracker (its α-β filter smooths the
    /// curvature the fit measures: each position is taken back to the
    /// detection it came from); None: positions are raw detections.
    pub tracker_alpha: Option<f64>,
    /// Vision's frame period (s): a gap longer than 1.5 of it means a
    /// frame the fit did not see, and the tracker's step cannot be undone.
    pub frame_period_s: f64,
    /// The calibration the core is playing through, if any.
    pub prior_correction: Option<[[f64; 3]; 3]>,
    /// How the plate follows its command: the drives as specified.
    pub follow: PlateFollow,
    pub params: ExciteParams,
}

/// One frame: (id, class, position, velocity) of every part.
#[derive(Debug, Clone)]
struct Frame {
    t: f64,
    parts: Vec<(u32, u32, [f64; 2], [f64; 2])>,
}

/// What to do after a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Play `out` (it was filled).
    Play,
    /// Every burst is done: stop playing and fit.
    Done,
}

#[derive(Debug, Clone)]
pub struct Exciter {
    setup: CalibrateSetup,
    /// Excited centers, in play order.
    excited: Vec<usize>,
    t0: Option<f64>,
    frames: Vec<Frame>,
    /// Parts on the first frame.
    start_count: usize,
    /// Since when fewer parts than that are seen.
    short_since: Option<f64>,
}

impl Exciter {
    pub fn new(setup: CalibrateSetup) -> Result<Self, CalibrateError> {
        let p = &setup.params;
        if setup.centers.is_empty() || setup.k_bounds.len() != setup.centers.len() {
            return Err(CalibrateError::Setup("the rig's centers and their k bounds"));
        }
        if !(p.k > 0.0 && p.k < 1.0 && p.burst_s > p.settle_s && p.settle_s >= 0.0 && p.pairs > 0) {
            return Err(CalibrateError::Setup("excitation parameters"));
        }
        // Farthest-point order from the center farthest from the plate's middle.
        let n = setup.centers.len();
        let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
        let mut excited = vec![
            (0..n)
                .max_by(|&a, &b| d(setup.centers[a], [0.0; 2]).total_cmp(&d(setup.centers[b], [0.0; 2])))
                .unwrap_or(0),
        ];
        while excited.len() < p.centers.min(n) {
            let next = (0..n).filter(|j| !excited.contains(j)).max_by(|&a, &b| {
                let near = |j: usize| {
                    excited
                        .iter()
                        .map(|&e| d(setup.centers[j], setup.centers[e]))
                        .fold(f64::INFINITY, f64::min)
                };
                near(a).total_cmp(&near(b))
            });
            match next {
                Some(j) => excited.push(j),
                None => break,
            }
        }
        Ok(Self { setup, excited, t0: None, frames: Vec::new(), start_count: 0, short_since: None })
    }

    /// Rig time the excitation takes (s).
    pub fn rig_seconds(&self) -> f64 {
        self.setup.params.rig_seconds()
    }

    /// The centers excited (indices into the rig's).
    pub fn excited(&self) -> &[usize] {
        &self.excited
    }

    fn burst(&self, b: usize) -> (usize, f64) {
        let center = self.excited[(b / 2) % self.excited.len()];
        let k = self.setup.params.k.min(0.9 * self.setup.k_bounds[center]);
        (center, if b.is_multiple_of(2) { k } else { -k })
    }

    /// Take the newest part states (time `t`, s, from their stamp) and fill
    /// `out` with the slot to play now. Errors: too few parts, parts at the
    /// fence, a part that vanished, a non-finite value (naming the field).
    pub fn on_frame(
        &mut self,
        states: &PartStates,
        t: f64,
        out: &mut ExplicitSchedule,
    ) -> Result<Step, CalibrateError> {
        let p = self.setup.params;
        let mut frame = Frame { t, parts: Vec::with_capacity(states.parts().len()) };
        for (i, s) in states.parts().iter().enumerate() {
            for (field, v) in [("x", s.x), ("y", s.y), ("vx", s.vx), ("vy", s.vy)] {
                if !v.is_finite() {
                    return Err(CalibrateError::NonFinite { index: i, field });
                }
            }
            frame.parts.push((s.id, s.class, [s.x, s.y], [s.vx, s.vy]));
        }
        let t0 = match self.t0 {
            Some(t0) => t0,
            None => {
                if frame.parts.len() < p.min_parts {
                    return Err(CalibrateError::TooFewParts { seen: frame.parts.len(), need: p.min_parts });
                }
                let half = self.setup.plate_half_extent;
                let pinned = frame.parts.iter().filter(|q| at_fence(q.2, half, p.fence_margin)).count();
                if 2 * pinned > frame.parts.len() {
                    return Err(CalibrateError::Pinned { pinned, parts: frame.parts.len() });
                }
                self.start_count = frame.parts.len();
                self.t0 = Some(t);
                t
            }
        };
        // A tracker may lose a part and find it again under a new id; a
        // part gone for good leaves fewer parts seen.
        if frame.parts.len() < self.start_count {
            let since = *self.short_since.get_or_insert(t);
            if t - since > p.vanish_s {
                return Err(CalibrateError::Vanished {
                    seen: frame.parts.len(),
                    parts: self.start_count,
                    at_s: t - t0,
                });
            }
        } else {
            self.short_since = None;
        }
        let b = ((t - t0) / p.burst_s).floor() as usize;
        self.frames.push(frame);
        if b >= 2 * p.pairs {
            return Ok(Step::Done);
        }
        let (center, k) = self.burst(b);
        out.clear();
        let _ = out.push(ExplicitSlot::new(center as u32, k));
        Ok(Step::Play)
    }

    /// Every (pair, part) the fit can use, and how many were dropped.
    pub fn observations(&self) -> (Vec<Observation>, u32) {
        let p = self.setup.params;
        let Some(t0) = self.t0 else { return (Vec::new(), 0) };
        let half = self.setup.plate_half_extent;
        let (mut obs, mut dropped) = (Vec::new(), 0u32);
        let mut ids: Vec<(u32, u32)> =
            self.frames.iter().flat_map(|f| f.parts.iter().map(|q| (q.0, q.1))).collect();
        ids.sort_unstable();
        ids.dedup();
        for pair in 0..p.pairs {
            let (center, k) = self.burst(2 * pair);
            for &(id, class) in &ids {
                let mut fits = [None; 2];
                let mut clean = true;
                for (h, slot) in fits.iter_mut().enumerate() {
                    let start = t0 + (2 * pair + h) as f64 * p.burst_s;
                    let mut track = Vec::new();
                    for (i, f) in self.frames.iter().enumerate() {
                        if !(f.t >= start + p.settle_s && f.t < start + p.burst_s) {
                            continue;
                        }
                        let Some(&(_, _, q, _)) = f.parts.iter().find(|q| q.0 == id) else { continue };
                        let crowded = f
                            .parts
                            .iter()
                            .any(|o| o.0 != id && (o.2[0] - q[0]).hypot(o.2[1] - q[1]) < p.neighbour);
                        clean &= !crowded && !at_fence(q, half, p.fence_margin);
                        if let Some(z) = self.detection(i, id) {
                            track.push((f.t - start, z));
                        }
                    }
                    *slot = parabola(&track);
                }
                match (fits, clean) {
                    ([None, None], _) => {}
                    ([Some(a), Some(b)], true) => obs.push(Observation {
                        center,
                        k,
                        class,
                        position: core::array::from_fn(|d| (a.position[d] + b.position[d]) / 2.0),
                        acceleration: core::array::from_fn(|d| (a.acceleration[d] - b.acceleration[d]) / 2.0),
                        bursts: [a, b],
                    }),
                    _ => dropped += 1,
                }
            }
        }
        (obs, dropped)
    }

    /// The detection behind part `id`'s position in frame `i`: the tracker
    /// predicted q + v·dt from the previous frame and moved α of the way
    /// to the detection. None without a previous frame of that part.
    fn detection(&self, i: usize, id: u32) -> Option<[f64; 2]> {
        let f = &self.frames[i];
        let &(_, _, q, _) = f.parts.iter().find(|q| q.0 == id)?;
        let Some(alpha) = self.setup.tracker_alpha else { return Some(q) };
        let prev = self.frames.get(i.checked_sub(1)?)?;
        let &(_, _, q0, v0) = prev.parts.iter().find(|q| q.0 == id)?;
        let dt = f.t - prev.t;
        if dt > 1.5 * self.setup.frame_period_s {
            return None;
        }
        let pred = [q0[0] + v0[0] * dt, q0[1] + v0[1] * dt];
        Some([pred[0] + (q[0] - pred[0]) / alpha, pred[1] + (q[1] - pred[1]) / alpha])
    }

    /// The rig as the fit sees it.
    pub fn rig_model(&self) -> RigModel {
        let s = &self.setup;
        RigModel {
            centers: s.centers.clone(),
            plate_half_extent: s.plate_half_extent,
            mu_m_g: s.mu_m_g,
            mu_g: s.mu_g,
            motion: s.motion,
            actuators: s.actuators,
            prior_correction: s.prior_correction,
            follow: s.follow,
        }
    }

    /// Fit what was seen (after [`Step::Done`]).
    pub fn fit(&self) -> Result<rig_config::PlateCalibration, CalibrateError> {
        let (obs, dropped) = self.observations();
        let counts = FitCounts {
            bursts: 2 * self.setup.params.pairs as u32,
            rig_seconds: self.rig_seconds(),
            dropped,
        };
        crate::fit::fit(&self.rig_model(), &obs, counts)
    }
}

fn at_fence(q: [f64; 2], half: [f64; 2], margin: f64) -> bool {
    q[0].abs() > half[0] - margin || q[1].abs() > half[1] - margin
}

/// Least-squares q(t) = q0 + v·t + ½·a·t² per axis, t from the frames'
/// mean time. None with fewer than 5 points.
fn parabola(track: &[(f64, [f64; 2])]) -> Option<BurstMotion> {
    if track.len() < 5 {
        return None;
    }
    let tm = track.iter().map(|p| p.0).sum::<f64>() / track.len() as f64;
    let mut n = nalgebra::Matrix3::<f64>::zeros();
    let mut b = [nalgebra::Vector3::<f64>::zeros(); 2];
    for &(t, q) in track {
        let s = t - tm;
        let row = nalgebra::Vector3::new(1.0, s, 0.5 * s * s);
        n += row * row.transpose();
        for d in 0..2 {
            b[d] += row * q[d];
        }
    }
    let inv = n.try_inverse()?;
    let (x, y) = (inv * b[0], inv * b[1]);
    let span = [track.first()?.0 - tm, track.last()?.0 - tm];
    Some(BurstMotion { position: [x[0], y[0]], velocity: [x[1], y[1]], acceleration: [x[2], y[2]], span })
}

#[cfg(test)]
mod tests {
    use ipc_types::PartState;

    use super::*;

    fn setup() -> CalibrateSetup {
        CalibrateSetup {
            centers: crate::fit::TEST_CENTERS.to_vec(),
            k_bounds: vec![0.9; 7],
            motion: MotionParams::default(),
            mu_m_g: 0.1,
            mu_g: 0.25 * 9.81,
            plate_half_extent: [1.0, 0.5],
            actuators: 4,
            tracker_alpha: None,
            frame_period_s: 1.0 / 30.0,
            prior_correction: None,
            follow: PlateFollow::Exact,
            params: ExciteParams { pairs: 4, ..ExciteParams::default() },
        }
    }

    fn states(at: &[[f64; 2]]) -> PartStates {
        let mut s = PartStates::new();
        for (i, p) in at.iter().enumerate() {
            let _ = s.push(PartState { id: i as u32 + 1, x: p[0], y: p[1], ..PartState::ZERO });
        }
        s
    }

    const THREE: [[f64; 2]; 3] = [[0.0, 0.0], [0.3, 0.1], [-0.3, -0.1]];

    #[test]
    fn bursts_alternate_their_sign_over_spread_centers_then_stop() {
        let mut e = Exciter::new(setup()).expect("exciter");
        assert_eq!(e.excited().len(), 7);
        // Farthest from the middle first, then as far from those as can be.
        assert_eq!(e.excited()[0], 4);
        let mut out = ExplicitSchedule::new();
        let (mut seen, mut done) = (Vec::new(), false);
        for f in 0..300 {
            let t = f as f64 / 30.0;
            match e.on_frame(&states(&THREE), t, &mut out).expect("frame") {
                Step::Play => seen.push((t, out.slots()[0])),
                Step::Done => {
                    assert!(t >= e.rig_seconds(), "done at {t}");
                    done = true;
                    break;
                }
            }
        }
        assert!(done, "still playing after {} s of rig time", e.rig_seconds());
        let at = |t: f64| seen.iter().find(|s| s.0 >= t).map(|s| s.1).expect("slot");
        let (burst, k) = (setup().params.burst_s, setup().params.k);
        let (a, b, c) = (at(0.0), at(burst + 0.01), at(2.0 * burst + 0.01));
        assert_eq!((a.center_index, b.center_index), (4, 4));
        assert!(a.k == k && b.k == -k && c.center_index != 4, "{a:?} {b:?} {c:?}");
    }

    #[test]
    fn bad_input_is_refused_in_one_line_naming_it() {
        let mut out = ExplicitSchedule::new();
        let mut e = Exciter::new(setup()).expect("exciter");
        let e1 = e.on_frame(&states(&THREE[..2]), 0.0, &mut out).expect_err("two parts");
        assert_eq!(e1.to_string(), "too few parts on the plate: 2 seen, the fit needs at least 3");
        let mut e = Exciter::new(setup()).expect("exciter");
        let mut s = states(&THREE);
        s.parts_mut()[1].y = f64::NAN;
        let e2 = e.on_frame(&s, 0.0, &mut out).expect_err("nan");
        assert_eq!(e2.to_string(), "part_states.parts[1].y is not finite");
        let mut e = Exciter::new(setup()).expect("exciter");
        let e3 =
            e.on_frame(&states(&[[0.99, 0.0], [0.0, 0.49], [0.0, 0.0]]), 0.0, &mut out).expect_err("fence");
        assert!(e3.to_string().starts_with("parts pinned at the fence: 2 of 3"), "{e3}");
        // A part lost for a moment is no error; gone for good, it is.
        let mut e = Exciter::new(setup()).expect("exciter");
        e.on_frame(&states(&THREE), 0.0, &mut out).expect("start");
        e.on_frame(&states(&THREE[..2]), 0.1, &mut out).expect("a moment");
        e.on_frame(&states(&THREE), 0.2, &mut out).expect("back");
        e.on_frame(&states(&THREE[..2]), 0.3, &mut out).expect("again");
        let e4 = e.on_frame(&states(&THREE[..2]), 0.9, &mut out).expect_err("gone");
        assert!(
            e4.to_string().starts_with("a part vanished 0.90 s into the calibration: 2 of 3 seen"),
            "{e4}"
        );
        // Parts that never move: nothing to fit.
        let mut e = Exciter::new(setup()).expect("exciter");
        let mut f = 0;
        while e.on_frame(&states(&THREE), f as f64 / 30.0, &mut out).expect("frame") == Step::Play {
            f += 1;
        }
        let e5 = e.fit().expect_err("still");
        assert!(
            e5.to_string().starts_with("the plate's turning is not determined")
                || e5.to_string().starts_with("too little motion"),
            "{e5}"
        );
    }
}
