//! The core's motor loop and solver stage in lock-step (one thread,
//! hand-stepped clock), driving the physics simulator: determinism, hold on
//! stale input, rejection of bad messages, and schedule swaps only at cycle
//! boundaries.

mod common;

use common::{PAPER_PARTS, part_states, request};
use drivers::{SimConfig, Simulator};
use ipc_types::{CoreState, ExplicitSchedule, ExplicitSlot, ForceEntry, PROTOCOL_VERSION, PartState};
use rt_core::CoreParams;
use rt_core::lockstep::Lockstep;

const START_NS: u64 = 1_000_000_000;
const TICK_NS: u64 = 100_000;

fn core() -> Lockstep<Simulator> {
    let sim = Simulator::new(SimConfig::default(), &[]).expect("sim");
    Lockstep::new(&CoreParams::default(), sim, START_NS).expect("core")
}

/// Feed fresh part states and a request every `every` ticks while `feed(t)`.
fn run_fed(
    core: &mut Lockstep<Simulator>,
    ticks: u64,
    every: u64,
    feed: impl Fn(u64) -> bool,
    mut each: impl FnMut(u64, &Lockstep<Simulator>),
) {
    let mut seq = 0;
    for t in 0..ticks {
        if t % every == 0 && feed(t) {
            seq += 1;
            let now = core.now_ns();
            let scale = if t < ticks / 2 { 1.0 } else { 0.5 };
            core.inbox().push_parts(&part_states(seq, now, &PAPER_PARTS));
            core.inbox().push_request(&request(seq, now, &PAPER_PARTS, scale));
        }
        core.run_ticks(1, |_| {});
        each(t, core);
    }
}

/// Everything observable per tick, as bits.
fn record(ticks: u64) -> Vec<[u64; 6]> {
    let mut c = core();
    let mut rec = Vec::new();
    run_fed(
        &mut c,
        ticks,
        100,
        |_| true,
        |_, c| {
            let s = c.motor().plate_state();
            let [x, y, th] = c.shared().pose();
            rec.push([
                s.pose.x.to_bits(),
                s.pose.theta.to_bits(),
                x.to_bits() ^ y.to_bits(),
                th.to_bits(),
                c.shared().schedule_swaps.load(core::sync::atomic::Ordering::Relaxed),
                c.shared().state() as u64,
            ]);
        },
    );
    assert!(
        c.shared().schedule_swaps.load(core::sync::atomic::Ordering::Relaxed) > 5,
        "schedules were played"
    );
    rec
}

#[test]
fn lockstep_runs_are_bit_identical() {
    let a = record(4000);
    let b = record(4000);
    assert_eq!(a.len(), b.len());
    assert!(a == b, "record A != record B");
    // The plate really moved (the comparison is not between two idle runs).
    assert!(a.iter().any(|r| f64::from_bits(r[1]) != 0.0));
}

#[test]
fn plays_solved_schedule_and_swaps_only_at_cycle_boundaries() {
    let mut c = core();
    let mut prev_pose = [0.0; 3];
    let mut prev_swaps = 0;
    let mut swaps_seen = 0;
    let mut running_ticks = 0;
    run_fed(
        &mut c,
        3000,
        37,
        |_| true,
        |_, c| {
            let swaps = c.shared().schedule_swaps.load(core::sync::atomic::Ordering::Relaxed);
            if swaps != prev_swaps {
                // The plate was home when the new schedule took over.
                assert_eq!(prev_pose, [0.0; 3], "schedule swapped mid-cycle");
                swaps_seen += 1;
            }
            if c.shared().state() == CoreState::Running {
                running_ticks += 1;
            }
            prev_swaps = swaps;
            prev_pose = c.shared().pose();
        },
    );
    assert!(swaps_seen > 3);
    assert!(running_ticks > 2500, "running ticks {running_ticks}");
    let published = c.published();
    assert!(!published.is_empty());
    // The published schedule is the solver's answer for the paper's §3.1.
    let s = &published[0];
    assert_eq!(s.len(), 4);
    let mut k = [0.0; 4];
    for slot in s.slots() {
        k[slot.center_index as usize] = slot.k;
    }
    for (got, want) in k.iter().zip([0.584f64, -0.389, 0.480, -0.0946]) {
        assert!((got - want).abs() < 0.006, "k {k:?}");
    }
}

