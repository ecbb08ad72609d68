//! A solve allocates nothing: a counting global allocator watches thousands of
//! solves of varying size, on both the exact and the bounded path, up to the
//! full capacity (64 parts, 16 curl points, 192 centers).

mod common;

use common::random_case;
use rt_core::alloc_count::{RtAllocCounter, allocations_in, counter_installed};
use upm_solver::{ForceConstraint, Problem, SolveMethod, Solver, SolverCapacity, SolverParams};

// The project's one counting allocator; it counts only threads marked
// real-time, so tests running in parallel do not count each other.
#[global_allocator]
static GLOBAL: RtAllocCounter = RtAllocCounter;

/// Per-center bounds for every other case (the scaled columns' path).
static BOUNDS: [f64; 192] = {
    let mut b = [0.0; 192];
    let mut j = 0;
    while j < 192 {
        b[j] = 0.3 + 0.1 * (j % 7) as f64;
        j += 1;
    }
    b
};

fn problem(case: &common::RandomCase, i: usize) -> Problem<'_> {
    Problem {
        mu_m_g: 0.1,
        k_max: 0.9,
        centers: &case.centers,
        parts: &case.parts,
        curls: &case.curls,
        k_bounds: if i.is_multiple_of(2) { &[] } else { &BOUNDS[..case.centers.len()] },
    }
}

#[test]
fn thousands_of_solves_allocate_nothing() {
    // Build every input first: only the solves are counted.
    let mut cases = Vec::new();
    for seed in 0..3000u64 {
        // Both paths up to full capacity.
        let bounded = seed % 3 == 0;
        let parts = 1 + (seed as usize * 7) % 64;
        let curls = (seed as usize) % 17;
        let rows = 2 * parts + curls;
        let centers = (rows + (seed as usize % 40)).clamp(3, 192);
        // Every third case asks for far too much force: the bounded path.
        let mut case = random_case(seed, parts, curls, centers, 0.05);
        let gain = if bounded { 400.0 } else { 0.002 };
        case.parts.iter_mut().for_each(|p: &mut ForceConstraint| {
            p.force = p.force.map(|f| [f[0] * gain, f[1] * gain]);
        });
        case.curls.iter_mut().for_each(|q| q.curl *= gain);
        // A bounded case comes back as the next frame (every part 1 mm
        // further): the warm-started path.
        let next = bounded.then(|| {
            let mut next = case.clone();
            next.parts.iter_mut().for_each(|p| p.position[0] += 0.001);
            next
        });
        cases.push(case);
        cases.extend(next);
    }
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    // Start-up, as an RT thread does it (every buffer touched once).
    assert!(solver.warm_up());
    let mut methods = [0usize; 3];
    let (mut unconverged, mut warm) = (0, 0);

    let ((), allocations) = allocations_in(|| {
        for (i, case) in cases.iter().enumerate() {
            let problem = problem(case, i);
            let result = solver.solve(&problem, &mut out);
            methods[match out.method {
                SolveMethod::Exact => 0,
                SolveMethod::BoundedLeastSquares => 1,
                SolveMethod::Trivial | SolveMethod::Sparse => 2,
            }] += usize::from(result.is_ok());
            unconverged += usize::from(!out.converged);
            warm += usize::from(out.warm_started);
        }
    });

    println!(
        "exact {}, bounded {} ({warm} warm-started), trivial {}, bounded not converged {unconverged}",
        methods[0], methods[1], methods[2]
    );
    assert_eq!(allocations, 0, "solves allocated {allocations} times");
    assert!(methods[0] > 100 && methods[1] > 100, "both paths must be exercised: {methods:?}");
    assert!(warm > 100, "the warm-started path must be exercised: {warm}");
    assert_eq!(methods.iter().sum::<usize>(), cases.len(), "every solve succeeded");
}

#[test]
fn sparse_solves_allocate_nothing() {
    // Up to full capacity: 64 parts, 16 curls, 192 candidates, 192 slots.
    let cases: Vec<_> = (0..600u64)
        .map(|seed| {
            let parts = 1 + (seed as usize * 7) % 64;
            let curls = (seed as usize) % 17;
            let centers = (2 * parts + curls + (seed as usize % 40)).clamp(3, 192);
            let gain = if seed % 2 == 0 { 400.0 } else { 0.002 };
            let mut case = random_case(seed, parts, curls, centers, 0.05);
            case.parts.iter_mut().for_each(|p| p.force = p.force.map(|f| [f[0] * gain, f[1] * gain]));
            case
        })
        .collect();
    let mut solvers: Vec<Solver> = [8, 24, 192]
        .iter()
        .map(|&cycle_slots| {
            let mut s =
                Solver::new(SolverCapacity::DEFAULT, SolverParams { cycle_slots, ..SolverParams::default() });
            assert!(s.warm_up());
            s
        })
        .collect();
    let mut out = solvers[0].new_solution();
    let mut sparse = 0;
    let ((), allocations) = allocations_in(|| {
        for (i, case) in cases.iter().enumerate() {
            let problem = problem(case, i);
            let solver = &mut solvers[i % 3];
            if solver.solve(&problem, &mut out).is_ok() && out.method == SolveMethod::Sparse {
                sparse += usize::from(out.slots() == solver.params().cycle_slots);
            }
        }
    });
    assert_eq!(allocations, 0, "sparse solves allocated {allocations} times");
    assert_eq!(sparse, cases.len(), "every solve took the sparse path and filled its cycle");
}

