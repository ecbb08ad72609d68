//! Changeovers in the core: the io thread loads the recipe a
//! `RecipeCommand` names, checks it against the plate and the running
//! recipe, and posts it to the feed cell. Loading allocates, so it happens
//! there, never on the motor thread.

use std::path::Path;

use anyhow::Context;
use rt_core::Changeovers;
use upm_recipe::Recipe;

use crate::config::CoreConfig;
use crate::plate_driver::SimulatedPlant;

/// The feed cell's changeovers, if the driver runs a cell: its running
/// recipe (by absolute path) and the sink that switches it.
pub fn changeovers<V, P, C, D: SimulatedPlant>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
    driver: &mut D,
) -> anyhow::Result<Option<Changeovers>> {
    let Some(running) = config.feed_recipe(shown)? else { return Ok(None) };
    let Some(mut mailbox) = driver.accept_recipes() else { return Ok(None) };
    let path = std::fs::canonicalize(&config.feed.recipe)
        .with_context(|| format!("{shown}: feed.recipe {:?}", config.feed.recipe))?;
    let path = path.to_str().with_context(|| format!("feed.recipe {path:?} is not UTF-8"))?;
    let announced = ipc_types::RecipeCommand::new(path, 0, ipc_types::monotonic_now_ns())
        .map_err(|e| anyhow::anyhow!("feed.recipe: {e}"))?;
    let half_extent = config.plate.half_extent;
    let mut running = running;
    let sink = move |path: &str| -> Result<(), String> {
        let next = Recipe::load(Path::new(path), half_extent).map_err(|e| e.to_string())?;
        running.check_changeover(&next).map_err(|e| format!("{path}: {e}"))?;
        mailbox.post(next.clone());
        running = next;
        Ok(())
    };
    Ok(Some(Changeovers { running: announced, sink: Box::new(sink) }))
}