#[test]
fn stale_input_holds_within_one_cycle_and_fresh_input_resumes() {
    let params = CoreParams::default();
    let max_age_ticks = params.safety.parts_max_age_ns / TICK_NS;
    let mut c = core();
    let stop_feeding = 1000;
    let resume = 5000;
    let mut first_hold = None;
    let mut resumed_at = None;
    run_fed(
        &mut c,
        7000,
        50,
        |t| !(stop_feeding..resume).contains(&t),
        |t, c| {
            let state = c.shared().state();
            if state == CoreState::Hold {
                first_hold.get_or_insert(t);
                assert_eq!(c.shared().pose(), [0.0; 3], "plate moved while holding");
            }
            if t > resume && state == CoreState::Running {
                resumed_at.get_or_insert(t);
            }
        },
    );
    let cycle = 4 * params.motion.slot_ticks as u64;
    let last_input = stop_feeding - 50;
    let hold = first_hold.expect("core never held");
    assert!(hold > last_input + max_age_ticks, "held too early at {hold}");
    assert!(
        hold <= last_input + max_age_ticks + cycle + 1,
        "held at {hold}, later than one cycle after stale"
    );
    let resumed = resumed_at.expect("core never resumed");
    assert!(resumed <= resume + cycle + 1, "resumed at {resumed}");
    assert_eq!(c.shared().hold_events.load(core::sync::atomic::Ordering::Relaxed), 1);
}

#[test]
fn bad_messages_are_rejected_and_counted_and_the_core_keeps_running() {
    use core::sync::atomic::Ordering::Relaxed;
    let mut c = core();
    run_fed(&mut c, 500, 50, |_| true, |_, _| {});
    assert_eq!(c.shared().state(), CoreState::Running);
    let now = c.now_ns();
    let good = part_states(100, now, &PAPER_PARTS);

    let mut bad_parts = Vec::new();
    let mut m = good;
    m.parts_mut()[0].x = f64::NAN;
    bad_parts.push(m);
    let mut m = good;
    m.protocol_version = PROTOCOL_VERSION + 1;
    bad_parts.push(m);
    let mut m = good;
    m.count = 1000;
    bad_parts.push(m);
    let mut m = good;
    m.parts_mut()[1].id = m.parts()[0].id;
    bad_parts.push(m);
    let mut m = good;
    m.parts_mut()[0] = PartState::new(1, 0, 0, [5.0, 0.0, 0.0], [0.0; 3]);
    bad_parts.push(m);
    let mut m = good;
    m.stamp_ns = now + 10_000_000_000;
    bad_parts.push(m);
    let mut m = good;
    m.parts_mut()[1] = m.parts()[1].with_disc(-0.01);
    bad_parts.push(m);

    let good_req = request(100, now, &PAPER_PARTS, 1.0);
    let mut bad_reqs = Vec::new();
    let mut r = good_req;
    r.entries_mut()[0].fx = f64::INFINITY;
    bad_reqs.push(r);
    let mut r = good_req;
    r.entries_mut()[0] = ForceEntry::force(99, [0.01, 0.0]);
    bad_reqs.push(r);
    let mut r = good_req;
    r.count = u32::MAX;
    bad_reqs.push(r);
    let mut r = good_req;
    r.protocol_version = 0;
    bad_reqs.push(r);

    let mut explicit = ExplicitSchedule::new();
    explicit.stamp_ns = now;
    explicit.push(ExplicitSlot::new(0, 1.5)).expect("capacity");
    let mut explicit_bad_center = ExplicitSchedule::new();
    explicit_bad_center.stamp_ns = now;
    explicit_bad_center.push(ExplicitSlot::new(17, 0.1)).expect("capacity");

    for m in &bad_parts {
        c.inbox().push_parts(m);
    }
    for r in &bad_reqs {
        c.inbox().push_request(r);
    }
    c.inbox().push_explicit(&explicit);
    c.inbox().push_explicit(&explicit_bad_center);
    let swaps_before = c.shared().schedule_swaps.load(Relaxed);
    run_fed(&mut c, 1000, 50, |_| true, |_, c| assert_ne!(c.shared().state(), CoreState::Fault));
    assert_eq!(c.shared().rejected_parts.load(Relaxed), bad_parts.len() as u64);
    assert_eq!(c.shared().rejected_requests.load(Relaxed), bad_reqs.len() as u64 + 2);
    assert_eq!(c.shared().state(), CoreState::Running);
    assert!(c.shared().schedule_swaps.load(Relaxed) > swaps_before, "good input still played");
    // The plate never left the actuators' limits.
    assert_eq!(c.motor().plate_state().rejected, 0);
}

