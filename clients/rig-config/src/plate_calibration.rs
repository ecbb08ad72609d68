//! The plate calibration file (`upm calibrate plate` writes it; the core
//! and the planner load it at start, named by `[calibration] file`): how
//! the plate really turns and where friction differs from the model.
//!
//! - `twist_correction` (3 × 3, rows x, y, θ): the twist to command for a
//!   wanted twist. The core plays every sample of a motion through it, so
//!   a rotation about C really turns about C.
//! - `class_friction` and `friction_map`: μ of a part of class c at plate
//!   point (x, y) is μ·s_c·m(x, y), with m(x, y) = 1 + Σ c_k·term_k over
//!   u = x / half-extent x, v = y / half-extent y and the terms u, v, u·v,
//!   u² − ⅓, v² − ⅓. The planner asks for f / (s_c·m) where it wants f.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// `[calibration]`: the calibration file core and planner load.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CalibrationSection {
    /// None: the model as configured.
    pub file: Option<PathBuf>,
}

/// Terms of the friction map.
pub const FRICTION_TERMS: usize = 5;

/// The terms u, v, u·v, u² − ⅓, v² − ⅓ at plate point (x, y).
pub fn friction_terms(half_extent: [f64; 2], x: f64, y: f64) -> [f64; FRICTION_TERMS] {
    let (u, v) = (x / half_extent[0], y / half_extent[1]);
    [u, v, u * v, u * u - 1.0 / 3.0, v * v - 1.0 / 3.0]
}

/// One part class's friction.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ClassFriction {
    pub class: u32,
    /// μ of this class over the nominal μ.
    pub scale: f64,
}

/// How well the fit explains what was seen.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CalibrationReport {
    /// Bursts played and rig time they took (s).
    pub bursts: u32,
    pub rig_seconds: f64,
    /// Observations used, and those rejected (fence, neighbours, outliers).
    pub observations: u32,
    pub rejected: u32,
    /// Median direction residual of the effective centers (degrees).
    pub direction_residual_deg: f64,
    /// Median relative residual of the friction fit.
    pub friction_residual: f64,
    /// The force error the fit predicts for a part (median, relative).
    pub predicted_force_err: f64,
}

/// The file.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlateCalibration {
    /// Format of this file (1).
    pub format: u32,
    /// The rig it was made on: actuator count, configured centers, plate
    /// half-extent and nominal μmg.
    pub actuators: u32,
    pub centers: Vec<[f64; 2]>,
    pub plate_half_extent: [f64; 2],
    pub mu_m_g: f64,
    pub twist_correction: [[f64; 3]; 3],
    pub class_friction: Vec<ClassFriction>,
    pub friction_map: [f64; FRICTION_TERMS],
    #[serde(default)]
    pub report: CalibrationReport,
}

pub const FORMAT: u32 = 1;

/// Friction may differ from the nominal between these multiples.
pub const MIN_SCALE: f64 = 0.2;
pub const MAX_SCALE: f64 = 3.0;

/// The rig a calibration file must match.
#[derive(Debug, Clone, Copy)]
pub struct RigIdentity<'a> {
    pub actuators: u32,
    pub centers: &'a [[f64; 2]],
    pub plate_half_extent: [f64; 2],
    pub mu_m_g: f64,
}

impl PlateCalibration {
    /// Read and check a file; every message names the file and the field.
    pub fn load(path: &Path) -> Result<Self, String> {
        let shown = path.display();
        let text = std::fs::read_to_string(path).map_err(|e| format!("{shown}: {e}"))?;
        let c: Self = toml::from_str(&text).map_err(|e| format!("{shown}: {}", e.message().trim_end()))?;
        c.validate().map_err(|e| format!("{shown}: {e}"))?;
        Ok(c)
    }

