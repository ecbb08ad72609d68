//! The cell: its pool of parts in the simulator, what each is doing, and
//! the millisecond step that runs the robot and the infeed.

use core::fmt;

use upm_recipe::{Outline, Recipe};

use super::changeover::{RecipeInbox, RecipeMailbox, cumulative_shares};
use super::counts::{FeedCounts, PickRecord};
use super::pick_mailbox::MailboxSlot;
use super::robot_mode::RobotMode;
use super::status_port::StatusSlot;
use crate::rng::SplitMix64;
use crate::sim::{BodyShape, Cell, MAX_POLYGON_VERTICES, PartSpec, SimConfig, SimError, Simulator};

/// Picks kept for the report (the oldest are dropped beyond this).
const PICK_LOG: usize = 1 << 16;

/// Why a cell could not be built.
#[derive(Debug, Clone, PartialEq)]
pub enum FeedError {
    /// The recipe does not fit this plate (the message names the field).
    Recipe(String),
    Sim(SimError),
}

impl fmt::Display for FeedError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Recipe(m) => write!(f, "recipe: {m}"),
            Self::Sim(e) => write!(f, "{e}"),
        }
    }
}

impl core::error::Error for FeedError {}

#[derive(Debug, Clone)]
pub struct FeedCell {
    pub(super) recipe: Recipe,
    /// Per simulator part (its pool slot): the index of its class in the
    /// recipe, its id while on the plate (0 parked), when it arrived.
    pub(super) slot_class: Vec<usize>,
    pub(super) slot_id: Vec<u32>,
    pub(super) arrived_t: Vec<f64>,
    /// Since when the part has lain within tolerance of `within_pose`
    /// (NaN: of no pose).
    pub(super) within_since: Vec<f64>,
    pub(super) within_pose: Vec<usize>,
    /// Per class: outline reach (m), symmetry order, cumulative share.
    pub(super) reach: Vec<f64>,
    pub(super) order: Vec<u32>,
    pub(super) cumulative_share: Vec<f64>,
    /// The cell steps every this many simulator ticks (1 ms).
    every: u64,
    pub(super) mode: RobotMode,
    /// The box the pick poses span (the zone, before its margin).
    pub(super) pick_box: ([f64; 2], [f64; 2]),
    pub(super) next_id: u32,
    pub(super) next_arrival: f64,
    pub(super) busy_until: f64,
    /// The simulated robot's cycles so far (s): each pick's `pick_s` as
    /// the recipe then had it.
    pub(super) busy_s: f64,
    pub(super) next_pose: usize,
    pub(super) rng: SplitMix64,
    pub(super) counts: FeedCounts,
    picks: Vec<PickRecord>,
    /// Where the next pick goes once `picks` is full.
    pick_head: usize,
    pub(super) status: StatusSlot,
    pub(super) mailbox: MailboxSlot,
    pub(super) changeover: RecipeInbox,
}

