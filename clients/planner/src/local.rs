//! `local`: one part moves to a goal while every other part holds its
//! start (the primitive of Reznik's later work).

use ipc_types::{ForceEntry, ForceRequest, PartStates};
use serde::{Deserialize, Serialize};

use crate::Planner;
use crate::drive::{DriveParams, PartPoints};

/// `[planner]` with `name = "local"`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct LocalParams {
    pub drive: DriveParams,
    /// The part that moves, and its goal (m).
    pub part: u32,
    pub goal: [f64; 2],
}

impl Default for LocalParams {
    fn default() -> Self {
        Self { drive: DriveParams::default(), part: 1, goal: [0.3, 0.2] }
    }
}

#[derive(Debug)]
pub struct LocalPlanner {
    p: LocalParams,
    starts: PartPoints,
}

impl LocalPlanner {
    pub fn new(p: LocalParams) -> Result<Self, String> {
        p.drive.validate()?;
        if !p.goal.iter().all(|x| x.is_finite()) {
            return Err(format!("planner.goal must be finite, got {:?}", p.goal));
        }
        Ok(Self { p, starts: PartPoints::default() })
    }
}

impl Planner for LocalPlanner {
    fn name(&self) -> &'static str {
        "local"
    }

    fn plan(&mut self, parts: &PartStates, _t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        for part in parts.parts() {
            let start = self.starts.get_or_remember(part);
            // Everyone else holds its start. Not a bare zero-force
            // constraint: with zero average force a part keeps whatever
            // velocity it has (nothing damps it), so it gets the same PD as
            // the driven part.
            let goal = if part.id == self.p.part { self.p.goal } else { start };
            if out.push(ForceEntry::force(part.id, self.p.drive.force_to(part, goal, [0.0; 2]))).is_err() {
                break;
            }
        }
        !out.is_empty()
    }
}
