//! A changeover: a new recipe for a running cell, from the core's io
//! thread to the cell where it steps. It is prepared (and allocated) off
//! the motor thread and swapped in there without allocating; the recipe it
//! replaces stays in the buffer and is freed by the io thread's next post
//! (or when the cell goes). The classes stay (`Recipe::check_changeover`),
//! so the pool of parts and the parts on the plate stay too.

use core::fmt;

use upm_recipe::Recipe;

use super::cell::FeedCell;
use crate::sim::Simulator;

/// A recipe and what the cell derives from it, ready to swap in.
#[derive(Debug, Clone)]
pub(super) struct Prepared {
    pub(super) recipe: Recipe,
    pub(super) cumulative_share: Vec<f64>,
    pub(super) pick_box: ([f64; 2], [f64; 2]),
}

impl Prepared {
    pub(super) fn of(recipe: Recipe) -> Self {
        let mut total = 0.0;
        let cumulative_share = recipe
            .classes
            .iter()
            .map(|c| {
                total += c.share;
                total
            })
            .collect();
        Self { pick_box: recipe.pick_box(), cumulative_share, recipe }
    }
}

/// The io thread's end: where a changeover is posted.
pub struct RecipeMailbox {
    input: triple_buffer::Input<Option<Prepared>>,
}

impl RecipeMailbox {
    /// Switch the cell to `recipe` at its next step. The caller has checked
    /// it against the plate and with `Recipe::check_changeover`.
    pub fn post(&mut self, recipe: Recipe) {
        self.input.write(Some(Prepared::of(recipe)));
    }
}

impl fmt::Debug for RecipeMailbox {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("RecipeMailbox")
    }
}

/// The cell's end, if a mailbox was opened; a clone reads none.
#[derive(Default)]
pub(super) struct RecipeInbox(Option<triple_buffer::Output<Option<Prepared>>>);

impl Clone for RecipeInbox {
    fn clone(&self) -> Self {
        Self(None)
    }
}

impl fmt::Debug for RecipeInbox {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() { "RecipeInbox(open)" } else { "RecipeInbox(none)" })
    }
}

impl FeedCell {
    /// Open the cell around `sim` to changeovers; None without a cell.
    pub fn accept_recipes(sim: &mut Simulator) -> Option<RecipeMailbox> {
        let cell = sim.cell_mut()?.as_any_mut().downcast_mut::<Self>()?;
        let (input, output) = triple_buffer::triple_buffer(&None);
        cell.changeover.0 = Some(output);
        Some(RecipeMailbox { input })
    }

    /// Swap in a posted recipe, if any. Allocation-free: the old recipe
    /// takes the new one's place in the buffer. Parts on the plate stay;
    /// what they were settling at is forgotten (the poses may have moved),
    /// and picks posted for the old poses are dropped.
    pub(super) fn take_changeover(&mut self) {
        let Some(inbox) = self.changeover.0.as_mut() else { return };
        if !inbox.update() {
            return;
        }
        let Some(next) = inbox.output_buffer_mut().as_mut() else { return };
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
}