    /// Finite, in range, invertible; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        if self.format != FORMAT {
            return Err(format!("format {} (this upm reads format {FORMAT})", self.format));
        }
        let m = &self.twist_correction;
        if m.iter().flatten().any(|v| !v.is_finite()) {
            return Err("twist_correction: not finite".into());
        }
        // A correction is a few percent from the identity; far from it is
        // a file for another rig or a broken fit.
        for (r, row) in m.iter().enumerate() {
            for (c, &v) in row.iter().enumerate() {
                let want = if r == c { 1.0 } else { 0.0 };
                if (v - want).abs() > 0.5 {
                    return Err(format!("twist_correction[{r}][{c}] = {v}: more than 0.5 from the identity"));
                }
            }
        }
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if det.is_nan() || det.abs() <= 0.5 {
            return Err(format!("twist_correction: determinant {det:.3}, not a small correction"));
        }
        for (i, f) in self.class_friction.iter().enumerate() {
            if !(MIN_SCALE..=MAX_SCALE).contains(&f.scale) {
                return Err(format!(
                    "class_friction[{i}].scale = {}: must be within {MIN_SCALE}..{MAX_SCALE}",
                    f.scale
                ));
            }
        }
        if let Some(k) = self.friction_map.iter().position(|c| !c.is_finite()) {
            return Err(format!("friction_map[{k}]: not finite"));
        }
        let half = self.plate_half_extent;
        if !(half.iter().all(|h| h.is_finite() && *h > 0.0)) {
            return Err("plate_half_extent: must be finite and positive".into());
        }
        for i in 0..=40 {
            for j in 0..=40 {
                let (x, y) = (half[0] * (i as f64 / 20.0 - 1.0), half[1] * (j as f64 / 20.0 - 1.0));
                let m = self.map_at(x, y);
                if !(MIN_SCALE..=MAX_SCALE).contains(&m) {
                    return Err(format!("friction_map: {m:.3} of the nominal μ at ({x:.2}, {y:.2})"));
                }
            }
        }
        if !(self.mu_m_g.is_finite() && self.mu_m_g > 0.0) {
            return Err("mu_m_g: must be finite and positive".into());
        }
        if self.centers.iter().flatten().any(|v| !v.is_finite()) {
            return Err("centers: not finite".into());
        }
        Ok(())
    }

    /// Refuse a file made on another rig; the message names the field.
    pub fn check_rig(&self, rig: &RigIdentity) -> Result<(), String> {
        if self.actuators != rig.actuators {
            return Err(format!("actuators = {}: this rig has {}", self.actuators, rig.actuators));
        }
        if self.centers.len() != rig.centers.len() {
            return Err(format!(
                "centers: {} listed, this rig has {}",
                self.centers.len(),
                rig.centers.len()
            ));
        }
        for (j, (a, b)) in self.centers.iter().zip(rig.centers).enumerate() {
            if (a[0] - b[0]).hypot(a[1] - b[1]) > 1e-6 {
                return Err(format!("centers[{j}] = {a:?}: this rig's is {b:?}"));
            }
        }
        if self.plate_half_extent != rig.plate_half_extent {
            return Err(format!(
                "plate_half_extent = {:?}: this rig's is {:?}",
                self.plate_half_extent, rig.plate_half_extent
            ));
        }
        if (self.mu_m_g - rig.mu_m_g).abs() > 1e-12 * rig.mu_m_g {
            return Err(format!("mu_m_g = {}: this rig's is {}", self.mu_m_g, rig.mu_m_g));
        }
        Ok(())
    }

    /// The friction map m at plate point (x, y).
    pub fn map_at(&self, x: f64, y: f64) -> f64 {
        let t = friction_terms(self.plate_half_extent, x, y);
        1.0 + t.iter().zip(&self.friction_map).map(|(t, c)| t * c).sum::<f64>()
    }

    /// μ of a part of `class` at (x, y) over the nominal μ, within
    /// [`MIN_SCALE`, `MAX_SCALE`] wherever the part is (off the plate too,
    /// where the map is extrapolated). A class the calibration never saw
    /// takes the mean of those it saw.
    pub fn friction_scale(&self, class: u32, x: f64, y: f64) -> f64 {
        let s = match self.class_friction.iter().find(|f| f.class == class) {
            Some(f) => f.scale,
            None if self.class_friction.is_empty() => 1.0,
            None => {
                self.class_friction.iter().map(|f| f.scale).sum::<f64>() / self.class_friction.len() as f64
            }
        };
        (s * self.map_at(x, y)).clamp(MIN_SCALE, MAX_SCALE)
    }

    /// Write to `path` without ever leaving a half-written file there: the
    /// new file is written beside it, synced, and renamed over it; an old
    /// file is kept as `<path>.previous`. Returns the kept file, if any.
    pub fn write_atomically(&self, path: &Path) -> Result<Option<PathBuf>, String> {
        let shown = path.display();
        let text = toml::to_string_pretty(self).map_err(|e| format!("{shown}: {e}"))?;
        let text = format!("# Plate calibration written by `upm calibrate plate`.\n{text}");
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(format!(".new-{}", std::process::id()));
        let tmp = PathBuf::from(tmp);
        let write = || -> std::io::Result<()> {
            use std::io::Write;
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(text.as_bytes())?;
            f.sync_all()
        };
        write().map_err(|e| format!("{}: {e}", tmp.display()))?;
        let mut kept = None;
        if path.exists() {
            let mut prev = path.as_os_str().to_owned();
            prev.push(".previous");
            let prev = PathBuf::from(prev);
            std::fs::copy(path, &prev).map_err(|e| format!("{}: {e}", prev.display()))?;
            kept = Some(prev);
        }
        std::fs::rename(&tmp, path).map_err(|e| format!("{shown}: {e}"))?;
        Ok(kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> PlateCalibration {
        PlateCalibration {
            format: FORMAT,
            actuators: 4,
            centers: vec![[0.5, 0.2], [-0.5, -0.2]],
            plate_half_extent: [1.0, 0.5],
            mu_m_g: 0.1,
            twist_correction: [[1.01, 0.0, 0.002], [0.0, 0.99, -0.001], [0.0, 0.0, 1.0]],
            class_friction: vec![
                ClassFriction { class: 0, scale: 1.1 },
                ClassFriction { class: 1, scale: 0.8 },
            ],
            friction_map: [0.1, 0.0, 0.0, 0.1, 0.1],
            report: CalibrationReport::default(),
        }
    }

    #[test]
    fn written_files_read_back_and_replace_the_old_one_atomically() {
        let dir = std::env::temp_dir().join(format!("upm-platecal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("plate.toml");
        let c = sample();
        assert_eq!(c.write_atomically(&path).expect("write"), None);
        assert_eq!(PlateCalibration::load(&path).expect("load"), c);
        let mut d = sample();
        d.class_friction[0].scale = 1.2;
        let kept = d.write_atomically(&path).expect("write").expect("kept");
        assert_eq!(PlateCalibration::load(&kept).expect("old"), c);
        assert_eq!(PlateCalibration::load(&path).expect("new"), d);
        let stray = std::fs::read_dir(&dir).expect("dir").filter_map(|e| e.ok()).count();
        assert_eq!(stray, 2, "only the file and the previous one");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn bad_files_and_other_rigs_are_refused_naming_the_field() {
        let c = sample();
        let rig = RigIdentity {
            actuators: 4,
            centers: &c.centers.clone(),
            plate_half_extent: [1.0, 0.5],
            mu_m_g: 0.1,
        };
        c.check_rig(&rig).expect("same rig");
        let three = RigIdentity { actuators: 3, ..rig };
        assert!(c.check_rig(&three).expect_err("actuators").starts_with("actuators = 4"));
        let other = [[0.5, 0.2], [-0.5, -0.25]];
        let moved = RigIdentity { centers: &other, ..rig };
        assert!(c.check_rig(&moved).expect_err("centers").starts_with("centers[1]"));
        let fewer = RigIdentity { centers: &other[..1], ..rig };
        assert!(c.check_rig(&fewer).expect_err("count").starts_with("centers: 2 listed"));
        let mut bad = sample();
        bad.twist_correction[1][2] = f64::NAN;
        assert!(bad.validate().expect_err("nan").starts_with("twist_correction"));
        let mut bad = sample();
        bad.class_friction[1].scale = 0.0;
        assert!(bad.validate().expect_err("scale").starts_with("class_friction[1]"));
        let mut bad = sample();
        bad.friction_map[3] = 5.0;
        assert!(bad.validate().expect_err("map").starts_with("friction_map"));
        let text = toml::to_string(&sample()).expect("toml").replace("mu_m_g = 0.1", "mu_m_g = nan");
        let dir = std::env::temp_dir().join(format!("upm-platecal-nan-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("nan.toml");
        std::fs::write(&path, text).expect("write");
        let e = PlateCalibration::load(&path).expect_err("nan");
        assert!(e.contains("mu_m_g"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn friction_scale_is_the_class_times_the_map() {
        let c = sample();
        let m = c.map_at(0.5, 0.25);
        assert!((c.friction_scale(1, 0.5, 0.25) - 0.8 * m).abs() < 1e-15);
        assert!((c.friction_scale(7, 0.5, 0.25) - 0.95 * m).abs() < 1e-12, "unseen class: the mean");
    }
}
