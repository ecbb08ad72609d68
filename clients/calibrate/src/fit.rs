//! The fit: from what each part did in each pair of bursts to the plate's
//! effective turning and its friction.
//!
//! 1. **Effective centers.** A slot about C pushes a part at P along
//!    R90(P − C′), C′ the center the plate really turns about: the part's
//!    acceleration A is perpendicular to P − C′, so A·C′ = A·P. Every part
//!    seen in a pair of bursts about one center gives one such line; C′ is
//!    their least-squares meeting point (outliers beyond 3 MADs dropped).
//! 2. **The plate's turning.** To first order the plate's true twist is a
//!    fixed 3 × 3 map M of the commanded one, so (c′_y, −c′_x, 1) ∥
//!    M·(c_y, −c_x, 1) (a homography of the centers; M₃₃ = 1). M = I + E is
//!    fitted by Gauss–Newton over the located centers (≥ 4), each weighed
//!    by its own uncertainty, with a prior pulling E towards 0: centers far
//!    from every part are located loosely, and what they cannot fix stays
//!    at the identity. The prior is narrow ([`MAP_PRIOR_SD`]): a map fitted
//!    freely to the centers turns some plates further off than none. The
//!    correction is M⁻¹.
//! 3. **Friction.** The model's own acceleration of the part under the
//!    same pair of slots about C′, read where and as fast as the part went
//!    (`upm_motion::cycle_mean_twist` on the plate as the drives
//!    follow it, nominal μ; step 1 reads
//!    it the same way), scales to the seen one by
//!    s = (A·a_model)/|a_model|². Then s = σ_class·(1 + Σ c_k·term_k(P)) is
//!    fitted by Gauss–Newton, with a weak pull of c towards 0 (a map is only
//!    known where parts went), outliers beyond 3 MADs dropped. Then the map
//!    is chosen on held-out observations: none, linear or full, whichever
//!    predicts the left-out fold best (a richer one by 5 % at least), and
//!    refitted: where the parts do not determine a quadratic map, a fitted
//!    one bends where no part went.
//!
//! The difference of the two bursts of a pair (+k then −k about one center)
//! cancels what the model does not hold (a bias common to both) to first
//! order; the drag of the part's own velocity is in the model.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix};
use rig_config::plate_calibration::{
    CalibrationReport, ClassFriction, FORMAT, FRICTION_TERMS, PlateCalibration, friction_terms,
};
use upm_motion::{DriftParams, MotionParams, PlateFollow, PlateMotion, ScheduleEntry, cycle_mean_twist};
use upm_solver::PartShape;

use crate::CalibrateError;

/// One part in one pair of bursts.
#[derive(Debug, Clone, Copy)]
pub struct Observation {
    /// Which excited center (index into the rig's centers).
    pub center: usize,
    pub k: f64,
    pub class: u32,
    /// Mean position over the pair (m).
    pub position: [f64; 2],
    /// Half the difference of the two bursts' accelerations (m/s²).
    pub acceleration: [f64; 2],
    /// How the part moved in each burst (+k, then −k): the model is read
    /// at the velocities it really had.
    pub bursts: [BurstMotion; 2],
}

/// A part's motion through one burst, from the parabola fitted to it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BurstMotion {
    /// Position (m), velocity (m/s) and acceleration (m/s²) of the fitted
    /// parabola at the mean time of the frames used.
    pub position: [f64; 2],
    pub velocity: [f64; 2],
    pub acceleration: [f64; 2],
    /// First and last frame used, relative to that mean time (s).
    pub span: [f64; 2],
}

impl BurstMotion {
    /// A part at rest at `position` through the whole burst.
    pub fn at_rest(position: [f64; 2]) -> Self {
        Self { position, ..Self::default() }
    }
}

/// What the fit needs of the rig.
#[derive(Debug, Clone)]
pub struct RigModel {
    pub centers: Vec<[f64; 2]>,
    pub plate_half_extent: [f64; 2],
    pub mu_m_g: f64,
    /// The model's μ·g (m/s²): the planner's μmg over its part mass.
    pub mu_g: f64,
    pub motion: MotionParams,
    pub actuators: u32,
    /// The correction the core played the excitation through (its loaded
    /// calibration), which the new one replaces.
    pub prior_correction: Option<[[f64; 3]; 3]>,
    /// How the plate follows its command (the drives as specified).
    pub follow: PlateFollow,
}

