//! A planner on a calibrated plate: where friction is μ·s (the plate
//! calibration's class scale times its map at the part), a force f needs a
//! request of f / s, and so does a curl. Wraps any planner; the wrapped one
//! plans for the model's plate as before.

use ipc_types::{ForceRequest, PartStates};
use rig_config::PlateCalibration;

use crate::Planner;

pub struct Calibrated<P> {
    inner: P,
    calibration: PlateCalibration,
}

impl<P: Planner> core::fmt::Debug for Calibrated<P> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Calibrated").field("planner", &self.inner.name()).finish_non_exhaustive()
    }
}

impl<P: Planner> Calibrated<P> {
    pub fn new(inner: P, calibration: PlateCalibration) -> Self {
        Self { inner, calibration }
    }
}

impl<P: Planner> Planner for Calibrated<P> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        if !self.inner.plan(parts, t, out) {
            return false;
        }
        for e in out.entries_mut() {
            let Some(p) = parts.parts().iter().find(|p| p.id == e.part_id) else { continue };
            let s = self.calibration.friction_scale(p.class, p.x, p.y);
            e.fx /= s;
            e.fy /= s;
            e.curl /= s;
        }
        true
    }
}

/// `planner`, calibrated if there is a calibration.
pub fn calibrated(planner: Box<dyn Planner>, calibration: Option<PlateCalibration>) -> Box<dyn Planner> {
    match calibration {
        Some(c) => Box::new(Calibrated::new(planner, c)),
        None => planner,
    }
}

/// `planner` on this plate: its calibration if any, and online friction
/// adaptation if `[planner.drive] adapt_friction` asks for it.
pub fn on_plate(
    config: &crate::PlannerConfig,
    calibration: Option<PlateCalibration>,
) -> Result<Box<dyn Planner>, String> {
    let planner = config.build()?;
    let mut c = config.clone();
    let drive = *c.drive_mut();
    Ok(if drive.adapt_friction {
        Box::new(crate::adaptive::Adaptive::new(planner, calibration, drive.part_mass))
    } else {
        calibrated(planner, calibration)
    })
}

impl Planner for Box<dyn Planner> {
    fn name(&self) -> &'static str {
        self.as_ref().name()
    }

    fn friction_estimates(&self) -> Vec<(u32, f64)> {
        self.as_ref().friction_estimates()
    }

    fn learning_counts(&self) -> Option<crate::adaptive::AdaptCounts> {
        self.as_ref().learning_counts()
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        self.as_mut().plan(parts, t, out)
    }
}