/// The solve stage's part-dynamics correction: plate trace, per-part
/// integration (points and patches, moving and spinning), re-solves and
/// the kept answer's swap, on the paper's cycle and on sparse ones.
#[test]
fn part_dynamics_corrections_allocate_nothing() {
    use upm_motion::{LinearizeAbout, PartDynamics, PartDynamicsParams, PartMotion};
    use upm_motion::{MotionParams, PlateMotion};
    let cases: Vec<_> = (0..40u64)
        .map(|seed| {
            let parts = 1 + (seed as usize * 5) % 12;
            let curls = (seed as usize) % 4;
            let centers = (2 * parts + curls + 4).clamp(3, 48);
            let mut case = random_case(seed, parts, curls, centers, 0.05);
            let gain = if seed % 2 == 0 { 400.0 } else { 0.002 };
            case.parts.iter_mut().for_each(|p| p.force = p.force.map(|f| [f[0] * gain, f[1] * gain]));
            // Curls on discs and squares: the patch path.
            for (c, q) in case.curls.iter_mut().enumerate() {
                q.shape = if c % 2 == 0 {
                    upm_solver::PartShape::Disc { radius: 0.02 }
                } else {
                    let mut v = [[0.0; 2]; ipc_types::MAX_SHAPE_VERTICES];
                    v[..4].copy_from_slice(&[[0.02, 0.02], [-0.02, 0.02], [-0.02, -0.02], [0.02, -0.02]]);
                    upm_solver::PartShape::Polygon { vertices: v, count: 4 }
                };
            }
            let motions: Vec<PartMotion> = (0..parts)
                .map(|i| PartMotion {
                    velocity: [0.01 * (i as f64).sin(), -0.02],
                    spin: 0.3 * i as f64,
                    friction: 0.8 + 0.1 * i as f64,
                })
                .collect();
            let curl_parts: Vec<usize> = (0..curls).map(|c| c % parts).collect();
            (case, motions, curl_parts)
        })
        .collect();
    let motion = MotionParams::default();
    let mut runs: Vec<(Solver, PartDynamics)> = [(0, LinearizeAbout::Reported), (8, LinearizeAbout::Rest)]
        .iter()
        .map(|&(cycle_slots, about)| {
            let mut s =
                Solver::new(SolverCapacity::DEFAULT, SolverParams { cycle_slots, ..SolverParams::default() });
            assert!(s.warm_up());
            let params = PartDynamicsParams { steps: 3, about, ..PartDynamicsParams::default() };
            let dynamics =
                PartDynamics::new(params, PlateMotion::new(motion).expect("motion"), 48, s.new_solution())
                    .expect("params");
            (s, dynamics)
        })
        .collect();
    let mut out = runs[0].0.new_solution();
    let (mut corrected, mut kept_worse, mut steps) = (0, 0, 0);
    let ((), allocations) = allocations_in(|| {
        for (i, (case, motions, curl_parts)) in cases.iter().enumerate() {
            let problem = problem(case, i);
            let (solver, dynamics) = &mut runs[i % 2];
            if solver.solve(&problem, &mut out).is_ok() {
                let c = dynamics.correct(solver, &problem, motions, curl_parts, &mut out);
                // The guarantee: never worse than the uncorrected answer.
                kept_worse += usize::from(c.lack > c.lack_before);
                corrected += usize::from(c.lack < c.lack_before);
                steps += c.steps;
            }
        }
    });
    assert_eq!(allocations, 0, "part-dynamics corrections allocated {allocations} times");
    assert_eq!(kept_worse, 0, "an answer the model says is worse was kept");
    // Every path ran: re-solves, and kept answers other than the first
    // (how much they gain is the unit tests' and the bench's business).
    assert!(corrected > 0 && steps as usize >= cases.len(), "{corrected} improved, {steps} steps");
}

#[test]
fn the_counter_sees_allocations() {
    // Guard against a counter that can never fail.
    assert!(counter_installed());
}