fn median(v: &mut [f64]) -> f64 {
    upm_stats::median(v).unwrap_or(f64::NAN)
}

/// Indices to keep: |r| within 3 scaled MADs (and at least `floor`).
fn inliers(r: &[f64], floor: f64) -> Vec<bool> {
    let mut a: Vec<f64> = r.iter().map(|x| x.abs()).collect();
    let cut = (3.0 * 1.4826 * median(&mut a)).max(floor);
    r.iter().map(|x| x.abs() <= cut).collect()
}

/// Step 1: C′ for the observations of one center, refined so that the
/// model's own direction of push (which leans off R90(P − C′) a little:
/// the slot's fast and slow phases do not cancel exactly) meets every
/// seen one; also the sine residuals against it.
fn effective_center(rig: &RigModel, obs: &[&Observation]) -> Option<CenterFit> {
    let mut c = perpendicular_center(obs)?;
    let sine = |c: [f64; 2], o: &Observation| -> Option<f64> {
        let m = model_acceleration(rig, c, o)?;
        let a = o.acceleration;
        Some((m[0] * a[1] - m[1] * a[0]) / (m[0].hypot(m[1]) * a[0].hypot(a[1])).max(1e-300))
    };
    let mut keep = vec![true; obs.len()];
    let h = 1e-4;
    let mut info = [[0.0; 2]; 2];
    for _ in 0..4 {
        let (mut n, mut b) = ([[0.0; 2]; 2], [0.0; 2]);
        for (o, _) in obs.iter().zip(&keep).filter(|(_, k)| **k) {
            let r = sine(c, o)?;
            let j = [(sine([c[0] + h, c[1]], o)? - r) / h, (sine([c[0], c[1] + h], o)? - r) / h];
            for x in 0..2 {
                for y in 0..2 {
                    n[x][y] += j[x] * j[y];
                }
                b[x] -= j[x] * r;
            }
        }
        let det = n[0][0] * n[1][1] - n[0][1] * n[1][0];
        if !(det > 0.0) {
            return None;
        }
        let step = [(n[1][1] * b[0] - n[0][1] * b[1]) / det, (n[0][0] * b[1] - n[1][0] * b[0]) / det];
        c = [c[0] + step[0], c[1] + step[1]];
        let res: Vec<f64> = obs.iter().map(|o| sine(c, o).unwrap_or(f64::NAN)).collect();
        let used = keep.iter().filter(|k| **k).count();
        let ss: f64 = res.iter().zip(&keep).filter(|(_, k)| **k).map(|(r, _)| r * r).sum();
        let var = (ss / (used as f64 - 2.0).max(1.0)).max(1e-18);
        info = n.map(|row| row.map(|x| x / var));
        keep = inliers(&res, 0.5f64.to_radians().sin());
    }
    let residuals = obs.iter().map(|o| sine(c, o).unwrap_or(f64::NAN)).collect();
    Some(CenterFit { center: c, residuals, info })
}

/// C′ as the least-squares meeting point of the lines through each P
/// perpendicular to its push (the paper's field), outliers dropped.
fn perpendicular_center(obs: &[&Observation]) -> Option<[f64; 2]> {
    let mut keep = vec![true; obs.len()];
    let mut out = None;
    for _ in 0..3 {
        let (mut n, mut b) = (Matrix3::<f64>::zeros(), [0.0; 2]);
        let mut used = 0;
        for (o, _) in obs.iter().zip(&keep).filter(|(_, k)| **k) {
            let a = o.acceleration;
            let len = a[0].hypot(a[1]);
            if len == 0.0 {
                continue;
            }
            let u = [a[0] / len, a[1] / len];
            let rhs = u[0] * o.position[0] + u[1] * o.position[1];
            for r in 0..2 {
                for c in 0..2 {
                    n[(r, c)] += u[r] * u[c];
                }
                b[r] += u[r] * rhs;
            }
            used += 1;
        }
        // Two lines that are not nearly parallel.
        let det = n[(0, 0)] * n[(1, 1)] - n[(0, 1)] * n[(1, 0)];
        if used < 2 || det < 0.01 * (used * used) as f64 {
            return None;
        }
        let c = [(n[(1, 1)] * b[0] - n[(0, 1)] * b[1]) / det, (n[(0, 0)] * b[1] - n[(1, 0)] * b[0]) / det];
        let res: Vec<f64> = obs
            .iter()
            .map(|o| {
                let a = o.acceleration;
                let d = [o.position[0] - c[0], o.position[1] - c[1]];
                (a[0] * d[0] + a[1] * d[1]) / (a[0].hypot(a[1]) * d[0].hypot(d[1])).max(1e-300)
            })
            .collect();
        keep = inliers(&res, 0.5f64.to_radians().sin());
        out = Some(c);
    }
    out
}

