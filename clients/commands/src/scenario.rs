//! Scenarios (`scenarios/*.toml`): the rig, the parts, the planner and the
//! run length of one closed-loop experiment, and how its goals are judged.

use std::path::{Path, PathBuf};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;
use serde_json::{Value, json};

use crate::config::{Config, SimPartSection};
use crate::launcher::Trails;
use upm_planner::PlannerConfig;
use upm_planner::sort::sort_side;
use upm_planner::track::distance_to_rectangle;
use upm_vision::class_outline::ClassOutline;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub name: String,
    #[serde(default = "default_seed")]
    pub seed: u64,
    pub duration_s: f64,
    /// Rig and simulator settings (the same sections as a core config);
    /// `[rig.sim].parts` may be left empty when `random_parts` places them.
    #[serde(default)]
    pub rig: Config,
    /// The planner and its parameters; the launcher puts it into the rig
    /// config (`[planner]`), with the parts' mass and μmg filled in.
    #[serde(default)]
    pub planner: PlannerConfig,
    /// Parts placed at random (seeded): count per class, shape and size.
    #[serde(default)]
    pub random_parts: Vec<RandomParts>,
}

fn default_seed() -> u64 {
    1
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomParts {
    pub count: u32,
    pub class: u32,
    pub shape: String,
    pub size: f64,
    /// Region (x0, y0, x1, y1) to scatter in.
    pub region: [f64; 4],
    /// Smallest distance between parts (m).
    pub min_spacing: f64,
}

/// `name` (a file under `scenarios/`) or a path.
pub fn resolve(name_or_path: &str) -> PathBuf {
    let p = Path::new(name_or_path);
    if p.extension().is_some() || p.components().count() > 1 {
        return p.to_path_buf();
    }
    let here = Path::new("scenarios").join(format!("{name_or_path}.toml"));
    if here.is_file() {
        return here;
    }
    repository().join("scenarios").join(format!("{name_or_path}.toml"))
}

/// How the camera sees a recipe's classes, class id k at index k: a
/// square or a triangle as such, any other outline as a disc of its reach.
fn recipe_looks(recipe: &upm_recipe::Recipe, levels: &[f64]) -> Vec<upm_camera::ClassLook> {
    let count = recipe.classes.iter().map(|c| c.id as usize + 1).max().unwrap_or(0);
    (0..count)
        .map(|k| {
            let class = recipe.classes.iter().find(|c| c.id as usize == k);
            let shape = match class.map(|c| (&c.outline, c.outline.symmetry_order())) {
                Some((upm_recipe::Outline::Polygon(v), 4)) if v.len() == 4 => ClassOutline::Square,
                Some((upm_recipe::Outline::Polygon(v), 3)) if v.len() == 3 => ClassOutline::Triangle,
                _ => ClassOutline::Disc,
            };
            let radius = class.map_or(0.015, |c| c.outline.reach());
            upm_camera::ClassLook { level: levels[k % levels.len()], radius, shape }
        })
        .collect()
}

/// A recipe path as a scenario writes it (`recipes/default.toml`): from
/// here if it is here, else from the repository's root, like [`resolve`].
pub fn resolve_recipe(path: &str) -> String {
    let p = Path::new(path);
    if p.is_absolute() || p.is_file() {
        return path.to_owned();
    }
    repository().join(p).display().to_string()
}

/// The repository's root (this crate is `clients/commands`), so a path in
/// a message reads `…/recipes/x.toml`, not `…/clients/commands/../../…`.
fn repository() -> &'static Path {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().and_then(Path::parent).unwrap_or(here)
}

/// A recipe named on the command line: a file, or NAME for
/// `recipes/NAME.toml`.
pub fn resolve_recipe_file(arg: &Path) -> std::path::PathBuf {
    if arg.is_file() {
        return arg.to_path_buf();
    }
    let text = arg.to_string_lossy();
    let bare_name = arg.extension().is_none() && arg.components().count() == 1;
    let relative = if bare_name { format!("recipes/{text}.toml") } else { text.into_owned() };
    resolve_recipe(&relative).into()
}

