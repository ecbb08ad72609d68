//! Every shipped recipe loads; a recipe that cannot work is refused in one
//! line naming the field.

use upm_recipe::{Outline, Recipe};

const PLATE: [f64; 2] = [1.0, 0.5];
const DEFAULT: &str = include_str!("../../recipes/default.toml");

#[test]
fn the_shipped_recipes_load() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../recipes");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).expect("recipes/") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            Recipe::load(&path, PLATE).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 1, "no recipe in recipes/");
    let r = Recipe::parse(DEFAULT, "default.toml", PLATE).expect("default");
    assert_eq!((r.classes.len(), r.picks.len(), r.robot.pick_s), (2, 4, 1.0));
    assert_eq!(r.classes[0].outline, Outline::Disc { radius: 0.015 });
    assert_eq!((r.robot.tolerance, r.robot.tolerance_angle), (1e-3, 2f64.to_radians()));
}

/// The default recipe with `from` replaced by `to`.
fn edited(from: &str, to: &str) -> String {
    assert!(DEFAULT.contains(from), "{from:?} is not in the default recipe");
    DEFAULT.replacen(from, to, 1)
}

#[test]
fn a_recipe_that_cannot_work_is_refused_naming_the_field() {
    for (from, to, field) in [
        ("position = [0.7, 0.25]", "position = [0.99, 0.25]", "pick[0].position: "),
        ("position = [0.7, 0.25]", "position = [0.7, -0.24]", "pick[1].position: within pick[0]'s clearance"),
        ("radius = 0.015", "radius = 0.00001", "class[0].outline: "),
        ("[-0.015, 0.015]] }", "[0.0, 0.0]] }", "class[1].outline: "),
        ("rate_per_min = 40", "rate_per_min = 0", "infeed.rate_per_min: "),
        ("rate_per_min = 40", "rate_per_min = -3", "infeed.rate_per_min: "),
        ("region = [-0.9, -0.4, -0.6, 0.4]", "region = [-0.6, -0.4, -0.9, 0.4]", "infeed.region: "),
        ("max_on_plate = 16", "max_on_plate = 0", "infeed.max_on_plate: "),
        ("pick_s = 1.0", "pick_s = nan", "robot.pick_s: "),
        ("tolerance_mm = 1.0", "tolerance_mm = \"1\"", "robot.tolerance_mm: "),
        ("share = 0.5", "share = 0.5\ncolour = 3", "class[0].colour: "),
        ("theta = 0.0", "theta = inf", "pick[0].theta: "),
        ("id = 1", "id = 0", "class[1].id: 0 is used twice"),
        ("clearance_mm = 5.0", "clearance_mm = -1.0", "robot.clearance_mm: "),
    ] {
        let text = edited(from, to);
        let e = Recipe::parse(&text, "r.toml", PLATE).expect_err(to).to_string();
        assert!(e.starts_with("r.toml: ") && !e.contains('\n'), "{to}: {e}");
        assert!(e.contains(field), "{to}: wanted {field:?} in {e}");
    }
    // Class 1 with no pose left: both of its poses given to class 0.
    let text = edited("class = 1\nposition = [0.85, -0.25]", "class = 0\nposition = [0.85, -0.25]").replacen(
        "class = 1\nposition = [0.85, 0.25]",
        "class = 0\nposition = [0.85, 0.25]",
        1,
    );
    let e = Recipe::parse(&text, "r.toml", PLATE).expect_err("class without a pose").to_string();
    assert!(e.contains("pick: class 1 has no pick pose"), "{e}");
}
