//! Online friction adaptation: each part's effective friction scale,
//! learnt from how it moves under the forces asked for it, and every
//! request divided by it (on top of a plate calibration's, if any).
//!
//! Over a sliding window (1 s) of frames, a part's positions are fitted
//! as x(t) = x₀ + v₀·t + (s/m)·∬f dt − γ·∫(x − x₀) dt, both axes sharing s
//! and γ, f the force the solver was asked (what the model delivers at
//! s = 1); γ takes up the drag of the part's own speed. What s learns is
//! the part's effective scale: its friction and the model's own loss on a
//! moving part together. The estimate moves
//! a fifth of the way to each window's fit. A window is skipped when it
//! holds too little push to tell s (its double integral moves the part
//! less than 3 mm) and rejected, and counted, when its fit leaves
//! residuals of a collision or a fence (beyond 1 mm RMS) or lands more than
//! half the estimate away. The estimate stays within [`MIN_SCALE`,
//! `MAX_SCALE`], so a bad one can ask at most twice the force the planner
//! wants, which its own cap and the core's bounds still limit.

use ipc_types::{ForceRequest, PartStates};
use rig_config::PlateCalibration;

use crate::Planner;

pub const MIN_SCALE: f64 = 0.5;
pub const MAX_SCALE: f64 = 2.0;
const WINDOW_S: f64 = 1.0;
const UPDATE_EVERY_S: f64 = 0.5;
const GAIN: f64 = 0.2;

/// One part's frames and estimate.
#[derive(Debug, Clone)]
struct Track {
    id: u32,
    /// The calibration's scale where the part was last seen.
    calibrated: f64,
    /// (t, x, y, fx, fy): the force asked after that frame.
    samples: Vec<[f64; 5]>,
    scale: f64,
    last_update: f64,
}

pub use crate::adapt_counts::AdaptCounts;

pub struct Adaptive<P> {
    inner: P,
    calibration: Option<PlateCalibration>,
    part_mass: f64,
    tracks: Vec<Track>,
    counts: AdaptCounts,
}

impl<P: Planner> core::fmt::Debug for Adaptive<P> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Adaptive").field("planner", &self.inner.name()).field("counts", &self.counts).finish()
    }
}

impl<P: Planner> Adaptive<P> {
    pub fn new(inner: P, calibration: Option<PlateCalibration>, part_mass: f64) -> Self {
        Self { inner, calibration, part_mass, tracks: Vec::new(), counts: AdaptCounts::default() }
    }

    fn learn(&mut self, t: f64) {
        let m = self.part_mass;
        for tr in &mut self.tracks {
            tr.samples.retain(|s| t - s[0] <= WINDOW_S);
            if t - tr.last_update < UPDATE_EVERY_S || tr.samples.len() < 10 {
                continue;
            }
            tr.last_update = t;
            match fit_scale(&tr.samples, m) {
                Fit::Scale(s) if (s - tr.scale).abs() <= 0.5 * tr.scale => {
                    tr.scale = (tr.scale + GAIN * (s - tr.scale)).clamp(MIN_SCALE, MAX_SCALE);
                    self.counts.updates += 1;
                }
                Fit::Scale(_) | Fit::Disturbed => self.counts.rejected += 1,
                Fit::Weak => self.counts.skipped += 1,
            }
        }
    }
}

enum Fit {
    Scale(f64),
    Weak,
    Disturbed,
}

/// Unknowns of a window's fit: x₀, v₀x, y₀, v₀y, s, γ.
const UNKNOWNS: usize = 6;

/// Least squares over one window of x(t) = x₀ + v₀·t + (s/m)·∬f dt −
/// γ·∫(x − x₀) dt on both axes (shared s and γ): a moving part is
/// dragged in proportion to its speed (the plate's friction leans towards
/// its own velocity), so a part driven at constant speed feels a force and
/// does not accelerate; γ takes that up.
#[allow(clippy::needless_range_loop)] // index loops mirror the formulas
fn fit_scale(samples: &[[f64; 5]], mass: f64) -> Fit {
    let t0 = samples[0][0];
    // ∬f dt per axis, the force held from each frame to the next, and
    // ∫(x − x₀) dt from the positions seen.
    let mut push = vec![[0.0; 2]; samples.len()];
    let mut drift = vec![[0.0; 2]; samples.len()];
    let (mut v, mut p) = ([0.0; 2], [0.0; 2]);
    for i in 1..samples.len() {
        let dt = samples[i][0] - samples[i - 1][0];
        for d in 0..2 {
            let a = samples[i - 1][3 + d] / mass;
            p[d] += v[d] * dt + 0.5 * a * dt * dt;
            v[d] += a * dt;
            let (q0, q1) = (samples[i - 1][1 + d] - samples[0][1 + d], samples[i][1 + d] - samples[0][1 + d]);
            drift[i][d] = drift[i - 1][d] + 0.5 * (q0 + q1) * dt;
        }
        push[i] = p;
    }
    let reach = push.iter().map(|q| q[0].hypot(q[1])).fold(0.0, f64::max);
    if reach < 3e-3 {
        return Fit::Weak;
    }
    let row = |i: usize, d: usize| -> [f64; UNKNOWNS] {
        let mut r = [0.0; UNKNOWNS];
        r[2 * d] = 1.0;
        r[2 * d + 1] = samples[i][0] - t0;
        r[4] = push[i][d];
        r[5] = -drift[i][d];
        r
    };
    let mut n = [[0.0; UNKNOWNS]; UNKNOWNS];
    let mut b = [0.0; UNKNOWNS];
    for i in 0..samples.len() {
        for d in 0..2 {
            let r = row(i, d);
            for a in 0..UNKNOWNS {
                b[a] += r[a] * samples[i][1 + d];
                for c in 0..UNKNOWNS {
                    n[a][c] += r[a] * r[c];
                }
            }
        }
    }
    let Some(x) = solve(n, b) else { return Fit::Weak };
    let mut ss = 0.0;
    for i in 0..samples.len() {
        for d in 0..2 {
            let r = row(i, d);
            let e = samples[i][1 + d] - (0..UNKNOWNS).map(|a| r[a] * x[a]).sum::<f64>();
            ss += e * e;
        }
    }
    let rms = (ss / (2 * samples.len()) as f64).sqrt();
    if rms > 1e-3 || !x[4].is_finite() { Fit::Disturbed } else { Fit::Scale(x[4]) }
}