impl Scenario {
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let s: Scenario = rig_config::load_toml(path)?;
        if !(s.duration_s.is_finite() && s.duration_s > 0.0) {
            anyhow::bail!("{}: duration_s must be positive", path.display());
        }
        // One planner per scenario: `[planner]` (`config` copies it into
        // the rig config every process gets).
        if s.rig.planner != PlannerConfig::default() {
            anyhow::bail!("{}: the planner goes in [planner], not [rig.planner]", path.display());
        }
        Ok(s)
    }

    /// The rig config every process gets: the scenario's parts (random ones
    /// placed with `seed`), part mass consistent with μmg, the planner with
    /// that mass and μmg, and `prefix`.
    /// Run the feed cell on `recipe` (a file) instead of the scenario's;
    /// refused for a scenario without a feed cell.
    pub fn use_recipe(&mut self, recipe: &Path) -> anyhow::Result<()> {
        if self.rig.feed.recipe.is_empty() {
            anyhow::bail!(
                "--recipe: scenario {} runs no feed cell (its [rig.feed] recipe is empty)",
                self.name
            );
        }
        // Absolute: the processes start in other directories.
        self.rig.feed.recipe = std::path::absolute(recipe)?.display().to_string();
        Ok(())
    }

    pub fn config(&self, seed: u64, prefix: &str) -> anyhow::Result<Config> {
        let mut c = self.rig.clone();
        c.service.prefix = prefix.to_owned();
        c.sim.config.seed = seed;
        c.vision.seed = seed;
        let mass = c.plate.mu_m_g / (c.sim.config.mu_kinetic * 9.81);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut next_id = c.sim.parts.iter().map(|p| p.id).max().unwrap_or(0) + 1;
        for group in &self.random_parts {
            for _ in 0..group.count {
                let mut tries = 0;
                let pos = loop {
                    let [x0, y0, x1, y1] = group.region;
                    let p = [rng.random_range(x0..x1), rng.random_range(y0..y1)];
                    let free = c
                        .sim
                        .parts
                        .iter()
                        .all(|q| (q.position[0] - p[0]).hypot(q.position[1] - p[1]) >= group.min_spacing);
                    tries += 1;
                    if free {
                        break p;
                    }
                    if tries > 10_000 {
                        anyhow::bail!(
                            "random_parts: cannot place {} parts {} m apart",
                            group.count,
                            group.min_spacing
                        );
                    }
                };
                c.sim.parts.push(SimPartSection {
                    id: next_id,
                    class: group.class,
                    shape: group.shape.clone(),
                    size: group.size,
                    mass,
                    position: pos,
                    angle: 0.0,
                });
                next_id += 1;
            }
        }
        for p in &mut c.sim.parts {
            p.mass = mass;
        }
        // The rendered camera and vision see the parts' classes as they are.
        c.camera.half_extent = c.plate.half_extent;
        c.camera.frame_hz = c.vision.frame_hz;
        c.camera.seed = seed;
        let levels = [0.1, 0.4, 0.25, 0.55];
        if !c.feed.recipe.is_empty() {
            c.feed.recipe = resolve_recipe(&c.feed.recipe);
        }
        let recipe = c.feed_recipe("scenario")?;
        let classes = c.sim.parts.iter().map(|p| p.class as usize + 1).max().unwrap_or(0);
        c.camera.classes = (0..classes)
            .map(|k| {
                let part = c.sim.parts.iter().find(|p| p.class as usize == k);
                let shape = match part.map(|p| p.shape.as_str()) {
                    Some("square") => ClassOutline::Square,
                    Some("triangle") => ClassOutline::Triangle,
                    _ => ClassOutline::Disc,
                };
                upm_camera::ClassLook {
                    level: levels[k % levels.len()],
                    radius: part.map_or(0.015, bounding_radius),
                    shape,
                }
            })
            .collect();
        if let Some(recipe) = &recipe {
            c.camera.classes = recipe_looks(recipe, &levels);
        }
        c.vision.classes = c.camera.vision_classes();
        // The planner's model of the parts: the rig's μmg, the parts' mass.
        c.planner = self.planner.clone();
        let drive = c.planner.drive_mut();
        drive.mu_m_g = c.plate.mu_m_g;
        drive.part_mass = mass;
        // The presenting planner works on the rig's plate and its cell's recipe.
        if let PlannerConfig::Present(p) = &mut c.planner {
            p.plate_half_extent = c.plate.half_extent;
            if !c.feed.recipe.is_empty() {
                p.recipe = c.feed.recipe.clone();
            }
        }
        Ok(c)
    }

    /// Goal metrics from the recorded trails (ARCHITECTURE.md §7).
    pub fn evaluate(&self, config: &Config, trails: &Trails) -> Value {
        let p = &self.planner;
        let sorted_x = match p {
            PlannerConfig::Sort(s) => s.sorted_x,
            PlannerConfig::SortPaper(s) => s.sorted_x,
            _ => f64::NAN,
        };
        let mut parts = Vec::new();
        let mut sorted = 0usize;
        // sort: when the last part reached its side for good (None: one never did).
        let mut time_to_sort: Option<f64> = Some(0.0);
        let mut rms_sum = 0.0;
        let mut rms_n = 0usize;
        for (id, trail) in &trails.parts {
            let (Some(first), Some(last)) = (trail.points.first(), trail.points.last()) else { continue };
            let goal_met = match p {
                PlannerConfig::Sort(_) | PlannerConfig::SortPaper(_) => {
                    let on_side = |q: &[f64; 4]| sort_side(trail.class) * q[1] >= sorted_x;
                    let ok = on_side(last);
                    sorted += usize::from(ok);
                    let from = match trail.points.iter().rposition(|q| !on_side(q)) {
                        None => Some(first[0]),
                        Some(i) => trail.points.get(i + 1).map(|q| q[0]),
                    };
                    time_to_sort = time_to_sort.zip(from).map(|(a, b)| a.max(b));
                    ok
                }
                PlannerConfig::Track(p) => match p.rects.get(*id as usize - 1) {
                    Some(&rect) => {
                        // Settling: judged over the last 80 % of the run.
                        let settle = 0.2 * trails.duration();
                        for q in trail.points.iter().filter(|q| q[0] >= settle) {
                            let d = distance_to_rectangle(rect, [q[1], q[2]]);
                            rms_sum += d * d;
                            rms_n += 1;
                        }
                        true
                    }
                    None => true,
                },
                PlannerConfig::Spin(p) if *id == p.part => {
                    let there = p.goal.is_none_or(|g| (last[1] - g[0]).hypot(last[2] - g[1]) <= 0.02);
                    there && (last[3] - p.angle).abs() <= 5f64.to_radians()
                }
                PlannerConfig::Local(p) if *id == p.part => {
                    (last[1] - p.goal[0]).hypot(last[2] - p.goal[1]) <= 0.02
                }
                // A fed part has no goal of its own: the cell counts picks.
                PlannerConfig::Present(_) => false,
                _ => true,
            };
            parts.push(json!({
                "id": id, "class": trail.class,
                "start": [first[1], first[2], first[3]],
                "final": [last[1], last[2], last[3]],
                "goal_met": goal_met,
            }));
        }
        let n = parts.len().max(1);
        let mut v = json!({ "parts": parts, "collisions": contacts_in_trails(config, trails), "centers": config.plate.centers.len() });
        match p {
            PlannerConfig::Sort(_) | PlannerConfig::SortPaper(_) => {
                v["sorted_fraction"] = json!(sorted as f64 / n as f64);
                // Seconds since the trails began; null if not every part is sorted.
                v["time_to_sort_s"] = json!(time_to_sort.filter(|_| !trails.parts.is_empty()));
            }
            PlannerConfig::Track(p) => {
                let path: f64 =
                    p.rects.iter().map(|r| 2.0 * (r[2] + r[3])).sum::<f64>() / p.rects.len().max(1) as f64;
                v["tracking_rms_m"] =
                    json!(if rms_n > 0 { (rms_sum / rms_n as f64).sqrt() } else { f64::NAN });
                v["path_length_m"] = json!(path);
            }
            PlannerConfig::Spin(p) => {
                if let Some(t) = trails.parts.get(&p.part) {
                    if let Some(last) = t.points.last() {
                        v["spin_angle_error_deg"] = json!((last[3] - p.angle).to_degrees());
                    }
                    // From when on the angle stayed within 2° (null: never).
                    let settled =
                        match t.points.iter().rposition(|q| (q[3] - p.angle).abs() > 2f64.to_radians()) {
                            None => t.points.first(),
                            Some(i) => t.points.get(i + 1),
                        };
                    v["spin_settled_s"] = json!(settled.map(|q| q[0]));
                }
            }
            PlannerConfig::Local(p) => {
                // How far the parts asked to stay still ever got from their start.
                let drift = trails
                    .parts
                    .iter()
                    .filter(|(id, _)| **id != p.part)
                    .filter_map(|(_, t)| {
                        let first = t.points.first()?;
                        t.points.iter().map(|q| (q[1] - first[1]).hypot(q[2] - first[2])).reduce(f64::max)
                    })
                    .fold(0.0, f64::max);
                v["others_max_drift_m"] = json!(drift);
            }
            // The feed cell's counters and picks come off `upm/feed`.
            PlannerConfig::Present(_) => {}
        }
        v
    }
}

