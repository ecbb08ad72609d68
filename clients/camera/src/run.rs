//! The rendered camera's loop: the newest ground truth in, one frame per
//! period out on `upm/camera/frame`.

use std::time::Duration;

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use ipc_types::ports::FramePub;
use ipc_types::rig_node::rig_node;
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{FrameHeader, PartStates, monotonic_now_ns, service_names};

use crate::Renderer;

/// Run the rendered camera on `prefix` until SIGINT/SIGTERM (or
/// `duration`); returns the frames published.
pub fn run(
    prefix: &str,
    mut renderer: Renderer,
    frame_hz: f64,
    duration: Option<Duration>,
) -> anyhow::Result<u64> {
    let (w, h) = (renderer.model().width, renderer.model().height);
    let node = rig_node(prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
    let truth = ipc_types::ports::subscriber::<PartStates>(&node, service_names::SIM_GROUND_TRUTH)?;
    let mut frames = FrameOut::open(&node, (w * h) as usize)?;
    let period_ns = (1e9 / frame_hz) as u64;
    let exposure_ns = (renderer.camera().exposure_s * 1e9) as u64;
    let start = monotonic_now_ns();
    let end = duration.map(|d| start + d.as_nanos() as u64);
    let mut next = start;
    let mut newest: Option<PartStates> = None;
    let mut last_stamp = None;
    let mut seq = 0;
    loop {
        while let Some(s) = truth.receive().map_err(|e| anyhow::anyhow!("receiving ground truth: {e:?}"))? {
            newest = Some(*s.payload());
        }
        let now = monotonic_now_ns();
        if now >= next {
            next = (next + period_ns).max(now);
            // No core yet (or the same truth again): no new frame.
            if let Some(t) = &newest
                && last_stamp != Some(t.stamp_ns)
            {
                last_stamp = Some(t.stamp_ns);
                seq += 1;
                let pixels = renderer.render(t);
                let header =
                    FrameHeader { seq, stamp_ns: t.stamp_ns, exposure_ns, ..FrameHeader::mono8(w, h) };
                frames.publish(header, pixels)?;
            }
        }
        if end.is_some_and(|e| now >= e) {
            return Ok(seq);
        }
        let wait = Duration::from_nanos(next.saturating_sub(monotonic_now_ns()).clamp(100_000, 2_000_000));
        match node.wait(wait) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => return Ok(seq),
        }
    }
}

/// A frame source's output: the frame publisher and the frame event.
#[derive(Debug)]
pub struct FrameOut {
    frames: FramePub,
    wake: WakeNotifier,
}

impl FrameOut {
    /// Frames up to `max_bytes` of pixels.
    pub fn open(node: &Node<ipc::Service>, max_bytes: usize) -> anyhow::Result<Self> {
        let frames = ipc_types::ports::frame_publisher(node, max_bytes)?;
        let wake = WakeNotifier::new(node, WakeEvent::Frame)?;
        Ok(Self { frames, wake })
    }

    /// Loan a frame, fill it with `header` and `pixels`, send it, wake
    /// vision.
    pub fn publish(&mut self, header: FrameHeader, pixels: &[u8]) -> anyhow::Result<()> {
        let mut sample = self
            .frames
            .loan_slice_uninit(pixels.len())
            .map_err(|e| anyhow::anyhow!("loaning a frame: {e:?}"))?;
        *sample.user_header_mut() = header;
        sample.write_from_slice(pixels).send().map_err(|e| anyhow::anyhow!("publishing a frame: {e:?}"))?;
        self.wake.notify();
        Ok(())
    }
}
