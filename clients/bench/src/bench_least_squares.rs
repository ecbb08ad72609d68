//! The calibration fit's dense least squares (`upm bench calibration`),
//! three ways in the same run: the fit's own normal equations with
//! nalgebra (JᵀJ accumulated row by row, inverted: the inverse is also the
//! fit's covariance), faer's Householder QR (`Mat::qr().solve_lstsq`),
//! and faer's Cholesky of JᵀJ. The Jacobian has the friction fit's shape:
//! one column per part class (that class's friction map at the part), then
//! one per map term (σ·t_k), one row per observation.

use std::time::Instant;

use faer::linalg::solvers::{Solve, SolveLstsq};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

/// A Jacobian and residual of `rows` observations over `classes` classes.
fn system(rows: usize, classes: usize, seed: u64) -> (faer::Mat<f64>, faer::Mat<f64>) {
    let terms = rig_config::plate_calibration::FRICTION_TERMS;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = classes + terms;
    let mut j = faer::Mat::zeros(rows, n);
    let mut r = faer::Mat::zeros(rows, 1);
    for i in 0..rows {
        let class = i % classes;
        let (x, y) = (rng.random_range(-0.8..0.8), rng.random_range(-0.4..0.4));
        let t = rig_config::plate_calibration::friction_terms([1.0, 0.5], x, y);
        let sigma = 1.0 + 0.1 * class as f64;
        j[(i, class)] = 1.0 + 0.05 * t[0];
        for k in 0..terms {
            j[(i, classes + k)] = sigma * t[k];
        }
        r[(i, 0)] = rng.random_range(-0.05..0.05);
    }
    (j, r)
}

/// The fit's way: JᵀJ and Jᵀr row by row, then the inverse times Jᵀr.
fn normal_equations(j: &faer::Mat<f64>, r: &faer::Mat<f64>) -> Option<Vec<f64>> {
    let n = j.ncols();
    let mut jtj = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut jtr = nalgebra::DVector::<f64>::zeros(n);
    for i in 0..j.nrows() {
        for a in 0..n {
            jtr[a] += j[(i, a)] * r[(i, 0)];
            for b in 0..n {
                jtj[(a, b)] += j[(i, a)] * j[(i, b)];
            }
        }
    }
    Some((jtj.try_inverse()? * jtr).iter().copied().collect())
}

fn faer_qr(j: &faer::Mat<f64>, r: &faer::Mat<f64>) -> Vec<f64> {
    let x = j.qr().solve_lstsq(r);
    (0..x.nrows()).map(|i| x[(i, 0)]).collect()
}

fn faer_cholesky(j: &faer::Mat<f64>, r: &faer::Mat<f64>) -> Option<Vec<f64>> {
    let jtj = j.transpose() * j;
    let jtr = j.transpose() * r;
    let x = jtj.llt(faer::Side::Lower).ok()?.solve(&jtr);
    Some((0..x.nrows()).map(|i| x[(i, 0)]).collect())
}

/// Time each way on `rows` observations of `classes` classes (µs, p50 and
/// p99 over alternating batches of `budget_s`), with the largest relative
/// difference of their answers.
pub fn run(rows: usize, classes: usize, budget_s: f64) -> anyhow::Result<Value> {
    let (j, r) = system(rows.max(classes + rig_config::plate_calibration::FRICTION_TERMS), classes.max(1), 7);
    let reference = normal_equations(&j, &r).ok_or_else(|| anyhow::anyhow!("singular JᵀJ"))?;
    let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
    let diff = |x: &[f64]| x.iter().zip(&reference).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale;
    let qr_diff = diff(&faer_qr(&j, &r));
    let llt_diff = diff(&faer_cholesky(&j, &r).ok_or_else(|| anyhow::anyhow!("JᵀJ not positive definite"))?);
    let (mut ne, mut qr, mut llt) = (Vec::new(), Vec::new(), Vec::new());
    let time = |f: &dyn Fn(), out: &mut Vec<f64>| {
        for _ in 0..8 {
            let t = Instant::now();
            f();
            out.push(t.elapsed().as_secs_f64() * 1e6);
        }
    };
    let started = Instant::now();
    while started.elapsed().as_secs_f64() < budget_s || ne.len() < 64 {
        time(&|| drop(std::hint::black_box(normal_equations(&j, &r))), &mut ne);
        time(&|| drop(std::hint::black_box(faer_qr(&j, &r))), &mut qr);
        time(&|| drop(std::hint::black_box(faer_cholesky(&j, &r))), &mut llt);
    }
    for v in [&mut ne, &mut qr, &mut llt] {
        v.sort_by(f64::total_cmp);
    }
    let row = |v: &[f64]| json!({ "p50_us": upm_stats::percentile_or_nan(v, 0.5), "p99_us": upm_stats::percentile_or_nan(v, 0.99) });
    Ok(json!({
        "rows": j.nrows(),
        "unknowns": j.ncols(),
        "nalgebra_normal_equations": row(&ne),
        "faer_qr": row(&qr),
        "faer_cholesky": row(&llt),
        "faer_qr_rel_diff": qr_diff,
        "faer_cholesky_rel_diff": llt_diff,
        "samples": ne.len(),
    }))
}

/// One line for `upm bench calibration`'s text.
pub fn to_text(v: &Value) -> String {
    let p50 = |k: &str| v[k]["p50_us"].as_f64().unwrap_or(f64::NAN);
    format!(
        "friction fit's least squares ({} × {}), p50: nalgebra normal equations (the fit's) {:.1} µs, \
         faer QR {:.1} µs, faer Cholesky {:.1} µs (answers within {:.0e} / {:.0e})\n",
        v["rows"],
        v["unknowns"],
        p50("nalgebra_normal_equations"),
        p50("faer_qr"),
        p50("faer_cholesky"),
        v["faer_qr_rel_diff"].as_f64().unwrap_or(f64::NAN),
        v["faer_cholesky_rel_diff"].as_f64().unwrap_or(f64::NAN),
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_three_ways_agree_on_the_fits_shape() {
        let v = super::run(600, 2, 0.0).expect("run");
        assert_eq!(v["unknowns"], 2 + rig_config::plate_calibration::FRICTION_TERMS);
        for k in ["faer_qr_rel_diff", "faer_cholesky_rel_diff"] {
            assert!(v[k].as_f64().is_some_and(|d| d < 1e-8), "{k}: {v}");
        }
        println!("{}", super::to_text(&v));
    }
}