/// Step 1's answer: C′, each observation's sine residual against the
/// model's push there, and C′'s information matrix (1/m²).
struct CenterFit {
    center: [f64; 2],
    residuals: Vec<f64>,
    info: [[f64; 2]; 2],
}

/// A located effective center: the commanded one, the seen one, and its
/// information matrix (inverse covariance, 1/m²).
#[derive(Debug, Clone, Copy)]
struct Located {
    center: [f64; 2],
    seen: [f64; 2],
    info: [[f64; 2]; 2],
}

/// The prior's width on E: how far the fit lets the plate's map leave the
/// identity on what the centers say. Narrower than the maps of rigs built
/// to ±10 mm and ±5 % (up to 0.03 per element), because a map fitted at
/// that width turned the plate further off than no correction on 11 of
/// the bench's 50 truths: evidently the centers' errors go beyond the
/// spread they are weighed by. Chosen on 20 truths apart from the bench's
/// (the median turning error over widths 0.001–0.03; BENCHMARKS.md).
const MAP_PRIOR_SD: f64 = 0.003;

/// C′ of `c` under M = I + E (E₃₃ = 0; `e` row-major without it).
fn mapped(e: &[f64; 8], c: [f64; 2]) -> [f64; 2] {
    let xi = [c[1], -c[0], 1.0];
    let m = [[1.0 + e[0], e[1], e[2]], [e[3], 1.0 + e[4], e[5]], [e[6], e[7], 1.0]];
    let v: [f64; 3] = core::array::from_fn(|r| m[r][0] * xi[0] + m[r][1] * xi[1] + m[r][2] * xi[2]);
    [-v[1] / v[2], v[0] / v[2]]
}

/// Step 2: E by Gauss–Newton on every located center, each weighed by how
/// well it is known, with a Gaussian prior E ~ 0 ([`MAP_PRIOR_SD`]): what
/// the data do not fix stays at the identity instead of following noise.
fn plate_map(located: &[Located]) -> Option<Matrix3<f64>> {
    if located.len() < 4 {
        return None;
    }
    let mut e = [0.0; 8];
    let h = 1e-7;
    let w = 1.0 / (MAP_PRIOR_SD * MAP_PRIOR_SD);
    for _ in 0..6 {
        let mut jtj = SMatrix::<f64, 8, 8>::identity() * w;
        let mut jtr = SMatrix::<f64, 8, 1>::from_fn(|i, _| -e[i] * w);
        for l in located {
            let p = mapped(&e, l.center);
            let r = [l.seen[0] - p[0], l.seen[1] - p[1]];
            let mut j = [[0.0; 8]; 2];
            for k in 0..8 {
                let mut ek = e;
                ek[k] += h;
                let q = mapped(&ek, l.center);
                j[0][k] = (q[0] - p[0]) / h;
                j[1][k] = (q[1] - p[1]) / h;
            }
            for a in 0..8 {
                for x in 0..2 {
                    for y in 0..2 {
                        jtr[a] += j[x][a] * l.info[x][y] * r[y];
                        for b in 0..8 {
                            jtj[(a, b)] += j[x][a] * l.info[x][y] * j[y][b];
                        }
                    }
                }
            }
        }
        let step = jtj.try_inverse()? * jtr;
        for k in 0..8 {
            e[k] += step[k];
        }
    }
    Some(Matrix3::new(1.0 + e[0], e[1], e[2], e[3], 1.0 + e[4], e[5], e[6], e[7], 1.0))
}

