use upm_solver::{ForceConstraint, Problem, Solver, SolverCapacity, SolverParams};
fn main() {
    let rows: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(20);
    let n: usize = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(24);
    let mut x = 12345u64;
    let mut rnd = move || {
        x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut pts: Vec<[f64; 2]> = Vec::new();
    while pts.len() < rows / 2 {
        let p = [rnd() * 1.9 - 0.95, rnd() * 0.9 - 0.45];
        if pts.iter().all(|q| (p[0] - q[0]).hypot(p[1] - q[1]) > 0.08) {
            pts.push(p);
        }
    }
    let mut centers: Vec<[f64; 2]> = Vec::new();
    while centers.len() < n {
        let c = [rnd() * 3.0 - 1.5, rnd() * 2.0 - 1.0];
        if pts.iter().all(|q| (c[0] - q[0]).hypot(c[1] - q[1]) > 0.1) {
            centers.push(c);
        }
    }
    let parts: Vec<ForceConstraint> = pts
        .iter()
        .map(|&p| ForceConstraint {
            position: p,
            force: Some([1e-6, -1e-6]),
            shape: upm_solver::PartShape::Point,
        })
        .collect();
    let ci: usize = std::env::args().nth(3).and_then(|s| s.parse().ok()).unwrap_or(12);
    let mut s = Solver::new(
        SolverCapacity { parts: rows / 2, curls: 0, centers: n },
        SolverParams { condition_iterations: ci, ..SolverParams::default() },
    );
    s.warm_up();
    let mut sol = s.new_solution();
    let p = Problem { mu_m_g: 0.1, k_max: 0.95, centers: &centers, parts: &parts, curls: &[], k_bounds: &[] };
    // Median of 41 batches: this VM's noise swamps a single long timing.
    let n_batches: usize =
        std::env::var("UPM_PROFILE_BATCHES").ok().and_then(|s| s.parse().ok()).unwrap_or(41).max(1);
    let mut batches: Vec<f64> = (0..n_batches)
        .map(|_| {
            let t = std::time::Instant::now();
            for _ in 0..500 {
                s.solve(&p, &mut sol).expect("solve");
            }
            t.elapsed().as_secs_f64() * 1e6 / 500.0
        })
        .collect();
    batches.sort_by(f64::total_cmp);
    println!(
        "{:?} cond {:.1e} {:.2} us/solve (median of {} batches)",
        sol.method,
        sol.condition,
        batches[n_batches / 2],
        n_batches
    );
}