#[test]
fn explicit_schedule_bypasses_the_solver() {
    let mut c = core();
    let now = c.now_ns();
    c.inbox().push_parts(&part_states(1, now, &PAPER_PARTS));
    let mut e = ExplicitSchedule::new();
    e.seq = 7;
    e.stamp_ns = now;
    e.push(ExplicitSlot::new(2, 0.3)).expect("capacity");
    e.push(ExplicitSlot::new(0, -0.2)).expect("capacity");
    c.inbox().push_explicit(&e);
    c.run_ticks(200, |_| {});
    assert_eq!(c.shared().state(), CoreState::Running);
    let s = c.published().last().expect("published");
    assert_eq!(s.seq, 7);
    let slots: Vec<_> = s.slots().iter().map(|s| (s.center_index, s.k)).collect();
    assert_eq!(slots, vec![(2, 0.3), (0, -0.2)]);
}

/// Each center is bounded by what it can play on the rig, not all by the
/// weakest: an explicit slot between two centers' bounds plays about the
/// stronger and is refused, by name and counted, about the weaker; solved
/// schedules keep every slot within its own center's bound.
#[test]
fn each_center_is_bounded_by_what_it_can_play() {
    use core::sync::atomic::Ordering::Relaxed;
    let mut params = CoreParams::default();
    params.plate.centers.push([2.5, 0.0]);
    let far = params.plate.centers.len() - 1;
    let sim = Simulator::new(SimConfig::default(), &[]).expect("sim");
    let mut c = Lockstep::new(&params, sim, START_NS).expect("core");
    let bounds = c.stage().k_bounds().to_vec();
    assert_eq!(bounds.len(), params.plate.centers.len());
    assert!(bounds[far] < bounds[0], "bounds {bounds:?}");
    assert_eq!(c.stage().k_max(), bounds.iter().fold(0.0, |a: f64, &u| a.max(u)));
    let k = 0.5 * (bounds[far] + bounds[0]);
    let now = c.now_ns();
    c.inbox().push_parts(&part_states(1, now, &PAPER_PARTS));
    let explicit = |seq: u64, center: u32| {
        let mut e = ExplicitSchedule::new();
        e.seq = seq;
        e.stamp_ns = now + seq;
        e.push(ExplicitSlot::new(center, k)).expect("capacity");
        e
    };
    c.inbox().push_explicit(&explicit(1, 0));
    c.run_ticks(200, |_| {});
    let s = c.published().last().expect("published");
    assert_eq!((s.seq, s.slots()[0].k), (1, k));
    c.inbox().push_explicit(&explicit(2, far as u32));
    c.run_ticks(200, |_| {});
    assert_eq!(c.shared().rejected_requests.load(Relaxed), 1);
    let r = c.rejections().last().expect("rejection");
    assert_eq!(r.reason, ipc_types::RejectReason::KOutOfRange as u32, "{r:?}");
    // A request far beyond what a cycle gives: every slot within its bound.
    run_fed(&mut c, 3000, 100, |_| true, |_, _| {});
    let solved: Vec<_> = c.published().iter().filter(|s| s.parts_seq != 0).collect();
    assert!(!solved.is_empty());
    for s in solved {
        for slot in s.slots() {
            let u = bounds[slot.center_index as usize];
            assert!(slot.k.abs() <= u, "slot k {} beyond center {}'s {u}", slot.k, slot.center_index);
        }
    }
}

