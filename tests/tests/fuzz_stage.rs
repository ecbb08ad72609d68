//! Fuzz: the solver stage's entry points (`SolveStage::on_*`), exactly as
//! the core's solver thread calls them after copying a message out of
//! shared memory. Any bytes, with or without a valid header and a fresh
//! stamp: no panic (a panic here is a dead solver thread in the core), and
//! every rejection counted once, under its reason.

use std::sync::Arc;

use ipc_types::{CoreCommand, ExplicitSchedule, ForceRequest, PartStates, REJECT_REASONS, RejectedKind};
use proptest::prelude::*;
use rt_core::{CoreParams, CoreShared, SolveStage, StagedMotion, motion_handoff};
use upm_motion::{PlateMotion, Rig};
use upm_tests::{from_bytes, patch_header};

const NOW: u64 = 5_000_000_000;

struct Stage {
    stage: SolveStage,
    shared: Arc<CoreShared>,
    outputs: rt_core::StageOutputsRx,
}

fn stage() -> Stage {
    let params = CoreParams::default();
    let rig = Rig::new(params.rig).expect("rig");
    let empty = PlateMotion::new(params.motion).expect("motion");
    let (writer, _reader) =
        motion_handoff(&StagedMotion { motion: empty, request_seq: 0, frame_stamp_ns: 0 });
    let shared = Arc::new(CoreShared::new());
    let (out, outputs) = rt_core::StageOutputs::rings();
    let k_bounds = params.playable_k_bounds().expect("playable");
    let stage = SolveStage::new(&params, rig, k_bounds, writer, shared.clone(), out).expect("stage");
    Stage { stage, shared, outputs }
}

fn rejected(shared: &CoreShared) -> u64 {
    let t = shared.rejected_by_reason();
    assert_eq!(t.len(), REJECT_REASONS);
    t.iter().sum()
}

/// Bytes of one message: random, or random with a valid header and a
/// stamp of `NOW` (so validation walks the body).
fn message(bytes: Vec<u8>, count: u32, patch: bool, stamp_at: usize) -> Vec<u8> {
    let mut b = bytes;
    b.resize(b.len().max(32), 0);
    if patch {
        patch_header(&mut b, count);
        b[stamp_at..stamp_at + 8].copy_from_slice(&NOW.to_ne_bytes());
    }
    b
}

fn body() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(any::<u8>(), 1..6000)
}

proptest! {
    #![proptest_config(upm_tests::fuzz_config(2048, 1))]

    #[test]
    fn the_stage_never_panics_and_counts_every_rejection(
        parts in body(), request in body(), explicit in body(), command in body(),
        counts in any::<[u32; 3]>(), small in any::<[bool; 3]>(), patch in any::<[bool; 4]>(),
    ) {
        let mut s = stage();
        // Counts within the capacities most of the time, any u32 otherwise.
        let count = |i: usize, cap: u32| if small[i] { counts[i] % (cap + 2) } else { counts[i] };
        // Stamps sit after protocol_version, count and seq (16 bytes in).
        let p: PartStates = from_bytes(&message(parts, count(0, 64), patch[0], 16));
        let r: ForceRequest = from_bytes(&message(request, count(1, 64), patch[1], 16));
        let e: ExplicitSchedule = from_bytes(&message(explicit, count(2, 192), patch[2], 16));
        let mut c: CoreCommand = from_bytes(&message(command, 0, false, 16));
        if patch[3] {
            c = CoreCommand { stamp_ns: NOW, ..CoreCommand::new(c.command % 3, c.seq, NOW) };
        }
        // Every refusal is counted once and answered once, to its sender:
        // its kind, its seq and stamp, a reason and a text naming the field.
        let mut refused = Vec::new();
        if s.stage.on_part_states(&p, NOW, NOW).is_err() {
            refused.push((RejectedKind::PartStates, p.seq, p.stamp_ns));
        }
        if s.stage.on_request(&r, NOW, &|| NOW).is_err() {
            refused.push((RejectedKind::ForceRequest, r.seq, r.stamp_ns));
        }
        if s.stage.on_explicit(&e, NOW).is_err() {
            refused.push((RejectedKind::ExplicitSchedule, e.seq, e.stamp_ns));
        }
        if s.stage.on_command(&c, NOW).is_err() {
            refused.push((RejectedKind::CoreCommand, c.seq, c.stamp_ns));
        }
        prop_assert_eq!(rejected(&s.shared), refused.len() as u64);
        let mut answers = Vec::new();
        while let Ok(a) = s.outputs.rejections.pop() {
            prop_assert!(a.reason().is_some() && !a.detail_str().is_empty(), "{a:?}");
            prop_assert_eq!(a.stamp_ns, NOW);
            answers.push((a.kind().expect("kind"), a.seq, a.message_stamp_ns));
        }
        prop_assert_eq!(answers, refused);
    }
}
