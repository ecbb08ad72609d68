//! Fuzz: the solver on any input a client could send. Hostile numbers
//! (NaN, ±inf, huge, subnormal), parts sitting on centers, sizes beyond the
//! capacity. A solve must return an error or an answer that keeps every
//! promise (|k| ≤ k_max, finite, achieved forces truthful), never panic,
//! and never allocate.

use proptest::prelude::*;
use proptest::test_runner::TestRunner;
use rt_core::alloc_count;
use upm_solver::field::cycle_force;
use upm_solver::{CurlConstraint, ForceConstraint, Problem, Solver, SolverCapacity, SolverParams};

#[global_allocator]
static ALLOC: rt_core::RtAllocCounter = rt_core::RtAllocCounter;

/// One solve request, owned so proptest can generate it.
#[derive(Debug, Clone)]
struct Input {
    mu_m_g: f64,
    k_max: f64,
    centers: Vec<[f64; 2]>,
    parts: Vec<ForceConstraint>,
    curls: Vec<CurlConstraint>,
}

/// Mostly plate-sized numbers, one in `1 + plain / 2` anything an f64 can
/// hold: set `plain` so most problems are still valid.
fn number(plain: u32) -> impl Strategy<Value = f64> {
    prop_oneof![
        plain => -2.0..2.0f64,
        1 => any::<f64>(),
        1 => prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -0.0, 1e300, -1e300, 1e-300, f64::MIN_POSITIVE / 4.0]),
    ]
}

fn point(plain: u32) -> impl Strategy<Value = [f64; 2]> {
    [number(plain), number(plain)]
}

fn input(max_parts: usize, max_curls: usize, max_centers: usize) -> impl Strategy<Value = Input> {
    // ≈ one hostile number per problem on average.
    let plain = (10 * (2 * max_parts + 3 * max_curls + 2 * max_centers)) as u32;
    let part = (point(plain), prop::option::weighted(0.9, point(plain))).prop_map(|(position, force)| {
        ForceConstraint { position, force, shape: upm_solver::PartShape::Point }
    });
    let curl = (point(plain), number(plain)).prop_map(|(position, curl)| CurlConstraint {
        position,
        curl,
        shape: upm_solver::PartShape::Point,
    });
    (
        prop_oneof![20 => 0.01..10.0f64, 1 => number(1)],
        prop_oneof![20 => 0.05..=1.0f64, 1 => number(1)],
        prop::collection::vec(point(plain), 0..=max_centers),
        prop::collection::vec(part, 0..=max_parts),
        prop::collection::vec(curl, 0..=max_curls),
        // Sometimes put a part on, or a hair away from, a center.
        (prop::bool::weighted(0.1), any::<prop::sample::Index>(), any::<prop::sample::Index>(), 0.0..2e-6f64),
    )
        .prop_map(|(mu_m_g, k_max, centers, mut parts, curls, (snap, pi, ci, eps))| {
            if snap && !parts.is_empty() && !centers.is_empty() {
                let c: [f64; 2] = centers[ci.index(centers.len())];
                let i = pi.index(parts.len());
                parts[i].position = [c[0] + eps, c[1]];
            }
            Input { mu_m_g, k_max, centers, parts, curls }
        })
}

fn all_finite(i: &Input) -> bool {
    let p = |q: &[f64; 2]| q.iter().all(|v| v.is_finite());
    i.mu_m_g.is_finite()
        && i.k_max.is_finite()
        && i.centers.iter().all(p)
        && i.parts.iter().all(|c| p(&c.position) && c.force.is_none_or(|f| p(&f)))
        && i.curls.iter().all(|c| p(&c.position) && c.curl.is_finite())
}