/// The k the core publishes for the paper's §3.1 request when part 1 (at
/// (0.5, 0), 0.5 m from the nearest corner center) is `part_1` and the
/// core's `part_shapes` is as given.
fn published_k(part_1: PartState, part_shapes: bool) -> Vec<u64> {
    let mut params = CoreParams::default();
    params.motion.part_shapes = part_shapes;
    published_k_with(part_1, &params)
}

fn published_k_with(part_1: PartState, params: &CoreParams) -> Vec<u64> {
    let sim = Simulator::new(SimConfig::default(), &[]).expect("sim");
    let mut c = Lockstep::new(params, sim, START_NS).expect("core");
    let now = c.now_ns();
    let mut parts = part_states(1, now, &PAPER_PARTS);
    parts.parts_mut()[0] = part_1;
    c.inbox().push_parts(&parts);
    c.inbox().push_request(&request(1, now, &PAPER_PARTS, 1.0));
    c.run_ticks(10, |_| {});
    assert!(c.rejections().is_empty(), "{:?}", c.rejections().first().map(|r| r.detail_str().to_owned()));
    let s = c.published().first().expect("a schedule");
    let mut k = vec![0; 4];
    for slot in s.slots() {
        k[slot.center_index as usize] = slot.k.to_bits();
    }
    k
}

/// `[motion.part_dynamics]`: the core's answer depends on the velocity and
/// spin vision reports exactly when it is linearized about them; off, it
/// is the solver's answer as before; and it is deterministic.
#[test]
fn a_parts_reported_motion_reaches_the_part_dynamics_correction() {
    use upm_motion::LinearizeAbout;
    let still = PartState::new(1, 0, 0, [0.5, 0.0, 0.0], [0.0; 3]);
    let sliding = PartState::new(1, 0, 0, [0.5, 0.0, 0.0], [0.01, -0.004, 0.0]);
    let with = |steps, about| {
        let mut p = CoreParams::default();
        p.motion.part_dynamics.steps = steps;
        p.motion.part_dynamics.about = about;
        p
    };
    let off = with(0, LinearizeAbout::Reported);
    let reported = with(2, LinearizeAbout::Reported);
    let rest = with(2, LinearizeAbout::Rest);
    let uncorrected = published_k_with(still, &off);
    assert_eq!(published_k_with(sliding, &off), uncorrected, "off: the velocity is not read");
    assert_ne!(published_k_with(still, &rest), uncorrected, "the correction changed nothing");
    assert_eq!(
        published_k_with(sliding, &rest),
        published_k_with(still, &rest),
        "from rest: velocity ignored"
    );
    let moving = published_k_with(sliding, &reported);
    assert_ne!(moving, published_k_with(still, &reported), "the reported velocity changed nothing");
    assert_eq!(moving, published_k_with(sliding, &reported), "deterministic");
    // A calibration's friction for the part's class slides it harder.
    let gripping = PartState::new(1, 1, 0, [0.5, 0.0, 0.0], [0.0; 3]);
    let calibrated = CoreParams {
        part_friction: upm_motion::PartFriction::new(&[(0, 1.0), (1, 1.3)], [0.0; 5], [1.0, 0.5])
            .expect("friction"),
        ..rest.clone()
    };
    assert_eq!(published_k_with(gripping, &rest), published_k_with(still, &rest), "uniform: class ignored");
    assert_eq!(published_k_with(still, &calibrated), published_k_with(still, &rest), "class 0 is the model");
    assert_ne!(
        published_k_with(gripping, &calibrated),
        published_k_with(still, &rest),
        "class 1's friction ignored"
    );
    let mut off_calibrated = calibrated;
    off_calibrated.motion.part_dynamics = off.motion.part_dynamics;
    assert_eq!(published_k_with(gripping, &off_calibrated), uncorrected, "off: friction is not read");
}