impl FeedCell {
    /// A simulator with the cell around it: `recipe.infeed.max_on_plate`
    /// parts of each class, each of `part_mass` (kg), all parked until
    /// they arrive; the robot takes what `mode` says. The recipe is
    /// checked against `cfg`'s plate.
    pub fn simulator(
        cfg: SimConfig,
        recipe: &Recipe,
        part_mass: f64,
        mode: RobotMode,
    ) -> Result<Simulator, FeedError> {
        recipe.validate(cfg.plate_half_extent).map_err(FeedError::Recipe)?;
        let per_class = recipe.infeed.max_on_plate as usize;
        let mut specs = Vec::with_capacity(per_class * recipe.classes.len());
        let mut slot_class = Vec::with_capacity(specs.capacity());
        for (ci, class) in recipe.classes.iter().enumerate() {
            let shape = body_shape(&class.outline);
            for _ in 0..per_class {
                specs.push(PartSpec { shape, mass: part_mass, position: [0.0, 0.0], angle: 0.0 });
                slot_class.push(ci);
            }
        }
        let mut sim = Simulator::new(cfg, &specs).map_err(FeedError::Sim)?;
        for (i, &ci) in slot_class.iter().enumerate() {
            sim.park(i);
            let scale = recipe.classes[ci].friction;
            if scale != 1.0 && !sim.set_part_friction(i, scale) {
                return Err(FeedError::Recipe(format!(
                    "class[{ci}].friction: {scale} out of the simulator's range"
                )));
            }
        }
        let cumulative_share = cumulative_shares(recipe);
        let n = slot_class.len();
        let rng = SplitMix64::new(cfg.seed ^ 0xFEED_CE11_0000_0001);
        let cell = Self {
            reach: recipe.classes.iter().map(|c| c.outline.reach()).collect(),
            order: recipe.classes.iter().map(|c| c.outline.symmetry_order()).collect(),
            cumulative_share,
            recipe: recipe.clone(),
            slot_class,
            slot_id: vec![0; n],
            arrived_t: vec![0.0; n],
            within_since: vec![f64::NAN; n],
            within_pose: vec![0; n],
            every: (cfg.tick_hz / 1000.0).round().max(1.0) as u64,
            mode,
            pick_box: recipe.pick_box(),
            next_id: 1,
            next_arrival: 0.0,
            busy_until: 0.0,
            busy_s: 0.0,
            next_pose: 0,
            rng,
            counts: FeedCounts::default(),
            picks: Vec::with_capacity(PICK_LOG),
            pick_head: 0,
            status: StatusSlot::default(),
            mailbox: MailboxSlot::default(),
            changeover: RecipeInbox::default(),
        };
        let mut cell = cell;
        cell.schedule_first_arrival();
        sim.attach_cell(Box::new(cell));
        Ok(sim)
    }

    /// Open the cell around `sim` to changeovers; None without a cell.
    pub fn accept_recipes(sim: &mut Simulator) -> Option<RecipeMailbox> {
        let cell = sim.cell_mut()?.as_any_mut().downcast_mut::<Self>()?;
        let (inbox, mailbox) = RecipeInbox::open();
        cell.changeover = inbox;
        Some(mailbox)
    }

    /// Swap in a posted recipe, if any. Allocation-free: the old recipe
    /// takes the new one's place in the buffer. Parts on the plate stay;
    /// what they were settling at is forgotten (the poses may have moved),
    /// and picks posted for the old poses are dropped.
    fn take_changeover(&mut self) {
        let Some(next) = self.changeover.next() else { return };
        core::mem::swap(&mut self.recipe, &mut next.recipe);
        core::mem::swap(&mut self.cumulative_share, &mut next.cumulative_share);
        self.pick_box = next.pick_box;
        self.within_since.fill(f64::NAN);
        self.next_pose = 0;
        if let Some(mailbox) = self.mailbox.0.as_ref() {
            for j in 0..ipc_types::MAX_PICK_POSES {
                mailbox.take(j);
            }
        }
        self.counts.changeovers += 1;
    }

    /// The cell around `sim`, if it has one.
    pub fn of(sim: &Simulator) -> Option<&Self> {
        sim.cell().and_then(|c| c.as_any().downcast_ref::<Self>())
    }

    /// One step of the cell, after the simulator's tick. Allocation-free.
    fn step_cell(&mut self, sim: &mut Simulator) {
        if !sim.counters().ticks.is_multiple_of(self.every) {
            return;
        }
        let t = sim.time();
        self.take_changeover();
        self.count_lost(sim);
        self.track_settling(sim, t);
        self.robot_step(sim, t);
        self.infeed_step(sim, t);
        self.publish_status_if_due(sim);
    }

    pub fn counts(&self) -> FeedCounts {
        self.counts
    }

    pub fn recipe(&self) -> &Recipe {
        &self.recipe
    }