/// Gaussian elimination with partial pivoting; None if singular.
#[allow(clippy::needless_range_loop)]
fn solve<const N: usize>(mut n: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    for c in 0..N {
        let p = (c..N).max_by(|&i, &j| n[i][c].abs().total_cmp(&n[j][c].abs()))?;
        if n[p][c].abs() < 1e-15 {
            return None;
        }
        n.swap(c, p);
        b.swap(c, p);
        for r in c + 1..N {
            let f = n[r][c] / n[c][c];
            for k in c..N {
                n[r][k] -= f * n[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; N];
    for r in (0..N).rev() {
        x[r] = (b[r] - (r + 1..N).map(|k| n[r][k] * x[k]).sum::<f64>()) / n[r][r];
    }
    Some(x)
}

impl<P: Planner> Planner for Adaptive<P> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn friction_estimates(&self) -> Vec<(u32, f64)> {
        self.tracks.iter().map(|t| (t.id, t.calibrated * t.scale)).collect()
    }

    fn learning_counts(&self) -> Option<AdaptCounts> {
        Some(self.counts)
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        self.learn(t);
        let asked = self.inner.plan(parts, t, out);
        for p in parts.parts() {
            let i = match self.tracks.iter().position(|tr| tr.id == p.id) {
                Some(i) => i,
                None => {
                    self.tracks.push(Track {
                        id: p.id,
                        calibrated: 1.0,
                        samples: Vec::new(),
                        scale: 1.0,
                        last_update: t,
                    });
                    self.tracks.len() - 1
                }
            };
            let tr = &mut self.tracks[i];
            let calibrated = self.calibration.as_ref().map_or(1.0, |c| c.friction_scale(p.class, p.x, p.y));
            tr.calibrated = calibrated;
            let s = calibrated * tr.scale;
            let e = out.entries_mut().iter_mut().find(|e| e.part_id == p.id && asked);
            let mut f = [0.0; 2];
            if let Some(e) = e {
                e.fx /= s;
                e.fy /= s;
                e.curl /= s;
                // What the model delivers at scale 1, times the calibration's
                // scale: the estimate learns what is left.
                f = [e.fx * calibrated, e.fy * calibrated];
            }
            tr.samples.push([t, p.x, p.y, f[0], f[1]]);
        }
        // Parts no longer seen are forgotten.
        self.tracks.retain(|tr| tr.samples.last().is_some_and(|s| t - s[0] <= WINDOW_S));
        asked
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_part_with_less_friction_is_learnt_and_a_kick_is_rejected() {
        // A part of mass m under a varying asked force f moves as s·f/m,
        // dragged by γ·v.
        let (m, s_true, gamma) = (0.04, 0.7, 2.0);
        let mut samples = Vec::new();
        let (mut x, mut v) = ([0.0f64; 2], [0.0f64; 2]);
        for k in 0..31 {
            let t = k as f64 / 30.0;
            let f = [0.004 * (1.0 + t).cos(), 0.003];
            samples.push([t, x[0], x[1], f[0], f[1]]);
            // Fine steps: the drag acts continuously.
            for _ in 0..100 {
                for d in 0..2 {
                    let a = s_true * f[d] / m - gamma * v[d];
                    x[d] += v[d] / 3000.0 + 0.5 * a / 9e6;
                    v[d] += a / 3000.0;
                }
            }
        }
        match fit_scale(&samples, m) {
            Fit::Scale(s) => assert!((s - s_true).abs() < 0.01, "{s}"),
            _ => panic!("no fit"),
        }
        // A collision halfway: the part is knocked to 5 cm/s sideways.
        let mut kicked = samples.clone();
        for s in kicked.iter_mut().skip(15) {
            s[2] += 0.05 * (s[0] - 0.5);
        }
        match fit_scale(&kicked, m) {
            Fit::Disturbed => {}
            Fit::Scale(s) => assert!((s - s_true).abs() > 0.5 * s_true, "a kick passed for friction: {s}"),
            Fit::Weak => panic!("weak"),
        }
        // Almost no push: nothing to learn.
        let still: Vec<[f64; 5]> = samples.iter().map(|s| [s[0], 0.0, 0.0, 1e-6, 0.0]).collect();
        assert!(matches!(fit_scale(&still, m), Fit::Weak));
    }
}