/// Solve on an RT-marked thread and check every promise of the answer.
/// Ok(true) when the solve succeeded and its answer kept every promise.
fn check(solver: &mut Solver, out: &mut upm_solver::Solution, i: &Input) -> Result<bool, TestCaseError> {
    let problem = Problem {
        mu_m_g: i.mu_m_g,
        k_max: i.k_max,
        centers: &i.centers,
        parts: &i.parts,
        curls: &i.curls,
        k_bounds: &[],
    };
    let (verdict, allocated) = alloc_count::allocations_in(|| solver.solve(&problem, out));
    prop_assert_eq!(allocated, 0, "the solve allocated");
    if let Err(e) = verdict {
        prop_assert!(!e.to_string().is_empty() && !e.to_string().contains('\n'));
        return Ok(false);
    }
    prop_assert!(all_finite(i), "accepted a non-finite input");
    prop_assert!(i.mu_m_g > 0.0 && i.k_max > 0.0 && i.k_max <= 1.0, "accepted mu_m_g/k_max out of range");
    let n = i.centers.len();
    prop_assert_eq!(out.k().len(), n);
    for &k in out.k() {
        prop_assert!(
            k.is_finite() && k.abs() <= i.k_max * (1.0 + 1e-12),
            "k = {} beyond k_max {}",
            k,
            i.k_max
        );
    }
    let mut seen = vec![false; n];
    for &j in out.order() {
        prop_assert!((j as usize) < n && !seen[j as usize], "order is not a permutation");
        seen[j as usize] = true;
    }
    prop_assert!(seen.iter().all(|&s| s));
    let pr = out.priority();
    prop_assert!(
        out.order().windows(2).all(|w| pr[w[0] as usize] >= pr[w[1] as usize]),
        "order not by priority"
    );
    prop_assert!(out.residual.is_finite() && out.residual >= 0.0);
    prop_assert!(!out.condition.is_nan() && out.rank <= n);
    // Achieved forces are reported truthfully: the field of the returned K.
    prop_assert_eq!(out.achieved_forces().len(), i.parts.len());
    let scale =
        i.mu_m_g * (n as f64) * (1.0 + i.centers.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())));
    for (c, got) in i.parts.iter().zip(out.achieved_forces()) {
        let want = cycle_force(out.k(), &i.centers, i.mu_m_g, c.position);
        for d in 0..2 {
            prop_assert!(
                (got[d] - want[d]).abs() <= 1e-9 * scale,
                "achieved force {:?} but K gives {:?}",
                got,
                want
            );
        }
    }
    Ok(true)
}

fn run(cap: SolverCapacity, ci_cases: u32, weight: u32, strategy: impl Strategy<Value = Input>) {
    let mut solver = Solver::new(cap, SolverParams::default());
    assert!(solver.warm_up(), "warm-up solve failed");
    let out = std::cell::RefCell::new(solver.new_solution());
    let solver = std::cell::RefCell::new(solver);
    let mut config = upm_tests::fuzz_config(ci_cases, weight);
    // proptest! sets this; a hand-made runner must, or failures are not saved.
    config.source_file = Some(file!());
    let cases = config.cases;
    let mut runner = TestRunner::new(config);
    let solved = std::cell::Cell::new(0u32);
    let result = runner.run(&strategy, |i| {
        let ok = check(&mut solver.borrow_mut(), &mut out.borrow_mut(), &i)?;
        solved.set(solved.get() + u32::from(ok));
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    // Most cases must reach the numerics, not stop at input validation.
    eprintln!("{} of {cases} hostile problems solved, the rest refused", solved.get());
    assert!(solved.get() >= cases / 5, "only {} of {cases} cases got past validation", solved.get());
}

#[test]
fn small_hostile_problems_are_refused_or_solved_within_bounds() {
    run(SolverCapacity::DEFAULT, 20_000, 1, input(8, 3, 16));
}

#[test]
fn problems_up_to_and_beyond_capacity_are_refused_or_solved_within_bounds() {
    let cap = SolverCapacity::DEFAULT;
    // Solves near capacity cost ~20 ms each (bounded path): 1 % of the cases.
    run(cap, 10_000, 100, input(cap.parts + 2, cap.curls + 2, cap.centers + 2));
}
