//! Shared helpers for the solver tests: seeded random geometry and an
//! independent reference (nalgebra SVD) that shares no code with the solver.
#![allow(dead_code)]

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use upm_solver::{CurlConstraint, ForceConstraint};

#[derive(Clone)]
pub struct RandomCase {
    pub centers: Vec<[f64; 2]>,
    pub parts: Vec<ForceConstraint>,
    pub curls: Vec<CurlConstraint>,
}

/// Parts inside the unit plate [-1,1]×[-0.5,0.5] at least `min_sep` apart,
/// centers spread over [-1.4,1.4]×[-0.9,0.9], at least 0.1 from every part
/// (well conditioned when n exceeds the rows and parts are spread out).
pub fn random_case(seed: u64, n_parts: usize, n_curls: usize, n_centers: usize, min_sep: f64) -> RandomCase {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pts: Vec<[f64; 2]> = Vec::new();
    while pts.len() < n_parts + n_curls {
        let p = [rng.random_range(-1.0..1.0), rng.random_range(-0.5..0.5)];
        if pts.iter().all(|q| (p[0] - q[0]).hypot(p[1] - q[1]) >= min_sep) {
            pts.push(p);
        }
    }
    let mut centers: Vec<[f64; 2]> = Vec::new();
    while centers.len() < n_centers {
        let c = [rng.random_range(-1.4..1.4), rng.random_range(-0.9..0.9)];
        if pts.iter().all(|q| (c[0] - q[0]).hypot(c[1] - q[1]) >= 0.1) {
            centers.push(c);
        }
    }
    let parts = pts[..n_parts]
        .iter()
        .map(|&p| ForceConstraint {
            position: p,
            force: Some([rng.random_range(-0.0005..0.0005), rng.random_range(-0.0005..0.0005)]),
            shape: upm_solver::PartShape::Point,
        })
        .collect();
    let curls = pts[n_parts..]
        .iter()
        .map(|&p| CurlConstraint {
            position: p,
            curl: rng.random_range(-0.002..0.002),
            shape: upm_solver::PartShape::Point,
        })
        .collect();
    RandomCase { centers, parts, curls }
}

/// A and b of Eq. 10/12 built independently of the solver.
pub fn reference_system(
    centers: &[[f64; 2]],
    parts: &[ForceConstraint],
    curls: &[CurlConstraint],
    mu_m_g: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let forced: Vec<_> = parts.iter().filter_map(|p| p.force.map(|f| (p.position, f))).collect();
    let m = 2 * forced.len() + curls.len();
    let n = centers.len();
    let s = n as f64 / mu_m_g;
    let mut a = DMatrix::zeros(m, n);
    let mut b = DVector::zeros(m);
    for (i, (p, f)) in forced.iter().enumerate() {
        for (j, c) in centers.iter().enumerate() {
            let r = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt();
            a[(i, j)] = -(p[1] - c[1]) / r;
            a[(forced.len() + i, j)] = (p[0] - c[0]) / r;
        }
        b[i] = s * f[0];
        b[forced.len() + i] = s * f[1];
    }
    for (q, curl) in curls.iter().enumerate() {
        let row = 2 * forced.len() + q;
        for (j, c) in centers.iter().enumerate() {
            let p = curl.position;
            a[(row, j)] = 1.0 / ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt();
        }
        b[row] = s * curl.curl;
    }
    (a, b)
}

/// Minimum-norm solution through nalgebra's SVD.
pub fn svd_min_norm(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let svd = a.clone().svd(true, true);
    svd.solve(b, 1e-12).expect("svd solve")
}

pub fn svd_condition(a: &DMatrix<f64>) -> f64 {
    let s = a.clone().singular_values();
    s.max() / s.min()
}
