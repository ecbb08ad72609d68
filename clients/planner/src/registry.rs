//! The built-in planners by name: `[planner]` of the rig config is a
//! tagged enum, `name` picks the variant and the other fields are that
//! planner's parameters (`[planner.drive]` for the shared controller).

use serde::{Deserialize, Serialize};

use crate::Planner;
use crate::local::{LocalParams, LocalPlanner};
use crate::present::{PresentParams, PresentPlanner};
use crate::sort::{SortParams, SortPlanner};
use crate::sort_paper::{PaperSortParams, PaperSortPlanner};
use crate::spin::{SpinParams, SpinPlanner};
use crate::track::{TrackParams, TrackPlanner};

/// `[planner]`: which built-in planner, with its parameters.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum PlannerConfig {
    Track(TrackParams),
    Sort(SortParams),
    SortPaper(PaperSortParams),
    Spin(SpinParams),
    Local(LocalParams),
    Present(PresentParams),
}

impl Default for PlannerConfig {
    fn default() -> Self {
        Self::Sort(SortParams::default())
    }
}

impl PlannerConfig {
    /// The names `name` may take.
    pub const NAMES: [&str; 6] = ["track", "sort", "sort_paper", "spin", "local", "present"];

    /// `name`'s planner with its default parameters.
    pub fn by_name(name: &str) -> Result<Self, String> {
        match name {
            "track" => Ok(Self::Track(TrackParams::default())),
            "sort" => Ok(Self::Sort(SortParams::default())),
            "sort_paper" => Ok(Self::SortPaper(PaperSortParams::default())),
            "spin" => Ok(Self::Spin(SpinParams::default())),
            "local" => Ok(Self::Local(LocalParams::default())),
            "present" => Ok(Self::Present(PresentParams::default())),
            other => Err(format!("planner.name {other:?}: expected one of {:?}", Self::NAMES)),
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            Self::Track(_) => "track",
            Self::Sort(_) => "sort",
            Self::SortPaper(_) => "sort_paper",
            Self::Spin(_) => "spin",
            Self::Local(_) => "local",
            Self::Present(_) => "present",
        }
    }

    /// The shared controller's parameters, whichever the planner.
    pub fn drive_mut(&mut self) -> &mut crate::DriveParams {
        match self {
            Self::Track(p) => &mut p.drive,
            Self::Sort(p) => &mut p.drive,
            Self::SortPaper(p) => &mut p.drive,
            Self::Spin(p) => &mut p.drive,
            Self::Local(p) => &mut p.drive,
            Self::Present(p) => &mut p.drive,
        }
    }

    /// The planner, its parameters checked; the message names the field.
    pub fn build(&self) -> Result<Box<dyn Planner>, String> {
        Ok(match self.clone() {
            Self::Track(p) => Box::new(TrackPlanner::new(p)?),
            Self::Sort(p) => Box::new(SortPlanner::new(p)?),
            Self::SortPaper(p) => Box::new(PaperSortPlanner::new(p)?),
            Self::Spin(p) => Box::new(SpinPlanner::new(p)?),
            Self::Local(p) => Box::new(LocalPlanner::new(p)?),
            Self::Present(p) => Box::new(PresentPlanner::new(p)?),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_round_trips_and_builds_with_its_defaults() {
        for name in PlannerConfig::NAMES {
            let mut c = PlannerConfig::by_name(name).expect("known");
            // Its default recipe path is relative to the repository's root.
            if let PlannerConfig::Present(p) = &mut c {
                p.recipe = format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), p.recipe);
            }
            assert_eq!(c.name(), name);
            assert_eq!(c.build().expect("defaults are valid").name(), name);
            let text = toml::to_string(&c).expect("serialises");
            assert_eq!(toml::from_str::<PlannerConfig>(&text).expect("parses"), c, "{text}");
        }
        assert!(PlannerConfig::by_name("gather").expect_err("unknown").contains("\"gather\""));
    }

    #[test]
    fn fields_of_another_planner_are_refused() {
        let e =
            toml::from_str::<PlannerConfig>("name = \"track\"\nsorted_x = 0.5\n").expect_err("sort's field");
        assert!(e.to_string().contains("unknown field `sorted_x`"), "{e}");
        let e = toml::from_str::<PlannerConfig>("name = \"walk\"\n").expect_err("unknown planner");
        assert!(e.to_string().contains("unknown variant `walk`"), "{e}");
        let c: PlannerConfig =
            toml::from_str("name = \"spin\"\npart = 3\n[drive]\nmax_speed = 0.01\n").expect("ok");
        let PlannerConfig::Spin(p) = c else { panic!("spin expected") };
        assert_eq!((p.part, p.drive.max_speed), (3, 0.01));
    }

    #[test]
    fn invalid_values_name_the_field() {
        let mut c = PlannerConfig::by_name("local").expect("known");
        c.drive_mut().part_mass = -1.0;
        assert!(c.build().err().expect("refused").contains("planner.drive.part_mass"));
    }
}
