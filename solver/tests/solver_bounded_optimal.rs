//! The bounded path finds the true optimum: against an exhaustive
//! enumeration of active sets on small problems (every one of the 3ⁿ
//! assignments free / at +k_max / at −k_max solved by nalgebra's SVD), the
//! KKT conditions to 1e-9 relative, and a warm start that changes the
//! path but not the answer.

mod common;

use common::random_case;
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use upm_solver::{LeastSquaresSystem, Problem, SolveMethod, Solver, SolverCapacity, SolverParams};

const MU_M_G: f64 = 0.1;

/// min over all 3ⁿ active sets of the objective of the free block's
/// optimum, among those that stay inside the box.
fn enumerate_optimum(sys: &LeastSquaresSystem<'_>, k_max: f64) -> (f64, Vec<f64>) {
    let (m, n) = (sys.m, sys.n);
    let a = DMatrix::from_row_slice(m, n, sys.rows);
    let b = DVector::from_column_slice(sys.b);
    let mut best = (f64::INFINITY, vec![0.0; n]);
    let mut code = vec![0u8; n];
    for mut c in 0..3usize.pow(n as u32) {
        for d in code.iter_mut() {
            *d = (c % 3) as u8;
            c /= 3;
        }
        let free: Vec<usize> = (0..n).filter(|&j| code[j] == 0).collect();
        let mut k = vec![0.0; n];
        let mut r = b.clone();
        for j in 0..n {
            if code[j] != 0 {
                k[j] = if code[j] == 1 { k_max } else { -k_max };
                r -= a.column(j) * k[j];
            }
        }
        if !free.is_empty() {
            // [A_F; √ε I] k_F = [r; 0] by SVD.
            let nf = free.len();
            let mut aug = DMatrix::zeros(m + nf, nf);
            for (c, &j) in free.iter().enumerate() {
                aug.view_mut((0, c), (m, 1)).copy_from(&a.column(j));
                aug[(m + c, c)] = sys.eps.sqrt();
            }
            let mut rhs = DVector::zeros(m + nf);
            rhs.rows_mut(0, m).copy_from(&r);
            let kf = aug.svd(true, true).solve(&rhs, 0.0).expect("svd solve");
            if kf.iter().any(|v| v.abs() > k_max * (1.0 + 1e-12)) {
                continue;
            }
            for (c, &j) in free.iter().enumerate() {
                k[j] = kf[c];
            }
        }
        let f = sys.objective(&k);
        if f < best.0 {
            best = (f, k);
        }
    }
    best
}

/// KKT of the box-constrained problem, relative to the gradient at k = 0.
fn kkt_violation(sys: &LeastSquaresSystem<'_>, k: &[f64], k_max: f64) -> f64 {
    let g = sys.gradient(k);
    let scale = sys.gradient(&vec![0.0; sys.n]).iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-300);
    let mut worst = 0.0f64;
    for (j, &kj) in k.iter().enumerate() {
        let v = if kj >= k_max * (1.0 - 1e-9) {
            g[j].max(0.0) // at +k_max the gradient may only push outward (g ≤ 0)
        } else if kj <= -k_max * (1.0 - 1e-9) {
            (-g[j]).max(0.0)
        } else {
            g[j].abs()
        };
        worst = worst.max(v / scale);
    }
    worst
}

fn problem<'a>(c: &'a common::RandomCase, k_max: f64) -> Problem<'a> {
    Problem { mu_m_g: MU_M_G, k_max, centers: &c.centers, parts: &c.parts, curls: &c.curls, k_bounds: &[] }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn bounded_answer_is_the_enumerated_optimum(
        seed in 0u64..1_000_000,
        parts in 1usize..=3,
        curls in 0usize..=1,
        n in 2usize..=7,
        gain in 1.0f64..400.0,
        k_max in 0.2f64..=1.0,
    ) {
        let mut case = random_case(seed, parts, curls, n, 0.05);
        for p in &mut case.parts {
            p.force = p.force.map(|f| [f[0] * gain, f[1] * gain]);
        }
        for q in &mut case.curls {
            q.curl *= gain;
        }
        let mut solver = Solver::new(SolverCapacity { parts: 3, curls: 1, centers: 7 }, SolverParams::default());
        let mut out = solver.new_solution();
        solver.solve(&problem(&case, k_max), &mut out).expect("solve");
        prop_assume!(out.method == SolveMethod::BoundedLeastSquares);
        prop_assert!(out.converged);
        let sys = solver.last_system();
        let (best, _) = enumerate_optimum(&sys, k_max);
        let got = sys.objective(out.k());
        prop_assert!(got <= best * (1.0 + 1e-9) + 1e-300, "objective {got} vs enumerated {best}");
        prop_assert!(got >= best * (1.0 - 1e-9), "objective {got} below the enumerated optimum {best}");
        let kkt = kkt_violation(&sys, out.k(), k_max);
        prop_assert!(kkt <= 1e-9, "KKT violated by {kkt:e}");
    }
}

/// Consecutive frames (every part moved by 1 mm): warm-started solves give
/// the cold answer, bit for bit when they end on the same active set.
#[test]
fn warm_start_changes_the_path_not_the_answer() {
    let (mut warm_used, mut frames) = (0, 0);
    for seed in 0..20u64 {
        let mut case = random_case(seed, 10, 0, 24, 0.1);
        for p in &mut case.parts {
            p.force = p.force.map(|f| [f[0] * 300.0, f[1] * 300.0]);
        }
        let cap = SolverCapacity { parts: 10, curls: 0, centers: 24 };
        let mut warm = Solver::new(cap, SolverParams::default());
        let mut cold = Solver::new(cap, SolverParams { warm_start: false, ..SolverParams::default() });
        let (mut out_w, mut out_c) = (warm.new_solution(), cold.new_solution());
        for frame in 0..30 {
            for (i, p) in case.parts.iter_mut().enumerate() {
                let angle = (seed * 31 + frame * 7 + i as u64) as f64 * 2.399_963;
                p.position[0] += 0.001 * angle.cos();
                p.position[1] += 0.001 * angle.sin();
            }
            let pr = problem(&case, 0.95);
            warm.solve(&pr, &mut out_w).expect("warm solve");
            cold.solve(&pr, &mut out_c).expect("cold solve");
            assert!(!out_c.warm_started);
            frames += 1;
            warm_used += usize::from(out_w.warm_started);
            let sys = cold.last_system();
            let (fw, fc) = (sys.objective(out_w.k()), sys.objective(out_c.k()));
            assert!(
                (fw - fc).abs() <= 1e-12 * fc.abs(),
                "seed {seed} frame {frame}: {fw} vs {fc}; warm {} it {} conv {}, cold it {} conv {}",
                out_w.warm_started,
                out_w.iterations,
                out_w.converged,
                out_c.iterations,
                out_c.converged
            );
            let same_set =
                out_w.k().iter().zip(out_c.k()).all(|(w, c)| (w.abs() >= 0.95) == (c.abs() >= 0.95));
            if same_set {
                assert_eq!(out_w.k(), out_c.k(), "seed {seed} frame {frame}");
            }
            if out_w.warm_started {
                assert!(
                    out_w.iterations <= out_c.iterations + 2,
                    "warm {} cold {}",
                    out_w.iterations,
                    out_c.iterations
                );
                assert_eq!((out_w.rank, out_w.condition), (0, 0.0), "warm solves do not estimate κ");
            }
        }
    }
    assert!(warm_used * 2 > frames, "warm start used in only {warm_used} of {frames} frames");
}