/// Bounding radius of a configured part (m): what the simulator's part–part
/// contact uses.
fn bounding_radius(part: &SimPartSection) -> f64 {
    match part.shape.as_str() {
        "square" => part.size * core::f64::consts::FRAC_1_SQRT_2,
        "triangle" => part.size / 3f64.sqrt(),
        _ => part.size,
    }
}

/// How close (m) beyond touching a pair must come in the trails to count:
/// the trails are sampled (30 Hz in lock-step), so a brief contact is seen
/// as a near miss at the samples around it.
const CONTACT_SLACK: f64 = 0.002;

/// Part–part collisions seen in the trails: each time a pair comes within
/// `CONTACT_SLACK` of touching after being apart, counted once per approach.
pub fn contacts_in_trails(config: &Config, trails: &Trails) -> u64 {
    let radius = |id: u32| config.sim.parts.iter().find(|p| p.id == id).map(bounding_radius);
    let parts: Vec<(f64, &Vec<[f64; 4]>)> =
        trails.parts.iter().filter_map(|(id, t)| Some((radius(*id)?, &t.points))).collect();
    let mut contacts = 0;
    for (i, (ra, a)) in parts.iter().enumerate() {
        for (rb, b) in &parts[i + 1..] {
            let reach = ra + rb + CONTACT_SLACK;
            let mut touching = false;
            // Walk both trails in time; only samples taken at the same
            // instant are compared (a part missing from a frame skips it).
            let (mut i, mut j) = (0, 0);
            while let (Some(p), Some(q)) = (a.get(i), b.get(j)) {
                if p[0] < q[0] {
                    i += 1;
                } else if q[0] < p[0] {
                    j += 1;
                } else {
                    let close = (p[1] - q[1]).hypot(p[2] - q[2]) <= reach;
                    contacts += u64::from(close && !touching);
                    touching = close;
                    i += 1;
                    j += 1;
                }
            }
        }
    }
    contacts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::launcher::PartTrail;

    fn disc(id: u32, size: f64) -> SimPartSection {
        SimPartSection {
            id,
            class: 0,
            shape: "disc".into(),
            size,
            mass: 0.04,
            position: [0.0; 2],
            angle: 0.0,
        }
    }

    #[test]
    fn each_approach_to_touching_counts_once() {
        let mut config = Config::default();
        config.sim.parts = vec![disc(1, 0.015), disc(2, 0.015), disc(3, 0.015)];
        // Part 2 gaps from part 1 (mm): apart, touching twice in a row, apart,
        // touching again. Part 3 stays far away.
        let gaps_mm = [50.0, 10.0, 1.0, 0.0, 20.0, 1.5, 40.0];
        let mut trails = Trails::default();
        let trail = |xs: Vec<f64>| PartTrail {
            class: 0,
            points: xs.iter().enumerate().map(|(i, &x)| [i as f64, x, 0.0, 0.0]).collect(),
        };
        trails.parts.insert(1, trail(vec![0.0; gaps_mm.len()]));
        trails.parts.insert(2, trail(gaps_mm.iter().map(|g| 0.03 + g * 1e-3).collect()));
        trails.parts.insert(3, trail(vec![0.5; gaps_mm.len()]));
        assert_eq!(contacts_in_trails(&config, &trails), 2);
    }
}
