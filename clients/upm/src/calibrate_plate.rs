//! `upm calibrate plate`: the plate calibration (`upm_calibrate`) against
//! a running rig, or in lock-step for the bench. Only what the controller
//! knows goes in (`[plate]`, `[motion]`, the core's k bounds and the
//! planner's μ·g); the simulator's `[sim]` never does.

use rig_config::PlateCalibration;
use rt_core::runtime::QueueInbox;
use upm_calibrate::{CalibrateSetup, ExciteParams, Exciter, Step};

use crate::closed_loop::LoopClient;
use crate::config::Config;

/// The calibration's view of the rig `config` describes.
pub fn setup(config: &Config, params: ExciteParams) -> anyhow::Result<CalibrateSetup> {
    let core = config.core_params("config")?;
    let k_bounds = core.playable_k_bounds().map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut planner = config.planner.clone();
    let drive = planner.drive_mut();
    Ok(CalibrateSetup {
        centers: core.centers.clone(),
        k_bounds,
        motion: core.motion,
        mu_m_g: core.mu_m_g,
        mu_g: drive.mu_m_g / drive.part_mass,
        plate_half_extent: config.plate.half_extent,
        actuators: core.rig.count as u32,
        tracker_alpha: Some(config.vision.alpha),
        prior_correction: core.twist_correction,
        params,
    })
}

/// The exciter as a lock-step client; keeps the first refusal.
struct Lockstepped {
    exciter: Exciter,
    seq: u64,
    failed: Option<upm_calibrate::CalibrateError>,
}

impl LoopClient for Lockstepped {
    fn answer(
        &mut self,
        seen: &ipc_types::PartStates,
        time: f64,
        now_ns: u64,
        inbox: &mut QueueInbox,
    ) -> bool {
        let mut msg = ipc_types::ExplicitSchedule::new();
        match self.exciter.on_frame(seen, time, &mut msg) {
            Ok(Step::Play) => {
                self.seq += 1;
                msg.seq = self.seq;
                msg.stamp_ns = now_ns;
                inbox.push_explicit(&msg);
                true
            }
            Ok(Step::Done) => false,
            Err(e) => {
                self.failed = Some(e);
                false
            }
        }
    }
}

/// Calibrate the plate of `config` in lock-step (the core, the simulator
/// and vision's camera model on one clock).
pub fn lockstep(config: &Config, params: ExciteParams) -> anyhow::Result<PlateCalibration> {
    let mut client = Lockstepped { exciter: Exciter::new(setup(config, params)?)?, seq: 0, failed: None };
    let limit = client.exciter.rig_seconds() + 2.0;
    crate::closed_loop::run_client(config, &mut client, limit, crate::launcher::CameraChoice::Truth)?;
    if let Some(e) = client.failed {
        return Err(e.into());
    }
    Ok(client.exciter.fit()?)
}
