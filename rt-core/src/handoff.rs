//! Wait-free hand-over of the next plate motion from the solver thread to
//! the motor thread (a triple buffer: neither side ever waits or
//! allocates). The motor only looks for a new motion at a cycle boundary,
//! so every cycle it plays is closed.

use triple_buffer::{Input, Output};

use upm_motion::PlateMotion;

/// A motion ready to play, with what produced it.
#[derive(Debug, Clone)]
pub struct StagedMotion {
    pub motion: PlateMotion,
    /// Sequence number of the request (or explicit schedule) it answers.
    pub request_seq: u64,
    /// Camera-frame stamp of the part states it was solved from (ns).
    pub frame_stamp_ns: u64,
}

/// Solver side.
#[derive(Debug)]
pub struct MotionWriter(Input<StagedMotion>);

/// Motor side.
#[derive(Debug)]
pub struct MotionReader(Output<StagedMotion>);

/// One writer, one reader, sharing three preallocated motions.
pub fn motion_handoff(initial: &StagedMotion) -> (MotionWriter, MotionReader) {
    let (i, o) = triple_buffer::triple_buffer(initial);
    (MotionWriter(i), MotionReader(o))
}

impl MotionWriter {
    /// The back buffer to fill in place (its content is stale: overwrite all).
    pub fn staging(&mut self) -> &mut StagedMotion {
        self.0.input_buffer_mut()
    }

    /// Make the staged motion the newest one.
    pub fn publish(&mut self) {
        self.0.publish();
    }
}

impl MotionReader {
    /// Switch to the newest published motion if there is one; true if so.
    pub fn take_newest(&mut self) -> bool {
        self.0.update()
    }

    /// The motion being played.
    pub fn current(&self) -> &StagedMotion {
        self.0.peek_output_buffer()
    }
}
