//! `[feed]`: the production cell the simulator plays, from a recipe
//! (`recipes/*.toml`): parts arrive, a robot takes each at its pick pose.
//! The cell brings its own parts, so `[[sim.parts]]` stays empty.

use serde::{Deserialize, Serialize};
use upm_recipe::Recipe;

#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct FeedSection {
    /// The recipe file; empty: no feed cell.
    pub recipe: String,
    /// What the simulated robot takes: `"at_pose"` (a part presented at
    /// its pick pose), `"any_in_zone"` (the feeders' shake-and-pick) or
    /// `"external"` (none: a robot outside posts its picks on `upm/pick`).
    pub robot: drivers::feed::RobotMode,
}

impl FeedSection {
    /// The robot is outside the simulator (`upm run --robot external`).
    pub fn use_external_robot(&mut self) -> Result<(), String> {
        if self.recipe.is_empty() {
            return Err(
                "--robot external: this scenario runs no feed cell (its [feed] recipe is empty)".into()
            );
        }
        self.robot = drivers::feed::RobotMode::External;
        Ok(())
    }

    /// The recipe, checked against a plate of `plate_half_extent`; None
    /// without one. The message names the field.
    pub fn recipe(&self, plate_half_extent: [f64; 2]) -> Result<Option<Recipe>, String> {
        if self.recipe.is_empty() {
            return Ok(None);
        }
        Recipe::load(std::path::Path::new(&self.recipe), plate_half_extent)
            .map(Some)
            .map_err(|e| format!("feed.recipe: {e}"))
    }
}
