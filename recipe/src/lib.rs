//! A production cell's recipe (`recipes/*.toml`): which part classes
//! arrive and how often, where the robot takes each class, the infeed and
//! the robot. [`Recipe::load`] reads and checks a file against the plate;
//! every refusal is one line naming the field. Parsing has no side effects.

mod changeover;
mod error;
mod outline;
mod recipe;
mod symmetry;

pub use error::RecipeError;
pub use outline::Outline;
pub use recipe::{Infeed, PartClass, PickPose, Recipe, Robot};
pub use symmetry::angle_error;