#[test]
fn a_parts_outline_reaches_the_solver() {
    use upm_solver::{ForceConstraint, PartShape, Problem, Solver, SolverCapacity, SolverParams};
    let point = PartState::new(1, 0, 0, [0.5, 0.0, 0.3], [0.0; 3]);
    // A large disc and a turned square: their patches feel the rotations
    // differently from a point at their centre.
    let disc = point.with_disc(0.3);
    let square =
        point.with_polygon(&[[0.2, 0.2], [-0.2, 0.2], [-0.2, -0.2], [0.2, -0.2]]).expect("4 vertices");
    let at_point = published_k(point, true);
    for shaped in [disc, square] {
        assert_ne!(published_k(shaped, true), at_point, "the outline changed nothing");
        assert_eq!(published_k(shaped, false), at_point, "part_shapes = false is the point model");
    }
    // What the core played is the solver's answer for the outline, turned
    // by the part's angle into plate axes.
    let params = CoreParams::default();
    let bounds = params.playable_k_bounds().expect("bounds");
    let k_max = bounds.iter().copied().fold(0.0, f64::max);
    let constraints: Vec<ForceConstraint> = PAPER_PARTS
        .iter()
        .map(|&(id, p, f)| ForceConstraint {
            position: p,
            force: Some(f),
            shape: if id == 1 { PartShape::from_wire(&square) } else { PartShape::Point },
        })
        .collect();
    let problem = Problem {
        mu_m_g: params.plate.mu_m_g,
        k_max,
        centers: &params.plate.centers,
        parts: &constraints,
        curls: &[],
        k_bounds: &bounds,
    };
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    solver.solve(&problem, &mut out).expect("solve");
    let want: Vec<u64> = out.k().iter().map(|k| k.to_bits()).collect();
    assert_eq!(published_k(square, true), want);
    let PartShape::Polygon { vertices, .. } = PartShape::from_wire(&square) else { panic!("a polygon") };
    let (s, c) = 0.3f64.sin_cos();
    assert!((vertices[0][0] - (0.2 * c - 0.2 * s)).abs() < 1e-15, "{vertices:?}");
}

/// Mean squared gap (m²) between the plate the driver reports at each
/// tick and the pose the previous tick commanded, over the last half of
/// `ticks`, and what the motor's feed-forward ended up taking the plate to
/// be; on a plate 10 % heavier than the model.
fn tracking_on_a_heavier_plate(adapt: bool, ticks: u64) -> (f64, rt_core::InertiaReport) {
    let mut truth = drivers::PlateTruth::NOMINAL;
    truth.plate_mass_error = 0.10;
    let sim = Simulator::new(SimConfig { truth, ..SimConfig::default() }, &[]).expect("sim");
    let params = CoreParams {
        inertia_adaptation: adapt.then(upm_motion::InertiaParams::default),
        ..CoreParams::default()
    };
    let mut c = Lockstep::new(&params, sim, START_NS).expect("core");
    let (mut sum, mut n, mut commanded) = (0.0, 0u64, None::<[f64; 3]>);
    run_fed(
        &mut c,
        ticks,
        100,
        |_| true,
        |t, c| {
            let s = c.motor().plate_state().pose;
            if let Some([x, y, _]) = commanded.filter(|_| t > ticks / 2) {
                sum += (s.x - x).powi(2) + (s.y - y).powi(2);
                n += 1;
            }
            commanded = Some(c.shared().pose());
        },
    );
    (sum / n.max(1) as f64, c.shared().inertia())
}

#[test]
fn the_motor_learns_a_heavier_plate_from_its_drives_and_tracks_it_closer() {
    let (adapted, learnt) = tracking_on_a_heavier_plate(true, 20_000);
    let (fixed, model) = tracking_on_a_heavier_plate(false, 20_000);
    assert_eq!((model.scale, model.updates), ([1.0; 2], 0), "adaptation off touches nothing");
    assert!(learnt.updates > 10 && learnt.skipped == 0, "{learnt:?}");
    assert!((learnt.scale[0] - 1.10).abs() < 1e-3, "mass {learnt:?}");
    assert!((learnt.scale[1] - 1.10).abs() < 1e-2, "inertia {learnt:?}");
    // The plate lags each fast phase less when the feed-forward is right.
    assert!(adapted < 0.01 * fixed, "tracking {adapted:e} adapted vs {fixed:e} fixed (m²)");
}
