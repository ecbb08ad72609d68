//! A changeover: the recipe a running cell may switch to. The parts on the
//! plate stay, so the classes must stay too; where they are picked, how
//! often they arrive and how the robot works may all change.

use crate::recipe::Recipe;

impl Recipe {
    /// Whether a cell running `self` may switch to `next` (both already
    /// checked against the plate); the refusal is one line naming the field.
    pub fn check_changeover(&self, next: &Recipe) -> Result<(), String> {
        if next.classes.len() != self.classes.len() {
            return Err(format!(
                "class: {} classes where the running recipe \"{}\" has {}; a new part set needs a restart",
                next.classes.len(),
                self.name,
                self.classes.len()
            ));
        }
        for (i, (now, new)) in self.classes.iter().zip(&next.classes).enumerate() {
            let same = now.id == new.id && now.outline == new.outline && now.friction == new.friction;
            if !same {
                return Err(format!(
                    "class[{i}]: id, outline or friction differs from the running recipe \"{}\"'s; \
                     a new part set needs a restart",
                    self.name
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::Outline;

    fn recipe() -> crate::Recipe {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../recipes/default.toml"))
            .expect("the default recipe");
        crate::Recipe::parse(&text, "default", [1.0, 0.5]).expect("valid")
    }

    #[test]
    fn poses_infeed_and_robot_may_change_but_not_the_classes() {
        let running = recipe();
        let mut next = running.clone();
        next.picks.truncate(2);
        next.infeed.rate_per_min = 10.0;
        next.robot.pick_s = 0.5;
        next.classes[1].share = 0.1;
        assert_eq!(running.check_changeover(&next), Ok(()));
        let mut fewer = running.clone();
        fewer.classes.pop();
        let why = running.check_changeover(&fewer).err();
        assert!(why.as_deref().is_some_and(|e| e.starts_with("class: 1 classes")), "{why:?}");
        let mut bigger = running.clone();
        bigger.classes[0].outline = Outline::Disc { radius: 0.02 };
        let why = running.check_changeover(&bigger).err();
        assert!(why.as_deref().is_some_and(|e| e.starts_with("class[0]:")), "{why:?}");
        let mut slippery = running.clone();
        slippery.classes[1].friction = 0.5;
        let why = running.check_changeover(&slippery).err();
        assert!(why.as_deref().is_some_and(|e| e.starts_with("class[1]:")), "{why:?}");
    }
}