/// The model's mean acceleration of the part seen in `o` under a slot
/// about `c`, half the difference of the +k and −k bursts. Each burst is
/// read at a few times through it, at the position and velocity the part
/// had then: a part moving at a good fraction of the plate's speed feels
/// friction turned and weakened, and the two bursts do not cancel that
/// (the long bursts `ExciteParams` plays make parts fast).
fn model_acceleration(rig: &RigModel, c: [f64; 2], o: &Observation) -> Option<[f64; 2]> {
    const READS: usize = 4;
    let mut motion = PlateMotion::new(rig.motion).ok()?;
    let point = PartShape::Point.patch_points();
    let mut burst = |k: f64, b: &BurstMotion| -> Option<[f64; 2]> {
        motion.set_schedule(&[ScheduleEntry { center: c, k }]).ok()?;
        let mut sum = [0.0; 2];
        for i in 0..READS {
            let t = b.span[0] + (b.span[1] - b.span[0]) * (i as f64 + 0.5) / READS as f64;
            let at: [f64; 2] =
                core::array::from_fn(|d| b.position[d] + b.velocity[d] * t + 0.5 * b.acceleration[d] * t * t);
            let v: [f64; 2] = core::array::from_fn(|d| b.velocity[d] + b.acceleration[d] * t);
            let drift = DriftParams { follow: rig.follow, ..DriftParams::default() };
            let a = cycle_mean_twist(&motion, drift, at, &point, v, 0.0, rig.mu_g).0;
            sum = [sum[0] + a[0] / READS as f64, sum[1] + a[1] / READS as f64];
        }
        Some(sum)
    };
    let (plus, minus) = (burst(o.k, &o.bursts[0])?, burst(-o.k, &o.bursts[1])?);
    Some([(plus[0] - minus[0]) / 2.0, (plus[1] - minus[1]) / 2.0])
}

/// Step 3's model: s = σ_class·(1 + c·t).
struct FrictionFit {
    classes: Vec<u32>,
    sigma: Vec<f64>,
    c: [f64; FRICTION_TERMS],
}

impl FrictionFit {
    fn predict(&self, class: u32, t: &[f64; FRICTION_TERMS]) -> f64 {
        let i = self.classes.iter().position(|&c| c == class).unwrap_or(0);
        self.sigma[i] * (1.0 + t.iter().zip(&self.c).map(|(a, b)| a * b).sum::<f64>())
    }
}

/// Gauss–Newton on (σ per class, c); `pull[k]` weighs c_k towards 0.
fn fit_friction(
    data: &[(u32, [f64; FRICTION_TERMS], f64)],
    pull: [f64; FRICTION_TERMS],
) -> Option<(FrictionFit, DMatrix<f64>)> {
    let mut classes: Vec<u32> = data.iter().map(|d| d.0).collect();
    classes.sort_unstable();
    classes.dedup();
    let sigma = classes
        .iter()
        .map(|&c| {
            let mut v: Vec<f64> = data.iter().filter(|d| d.0 == c).map(|d| d.2).collect();
            median(&mut v)
        })
        .collect();
    let mut fit = FrictionFit { classes, sigma, c: [0.0; FRICTION_TERMS] };
    let n = fit.classes.len() + FRICTION_TERMS;
    let mut cov = DMatrix::zeros(n, n);
    for _ in 0..8 {
        let mut jtj = DMatrix::<f64>::zeros(n, n);
        let mut jtr = DVector::<f64>::zeros(n);
        let mut ss = 0.0;
        for (class, t, s) in data {
            let ci = fit.classes.iter().position(|c| c == class)?;
            let map = 1.0 + t.iter().zip(&fit.c).map(|(a, b)| a * b).sum::<f64>();
            let r = s - fit.sigma[ci] * map;
            ss += r * r;
            let mut j = vec![0.0; n];
            j[ci] = map;
            for k in 0..FRICTION_TERMS {
                j[fit.classes.len() + k] = fit.sigma[ci] * t[k];
            }
            for a in 0..n {
                jtr[a] += j[a] * r;
                for b in 0..n {
                    jtj[(a, b)] += j[a] * j[b];
                }
            }
        }
        for k in 0..FRICTION_TERMS {
            let i = fit.classes.len() + k;
            jtj[(i, i)] += pull[k];
            jtr[i] -= pull[k] * fit.c[k];
        }
        let inv = jtj.clone().try_inverse()?;
        let step = &inv * &jtr;
        for (i, s) in fit.sigma.iter_mut().enumerate() {
            *s += step[i];
        }
        for k in 0..FRICTION_TERMS {
            fit.c[k] += step[fit.classes.len() + k];
        }
        let dof = (data.len() as f64 - n as f64).max(1.0);
        cov = inv * (ss / dof);
    }
    Some((fit, cov))
}

