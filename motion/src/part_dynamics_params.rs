//! `[motion.part_dynamics]`: the tunables of the core's correction for
//! each part's own velocity and spin, and their check.

use core::fmt;

use serde::{Deserialize, Serialize};

use crate::plate_follow::PlateFollow;

/// The state each part's cycle starts from (`about` in
/// `[motion.part_dynamics]`: `"reported"` or `"rest"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LinearizeAbout {
    /// The velocity and spin vision reports: the request is the mean force
    /// the part feels as it moves now. A planner then gets no damping from
    /// the plate and must ask for it (the drive's velocity gain, `spin`'s
    /// `damping`).
    #[default]
    Reported,
    /// Rest at every cycle's start: only what the part picks up within the
    /// cycle is corrected (what `upm solve --part-dynamics` does), so the
    /// plate's drag on a moving part stays as the paper's model has it.
    Rest,
}

/// Tunables of the correction, read as they are from
/// `[motion.part_dynamics]` (the fields a rig file does not set are the
/// callers').
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PartDynamicsParams {
    /// Correction steps after the first answer; 0 turns it off.
    pub steps: u32,
    pub about: LinearizeAbout,
    /// μ·g of the parts (m/s²): how fast friction changes a sliding
    /// part's velocity. With `CoreParams::mu_m_g` it gives their mass.
    pub mu_g: f64,
    /// Integration steps per motor tick (`motion::DriftParams::substeps`).
    pub substeps: u32,
    /// How the plate follows its command (`upm solve` takes the rig's
    /// drives; the core its command, exactly).
    #[serde(skip)]
    pub follow: PlateFollow,
    /// true: a part asked only a force is integrated over its whole patch
    /// (`upm solve`; a disc costs 96 points); false: as a point at its
    /// centroid.
    #[serde(skip)]
    pub patch_forces: bool,
    /// Most contact-point evaluations per request ([`MAX_CORRECTION_WORK`]
    /// on the solver thread; `upm solve`, offline, has no bound).
    #[serde(skip)]
    pub max_work: u64,
}

impl Default for PartDynamicsParams {
    /// Off; the simulator's default friction; 4 substeps (the cycle's mean
    /// force within about 2 % of a finely stepped one).
    fn default() -> Self {
        Self {
            steps: 0,
            about: LinearizeAbout::Reported,
            mu_g: 0.25 * 9.81,
            substeps: 4,
            follow: PlateFollow::Exact,
            patch_forces: false,
            max_work: MAX_CORRECTION_WORK,
        }
    }
}

/// Most correction steps and substeps a configuration may ask for.
pub const MAX_DYNAMICS_STEPS: u32 = 8;
pub const MAX_DYNAMICS_SUBSTEPS: u32 = 32;
/// Most pieces of a plate trace (cycle ticks × substeps): 12 MB.
pub const MAX_TRACE_PIECES: u64 = 1 << 18;
/// The default bound on the contact-point evaluations one request's
/// correction may cost (pieces × points integrated × predictions): about
/// 0.1 s at the 24 ns each measured on `sort`. A request beyond it is
/// answered uncorrected (`Correction::skipped`).
pub const MAX_CORRECTION_WORK: u64 = 4_000_000;

/// Why [`PartDynamicsParams`] are refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartDynamicsError {
    Steps,
    MuG,
    Substeps,
    /// The longest cycle, finely cut, is more than [`MAX_TRACE_PIECES`].
    TraceTooLong {
        pieces: u64,
    },
}

impl fmt::Display for PartDynamicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Steps => write!(f, "motion.part_dynamics.steps must be 0 to {MAX_DYNAMICS_STEPS}"),
            Self::MuG => f.write_str("motion.part_dynamics.mu_g must be finite and positive (m/s²)"),
            Self::Substeps => {
                write!(f, "motion.part_dynamics.substeps must be 1 to {MAX_DYNAMICS_SUBSTEPS}")
            }
            Self::TraceTooLong { pieces } => write!(
                f,
                "motion.part_dynamics.substeps: the longest cycle (motion.cycle_slots, or one slot per \
                 center) × motion.slot_ticks × substeps is {pieces} pieces, at most {MAX_TRACE_PIECES}"
            ),
        }
    }
}

impl core::error::Error for PartDynamicsError {}

impl PartDynamicsParams {
    pub fn validate(&self) -> Result<(), PartDynamicsError> {
        if self.steps > MAX_DYNAMICS_STEPS {
            return Err(PartDynamicsError::Steps);
        }
        if !(self.mu_g.is_finite() && self.mu_g > 0.0) {
            return Err(PartDynamicsError::MuG);
        }
        if !(1..=MAX_DYNAMICS_SUBSTEPS).contains(&self.substeps) {
            return Err(PartDynamicsError::Substeps);
        }
        Ok(())
    }
}
