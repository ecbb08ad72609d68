//! The whole rig's config, as `upm` validates it before it starts anything:
//! the core's schema ([`upm_core::config`]) with the clients' sections
//! typed by their crates. Every process reads the same file, each its own
//! sections.

use upm_camera::CameraSection;
use upm_planner::PlannerConfig;
use upm_vision::VisionSection;

pub use upm_core::config::*;

/// The rig: the core's sections, `[vision]`, `[planner]` and `[camera]`.
pub type Config = CoreConfig<VisionSection, PlannerConfig, CameraSection>;

/// Every section checked, as each process will check its own.
pub fn validate(config: &Config, path: &str) -> Result<(), ConfigError> {
    let invalid = |m: String| ConfigError::invalid(path, m);
    config.validate_core(path)?;
    config.vision.validate().map_err(invalid)?;
    config.camera.validate().map_err(invalid)?;
    config.planner.build().map_err(invalid)?;
    Ok(())
}

/// The rate vision publishes part states at, as the core announces it.
pub fn vision_publish_hz(config: &Config) -> f64 {
    rig_config::frame_rate::publish_hz(&config.vision.source, config.vision.frame_hz, config.camera.frame_hz)
}