/// The friction maps tried, simplest first: none, linear (u, v), full.
const MAP_TERMS: [usize; 3] = [0, 2, FRICTION_TERMS];

/// Per-term pull for a map of the first `terms` terms: a weak one (a map is
/// only known where parts went) on those, a pin to 0 on the rest.
fn pull_for(terms: usize, n: usize) -> [f64; FRICTION_TERMS] {
    core::array::from_fn(|k| if k < terms { 1e-3 * n as f64 } else { 1e9 * n as f64 })
}

/// Which map the data support, chosen on held-out observations (4 folds):
/// the trimmed mean relative error of s on the fold each was left out of. A
/// richer map must do 5 % better than the simpler one to be chosen: a map
/// fitted where the parts do not say enough bends where no part went.
fn map_pull(data: &[(u32, [f64; FRICTION_TERMS], f64)]) -> [f64; FRICTION_TERMS] {
    const FOLDS: usize = 4;
    let score = |terms: usize| -> Option<f64> {
        let mut err = Vec::with_capacity(data.len());
        for fold in 0..FOLDS {
            let train: Vec<_> =
                data.iter().enumerate().filter(|(i, _)| i % FOLDS != fold).map(|(_, d)| *d).collect();
            let (f, _) = fit_friction(&train, pull_for(terms, train.len()))?;
            for (_, (c, t, s)) in data.iter().enumerate().filter(|(i, _)| i % FOLDS == fold) {
                // A class absent from the training folds predicts nothing.
                if f.classes.contains(c) {
                    err.push(((s - f.predict(*c, t)) / f.predict(*c, t)).abs());
                }
            }
        }
        // Mean of the smallest 90 %: collisions and fence contacts are
        // outliers, a wrong map is a bias everywhere.
        err.sort_by(f64::total_cmp);
        let kept = &err[..(err.len() * 9).div_ceil(10)];
        Some(kept.iter().sum::<f64>() / kept.len() as f64).filter(|m| m.is_finite())
    };
    let mut best = (MAP_TERMS[0], f64::INFINITY);
    for terms in MAP_TERMS {
        if let Some(e) = score(terms)
            && e < 0.95 * best.1
        {
            best = (terms, e);
        }
    }
    pull_for(best.0, data.len())
}

/// Counts the fit reports.
#[derive(Debug, Clone, Copy, Default)]
pub struct FitCounts {
    pub bursts: u32,
    pub rig_seconds: f64,
    /// Observations dropped before the fit (fence, neighbours, too few frames).
    pub dropped: u32,
}

