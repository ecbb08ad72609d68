//! What a validation run plays its schedule with.

use drivers::SimConfig;
use upm_motion::MotionParams;

/// Simulator substeps per motor tick when measuring (the most it takes).
/// The plate's servo is stepped to first order, so a cycle's mean friction
/// is off by about 0.25/substeps of the request: 0.4 % here, where the
/// rig's default of one is off by several percent on many-slot cycles
/// (BENCHMARKS.md, "Forces and curls on extended parts").
pub const MEASURE_SUBSTEPS: u32 = 64;

/// Motion and simulator settings of a validation run.
#[derive(Debug, Clone, Copy)]
pub struct ValidateSetup {
    pub motion: MotionParams,
    pub sim: SimConfig,
    /// A plate calibration's twist correction the motion is played through.
    pub twist_correction: Option<[[f64; 3]; 3]>,
    /// As the core does (`[motion] adapt_plate_inertia`): the feed-forward
    /// follows `upm_motion::InertiaEstimate`, after this many cycles
    /// of the schedule played first to let it settle; None: the model's
    /// feed-forward, no warm-up.
    pub inertia_warmup: Option<usize>,
}

impl Default for ValidateSetup {
    fn default() -> Self {
        // Parts are measured independently: no part–part contact.
        Self {
            motion: MotionParams::default(),
            sim: SimConfig { collisions: false, substeps: MEASURE_SUBSTEPS, ..SimConfig::default() },
            twist_correction: None,
            inertia_warmup: None,
        }
    }
}
