//! The whole core in one test: the motor loop and the solve stage in
//! lock-step on a hand-stepped clock, on the ideal mock driver. Feed it
//! part states and a force request as vision and a planner would, run
//! ticks, and look at what it published — deterministic to the bit.

use ipc_types::{CoreState, ForceEntry, ForceRequest, PartState, PartStates};
use rt_core::CoreParams;
use rt_core::lockstep::Lockstep;
use upm_hardware::IdealDriver;

const START_NS: u64 = 1_000_000_000;

/// The paper's §3.1 parts and the forces asked of them (N).
const PARTS: [(u32, [f64; 2], [f64; 2]); 2] =
    [(1, [0.5, 0.0], [0.01, 0.01]), (2, [-0.75, 0.25], [-0.01, 0.0])];

fn core() -> Lockstep<IdealDriver> {
    let params = CoreParams::default();
    let driver = IdealDriver::new(params.rig, params.motion.tick_hz).expect("the default rig");
    Lockstep::new(&params, driver, START_NS).expect("the default parameters")
}

/// Fresh part states and a request every `every` ticks, for `ticks` ticks;
/// returns every tick's plate pose, as bits.
fn run(core: &mut Lockstep<IdealDriver>, ticks: u64, every: u64) -> Vec<[u64; 3]> {
    let mut poses = Vec::new();
    for t in 0..ticks {
        if t % every == 0 {
            let (seq, now) = (t / every + 1, core.now_ns());
            let mut states = PartStates::new();
            let mut request = ForceRequest::new();
            (states.seq, states.stamp_ns) = (seq, now);
            (request.seq, request.stamp_ns, request.deadline_ns) = (seq, now, now + 1_000_000_000);
            for (id, p, f) in PARTS {
                states.push(PartState::new(id, 0, 0, [p[0], p[1], 0.0], [0.0; 3])).expect("capacity");
                request.push(ForceEntry::force(id, f)).expect("capacity");
            }
            core.inbox().push_parts(&states);
            core.inbox().push_request(&request);
        }
        core.run_ticks(1, |_| {});
        let pose = core.motor().plate_state().pose;
        poses.push([pose.x.to_bits(), pose.y.to_bits(), pose.theta.to_bits()]);
    }
    poses
}

#[test]
fn the_core_answers_the_papers_example_in_lockstep() {
    let mut c = core();
    run(&mut c, 3000, 100);
    assert_eq!(c.shared().state(), CoreState::Running);
    let schedule = c.published().first().expect("a schedule was published");
    // The paper's §3.1 answer: K = (.58, −.39, .48, −.095) on the corners.
    let mut k = [0.0; 4];
    for slot in schedule.slots() {
        k[slot.center_index as usize] = slot.k;
    }
    for (got, want) in k.iter().zip([0.58, -0.39, 0.48, -0.095]) {
        assert!((got - want).abs() < 0.01, "k = {k:?}");
    }
    assert!(c.rejections().is_empty(), "{:?}", c.rejections());
}

#[test]
fn two_runs_are_bit_identical() {
    let (a, b) = (run(&mut core(), 2000, 100), run(&mut core(), 2000, 100));
    assert!(a == b, "record A != record B");
    assert!(a.iter().any(|p| f64::from_bits(p[2]) != 0.0), "the plate turned");
}
