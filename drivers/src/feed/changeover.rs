//! A changeover: a new recipe for a running cell, from the core's io
//! thread to the cell where it steps. It is prepared (and allocated) off
//! the motor thread and swapped in there without allocating; the recipe it
//! replaces stays in the buffer and is freed by the io thread's next post
//! (or when the cell goes). The classes stay (`Recipe::check_changeover`),
//! so the pool of parts and the parts on the plate stay too.

use core::fmt;

use upm_recipe::Recipe;

/// A recipe and what the cell derives from it, ready to swap in.
#[derive(Debug, Clone)]
pub(super) struct Prepared {
    pub(super) recipe: Recipe,
    pub(super) cumulative_share: Vec<f64>,
    pub(super) pick_box: ([f64; 2], [f64; 2]),
}

impl Prepared {
    pub(super) fn of(recipe: Recipe) -> Self {
        Self { pick_box: recipe.pick_box(), cumulative_share: cumulative_shares(&recipe), recipe }
    }
}

/// Per class, the sum of the shares up to it: where a uniform draw over
/// the total picks the arriving class.
pub(super) fn cumulative_shares(recipe: &Recipe) -> Vec<f64> {
    let mut total = 0.0;
    recipe
        .classes
        .iter()
        .map(|c| {
            total += c.share;
            total
        })
        .collect()
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

impl RecipeInbox {
    /// A mailbox and the inbox it posts to.
    pub(super) fn open() -> (Self, RecipeMailbox) {
        let (input, output) = triple_buffer::triple_buffer(&None);
        (Self(Some(output)), RecipeMailbox { input })
    }

    /// The recipe posted since the last call, if any. The caller swaps its
    /// own into its place, so that it is freed by the poster.
    pub(super) fn next(&mut self) -> Option<&mut Prepared> {
        let inbox = self.0.as_mut()?;
        if !inbox.update() {
            return None;
        }
        inbox.output_buffer_mut().as_mut()
    }
}

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