    /// The id part `i` carries on the wire (0: parked).
    pub fn id_of(&self, i: usize) -> u32 {
        self.slot_id.get(i).copied().unwrap_or(0)
    }

    /// The recipe class id of part `i`.
    pub fn class_of(&self, i: usize) -> Option<u32> {
        self.slot_class.get(i).map(|&ci| self.recipe.classes[ci].id)
    }

    /// Part `i`'s body, as its class's outline gives it.
    pub fn shape_of(&self, i: usize) -> Option<BodyShape> {
        self.slot_class.get(i).map(|&ci| body_shape(&self.recipe.classes[ci].outline))
    }

    /// When part `i` arrived (s; meaningful while it is on the plate).
    pub fn arrived_at(&self, i: usize) -> Option<f64> {
        (self.id_of(i) != 0).then(|| self.arrived_t[i])
    }

    /// Parts on the plate that arrived more than `seconds` before `now`.
    pub fn on_plate_longer_than(&self, now: f64, seconds: f64) -> u32 {
        (0..self.slot_id.len()).filter(|&i| self.slot_id[i] != 0 && now - self.arrived_t[i] > seconds).count()
            as u32
    }

    /// The picks kept, oldest first (allocates: not for the motor thread).
    pub fn picks(&self) -> Vec<PickRecord> {
        let (newer, older) = self.picks.split_at(self.pick_head.min(self.picks.len()));
        older.iter().chain(newer).copied().collect()
    }

    /// Picks kept in the log.
    pub(super) fn picks_kept(&self) -> usize {
        self.picks.len()
    }

    /// The `k`-th kept pick, oldest first.
    pub(super) fn pick_record(&self, k: usize) -> Option<PickRecord> {
        let n = self.picks.len();
        (k < n).then(|| self.picks[(self.pick_head + k) % n])
    }

    pub(super) fn log_pick(&mut self, record: PickRecord) {
        if self.picks.len() < PICK_LOG {
            self.picks.push(record);
        } else {
            self.picks[self.pick_head] = record;
            self.pick_head = (self.pick_head + 1) % PICK_LOG;
        }
    }

    /// A part off the plate by any way but the robot: parked and counted.
    fn count_lost(&mut self, sim: &mut Simulator) {
        let [hx, hy] = sim.config().plate_half_extent;
        for i in 0..self.slot_id.len() {
            if self.slot_id[i] == 0 {
                continue;
            }
            let r = self.reach[self.slot_class[i]];
            let on =
                sim.part(i).is_some_and(|p| p.position[0].abs() <= hx + r && p.position[1].abs() <= hy + r);
            if !on {
                self.take_off(sim, i);
                self.counts.lost += 1;
            }
        }
    }

    /// Part `i` leaves the plate.
    pub(super) fn take_off(&mut self, sim: &mut Simulator, i: usize) {
        sim.park(i);
        self.slot_id[i] = 0;
        self.within_since[i] = f64::NAN;
        self.counts.on_plate = self.counts.on_plate.saturating_sub(1);
    }
}

impl Cell for FeedCell {
    fn step(&mut self, sim: &mut Simulator) {
        self.step_cell(sim);
    }

    fn id_of(&self, i: usize) -> u32 {
        FeedCell::id_of(self, i)
    }

    fn boxed_clone(&self) -> Box<dyn Cell> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn core::any::Any {
        self
    }

    fn as_any_mut(&mut self) -> &mut dyn core::any::Any {
        self
    }
}

/// The simulator's body for a recipe outline (checked by the recipe).
fn body_shape(outline: &Outline) -> BodyShape {
    match outline {
        Outline::Disc { radius } => BodyShape::Disc { radius: *radius },
        Outline::Polygon(v) => {
            let mut vertices = [[0.0; 2]; MAX_POLYGON_VERTICES];
            let count = v.len().min(MAX_POLYGON_VERTICES);
            vertices[..count].copy_from_slice(&v[..count]);
            BodyShape::Polygon { vertices, count }
        }
    }
}