/// Steps 1–3; the file `upm calibrate plate` writes.
pub fn fit(
    rig: &RigModel,
    obs: &[Observation],
    counts: FitCounts,
) -> Result<PlateCalibration, CalibrateError> {
    let mut excited: Vec<usize> = obs.iter().map(|o| o.center).collect();
    excited.sort_unstable();
    excited.dedup();
    let mut located = Vec::new();
    let mut effective = vec![None; rig.centers.len()];
    let mut direction_res = Vec::new();
    let mut outliers = 0u32;
    for &e in &excited {
        let of: Vec<&Observation> = obs.iter().filter(|o| o.center == e).collect();
        if let Some(CenterFit { center: c, residuals: res, info }) = effective_center(rig, &of) {
            let keep = inliers(&res, 0.5f64.to_radians().sin());
            outliers += keep.iter().filter(|k| !**k).count() as u32;
            direction_res
                .extend(res.iter().zip(&keep).filter(|(_, k)| **k).map(|(r, _)| r.asin().to_degrees()));
            effective[e] = Some(c);
            located.push(Located { center: rig.centers[e], seen: c, info });
        }
    }
    let undetermined = CalibrateError::Turning { determined: located.len(), excited: excited.len() };
    let m = plate_map(&located).ok_or(undetermined.clone())?;
    let inverse = m.try_inverse().ok_or(undetermined)?;
    // The core commanded prior·ξ and the plate turned as M·ξ: the plate's
    // own map is M·prior⁻¹, whose inverse is prior·M⁻¹.
    let prior = rig.prior_correction.map_or_else(Matrix3::identity, |p| Matrix3::from_fn(|r, c| p[r][c]));
    let correction = prior * inverse;
    // Friction: every observation against the model at the fitted center.
    let mut data = Vec::new();
    for o in obs {
        let Some(c) = effective[o.center] else { continue };
        let Some(a) = model_acceleration(rig, c, o) else { continue };
        let a2 = a[0] * a[0] + a[1] * a[1];
        if a2 > 0.0 {
            let s = (o.acceleration[0] * a[0] + o.acceleration[1] * a[1]) / a2;
            data.push((o.class, friction_terms(rig.plate_half_extent, o.position[0], o.position[1]), s));
        }
    }
    let mut moved: Vec<f64> = data.iter().map(|d| d.2).collect();
    let moved = median(&mut moved);
    if data.is_empty() || !(moved > 0.2) {
        return Err(CalibrateError::TooLittleMotion {
            fraction: if moved.is_finite() { moved } else { 0.0 },
        });
    }
    let pull = pull_for(FRICTION_TERMS, data.len());
    let (mut f, _) = fit_friction(&data, pull).ok_or(CalibrateError::Friction)?;
    for _ in 0..2 {
        let res: Vec<f64> = data.iter().map(|(c, t, s)| (s - f.predict(*c, t)) / f.predict(*c, t)).collect();
        let keep = inliers(&res, 0.02);
        let before = data.len();
        data = data.into_iter().zip(keep).filter(|(_, k)| *k).map(|(d, _)| d).collect();
        outliers += (before - data.len()) as u32;
        (f, _) = fit_friction(&data, pull).ok_or(CalibrateError::Friction)?;
    }
    // The map the inliers support, chosen on held-out ones.
    let (f, cov) = fit_friction(&data, map_pull(&data)).ok_or(CalibrateError::Friction)?;
    let mut rel: Vec<f64> =
        data.iter().map(|(c, t, s)| ((s - f.predict(*c, t)) / f.predict(*c, t)).abs()).collect();
    // The fit's own uncertainty of s over the plate (first class), relative.
    let half = rig.plate_half_extent;
    let mut spread = Vec::new();
    for i in 0..9 {
        for j in 0..5 {
            let (x, y) = (half[0] * (i as f64 / 4.0 - 1.0) * 0.9, half[1] * (j as f64 / 2.0 - 1.0) * 0.9);
            let t = friction_terms(half, x, y);
            let n = f.classes.len() + FRICTION_TERMS;
            let mut g = DVector::zeros(n);
            let map = 1.0 + t.iter().zip(&f.c).map(|(a, b)| a * b).sum::<f64>();
            g[0] = map;
            for k in 0..FRICTION_TERMS {
                g[f.classes.len() + k] = f.sigma[0] * t[k];
            }
            let var = (g.transpose() * &cov * &g)[(0, 0)];
            spread.push(var.max(0.0).sqrt() / (f.sigma[0] * map));
        }
    }
    let to_array =
        |m: &Matrix3<f64>| -> [[f64; 3]; 3] { core::array::from_fn(|r| core::array::from_fn(|c| m[(r, c)])) };
    let calibration = PlateCalibration {
        format: FORMAT,
        actuators: rig.actuators,
        centers: rig.centers.clone(),
        plate_half_extent: rig.plate_half_extent,
        mu_m_g: rig.mu_m_g,
        twist_correction: to_array(&correction),
        class_friction: f
            .classes
            .iter()
            .zip(&f.sigma)
            .map(|(&class, &scale)| ClassFriction { class, scale })
            .collect(),
        friction_map: f.c,
        report: CalibrationReport {
            bursts: counts.bursts,
            rig_seconds: counts.rig_seconds,
            observations: data.len() as u32,
            rejected: counts.dropped + outliers,
            direction_residual_deg: median(&mut direction_res.iter().map(|d| d.abs()).collect::<Vec<_>>()),
            friction_residual: median(&mut rel),
            predicted_force_err: median(&mut spread),
        },
    };
    calibration.validate().map_err(CalibrateError::Implausible)?;
    Ok(calibration)
}

/// Seven centers around a 2 m × 1 m plate, as the track rig's.
#[cfg(test)]
pub(crate) const TEST_CENTERS: [[f64; 2]; 7] =
    [[1.2, 0.2], [0.7, 0.7], [-0.2, 0.8], [-1.0, 0.5], [-1.3, 0.0], [-1.0, -0.5], [0.6, -0.7]];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_is_chosen_on_held_out_observations() {
        // Parts spread over the plate, two classes, 1 % noise: a plate with
        // no map gets none, a worn one its quadratic terms.
        let half = [1.0, 0.5];
        let data = |map: [f64; FRICTION_TERMS]| -> Vec<(u32, [f64; FRICTION_TERMS], f64)> {
            (0..300)
                .map(|i| {
                    let (x, y) = (((i * 37) % 97) as f64 / 48.5 - 1.0, ((i * 53) % 89) as f64 / 89.0 - 0.5);
                    let t = friction_terms(half, 0.9 * x, 0.9 * y);
                    let class = (i % 2) as u32;
                    let noise = 0.01 * (((i * 7919) % 201) as f64 / 100.0 - 1.0);
                    let s = [1.0, 0.8][class as usize]
                        * (1.0 + t.iter().zip(&map).map(|(a, b)| a * b).sum::<f64>());
                    (class, t, s * (1.0 + noise))
                })
                .collect()
        };
        let pinned = |p: [f64; FRICTION_TERMS]| p.map(|w| w > 1.0 * 300.0);
        let flat = map_pull(&data([0.0; FRICTION_TERMS]));
        assert!(pinned(flat)[2..].iter().all(|&p| p), "a flat plate got a quadratic map: {flat:?}");
        let worn = map_pull(&data([0.0, 0.0, 0.0, 0.15, 0.15]));
        assert!(pinned(worn).iter().all(|&p| !p), "a worn plate lost its map: {worn:?}");
    }

    #[test]
    fn a_known_map_and_friction_come_back_from_clean_observations() {
        // Synthetic: the plate turns about C′ = H(C) for a known M; friction
        // σ = (1.1, 0.8) and a map; accelerations exactly the model's.
        let m = Matrix3::new(1.02, 0.01, 0.004, -0.015, 0.99, -0.006, 0.01, -0.02, 1.0);
        let rig = RigModel {
            centers: TEST_CENTERS.to_vec(),
            plate_half_extent: [1.0, 0.5],
            mu_m_g: 0.1,
            mu_g: 0.25 * 9.81,
            motion: MotionParams::default(),
            actuators: 4,
            prior_correction: None,
            follow: PlateFollow::Exact,
        };
        let map = [0.1, -0.05, 0.05, 0.1, 0.08];
        let parts: Vec<([f64; 2], u32)> = (0..12)
            .map(|i| ([-0.7 + 0.13 * i as f64, 0.35 * ((i * 7 % 5) as f64 / 2.0 - 1.0)], (i % 2) as u32))
            .collect();
        let mut obs = Vec::new();
        for (e, c) in rig.centers.iter().enumerate() {
            let v = m * nalgebra::Vector3::new(c[1], -c[0], 1.0);
            let ce = [-v[1] / v[2], v[0] / v[2]];
            for &(p, class) in &parts {
                let bursts = [BurstMotion::at_rest(p); 2];
                let seen =
                    Observation { center: e, k: 0.35, class, position: p, acceleration: [0.0; 2], bursts };
                let a = model_acceleration(&rig, ce, &seen).expect("model");
                let t = friction_terms(rig.plate_half_extent, p[0], p[1]);
                let s =
                    [1.1, 0.8][class as usize] * (1.0 + t.iter().zip(&map).map(|(a, b)| a * b).sum::<f64>());
                obs.push(Observation { acceleration: [s * a[0], s * a[1]], ..seen });
            }
        }
        let cal = fit(&rig, &obs, FitCounts::default()).expect("fit");
        let back = Matrix3::from_fn(|r, c| cal.twist_correction[r][c]).try_inverse().expect("inverse");
        assert!((back - m).abs().max() < 1e-6, "{back} against {m}");
        assert!(
            (cal.class_friction[0].scale - 1.1).abs() < 0.01
                && (cal.class_friction[1].scale - 0.8).abs() < 0.01,
            "{:?} {:?}",
            cal.class_friction,
            cal.friction_map
        );
        for k in 0..FRICTION_TERMS {
            assert!((cal.friction_map[k] - map[k]).abs() < 0.02, "{:?}", cal.friction_map);
        }
    }
}
