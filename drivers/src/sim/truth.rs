//! The plate as it really is, which only the simulator knows.
//!
//! A real rig differs from the model its controller uses: actuators are
//! mounted a few millimetres off and a few milliradians askew, position
//! sensors read a few percent off scale, the plate is heavier than
//! specified, and friction varies over a worn plate and from one part
//! material to another. [`PlateTruth`] is that difference. The simulator
//! plays the commands through it; the controller's crates (`rt-core`,
//! planner, vision, calibration) never link this crate, and the
//! calibration client is handed the rig file without `[sim]`.
//!
//! - Actuators: the plant's rig is the nominal one with each attachment
//!   moved by `attach_offset` and each direction turned by
//!   `direction_error`; a sensor reads (1 + `sensor_scale_error`)·stroke, so
//!   the servo that drives the reading to the command leaves the true stroke
//!   at command / (1 + e). To first order a commanded rotation about C
//!   becomes a rotation about a shifted center plus nothing else: the true
//!   twist is a fixed 3 × 3 map of the commanded one.
//! - Friction: μ at plate point (x, y) is μ·m(x, y)·s_part with the map m
//!   of [`FrictionMap`] and a scale per part (its class's).
//! - Plate mass and inertia are (1 + `plate_mass_error`) times the model's.

use core::fmt;

use upm_hardware::MAX_ACTUATORS;
use upm_motion::{Pose, Rig, RigParams, Twist};

use crate::rng::SplitMix64;

/// Terms of a [`FrictionMap`]: with u = x / half-extent x and v likewise,
/// u, v, u·v, u² − ⅓, v² − ⅓ (each averages to 0 over the plate).
pub const FRICTION_MAP_TERMS: usize = 5;

/// A smooth, low-order friction field over the plate, relative to the
/// nominal μ: m(x, y) = 1 + Σ c_k·term_k(u, v). Its mean over the plate is 1.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrictionMap {
    pub coefficients: [f64; FRICTION_MAP_TERMS],
}

impl FrictionMap {
    pub const FLAT: Self = Self { coefficients: [0.0; FRICTION_MAP_TERMS] };

    /// m at plate point (x, y) on a plate of `half_extent`.
    #[inline]
    pub fn scale_at(&self, half_extent: [f64; 2], x: f64, y: f64) -> f64 {
        let (u, v) = (x / half_extent[0], y / half_extent[1]);
        let c = &self.coefficients;
        1.0 + c[0] * u + c[1] * v + c[2] * u * v + c[3] * (u * u - 1.0 / 3.0) + c[4] * (v * v - 1.0 / 3.0)
    }

    /// The least and greatest m over the plate (on a 41 × 41 grid, which
    /// holds every extremum of a quadratic to 1e-3 of its spread).
    pub fn range(&self, half_extent: [f64; 2]) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=40 {
            for j in 0..=40 {
                let x = half_extent[0] * (i as f64 / 20.0 - 1.0);
                let y = half_extent[1] * (j as f64 / 20.0 - 1.0);
                let m = self.scale_at(half_extent, x, y);
                (lo, hi) = (lo.min(m), hi.max(m));
            }
        }
        (lo, hi)
    }

    pub fn is_flat(&self) -> bool {
        self.coefficients.iter().all(|&c| c == 0.0)
    }
}

/// How the real plate differs from the model (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlateTruth {
    /// Attachment point error of each actuator (m, plate frame).
    pub attach_offset: [[f64; 2]; MAX_ACTUATORS],
    /// Push direction error of each actuator (rad, counter-clockwise).
    pub direction_error: [f64; MAX_ACTUATORS],
    /// A sensor reads (1 + e)·stroke.
    pub sensor_scale_error: [f64; MAX_ACTUATORS],
    /// Plate mass and inertia are (1 + e) times the model's.
    pub plate_mass_error: f64,
    pub friction_map: FrictionMap,
}

/// Why a truth was refused; each names its field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TruthError {
    AttachOffset {
        actuator: usize,
    },
    DirectionError {
        actuator: usize,
    },
    SensorScaleError {
        actuator: usize,
    },
    PlateMassError,
    /// The map leaves [`MIN_FRICTION_SCALE`, `MAX_FRICTION_SCALE`] somewhere on the plate.
    FrictionMap {
        least: f64,
        greatest: f64,
    },
    /// A non-finite coefficient of the map.
    FrictionCoefficient {
        term: usize,
    },
    /// A part's friction scale outside the same range.
    PartFriction {
        part: usize,
    },
}

/// Friction may vary between these multiples of the nominal μ.
pub const MIN_FRICTION_SCALE: f64 = 0.2;
pub const MAX_FRICTION_SCALE: f64 = 3.0;

impl fmt::Display for TruthError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::AttachOffset { actuator } => {
                write!(f, "sim.truth.attach_offset_mm[{actuator}] must be finite and within 50 mm")
            }
            Self::DirectionError { actuator } => {
                write!(f, "sim.truth.direction_error_mrad[{actuator}] must be finite and within 100 mrad")
            }
            Self::SensorScaleError { actuator } => {
                write!(f, "sim.truth.sensor_scale_error_pct[{actuator}] must be finite and within 20 %")
            }
            Self::PlateMassError => {
                f.write_str("sim.truth.plate_mass_error_pct must be finite, in -50..=100")
            }
            Self::FrictionMap { least, greatest } => write!(
                f,
                "sim.truth.friction_map spans {least:.3}..{greatest:.3} of the nominal μ over the plate; \
                 it must stay within {MIN_FRICTION_SCALE}..{MAX_FRICTION_SCALE}"
            ),
            Self::FrictionCoefficient { term } => write!(f, "sim.truth.friction_map[{term}] is not finite"),
            Self::PartFriction { part } => write!(
                f,
                "part {part}: friction scale must be finite, within {MIN_FRICTION_SCALE}..{MAX_FRICTION_SCALE}"
            ),
        }
    }
}

impl core::error::Error for TruthError {}

/// A friction scale the simulator accepts.
pub fn friction_scale_ok(s: f64) -> bool {
    (MIN_FRICTION_SCALE..=MAX_FRICTION_SCALE).contains(&s)
}

impl PlateTruth {
    /// The model exactly.
    pub const NOMINAL: Self = Self {
        attach_offset: [[0.0; 2]; MAX_ACTUATORS],
        direction_error: [0.0; MAX_ACTUATORS],
        sensor_scale_error: [0.0; MAX_ACTUATORS],
        plate_mass_error: 0.0,
        friction_map: FrictionMap::FLAT,
    };

    /// A plate after years of use: every error of the kind
    /// [`PlateTruth::random`] draws, at about half its range, and a plate
    /// worn smooth in the middle (μ 10 % below nominal there, up to 25 %
    /// above it at the corners).
    pub fn worn() -> Self {
        let mut t = Self::NOMINAL;
        t.attach_offset[..4].copy_from_slice(&[[4e-3, -2e-3], [-3e-3, 3e-3], [2e-3, 5e-3], [-5e-3, -1e-3]]);
        t.direction_error[..4].copy_from_slice(&[3e-3, -4e-3, 2e-3, -2e-3]);
        t.sensor_scale_error[..4].copy_from_slice(&[0.02, -0.015, 0.025, -0.02]);
        t.plate_mass_error = 0.08;
        t.friction_map = FrictionMap { coefficients: [0.03, -0.02, 0.0, 0.15, 0.15] };
        t
    }

    /// The friction scale of part class `class` on [`PlateTruth::worn`]'s
    /// rig: class 1 a smoother material, class 2 a rougher one.
    pub fn worn_class_friction(class: u32) -> f64 {
        [1.0, 0.8, 1.15].get(class as usize).copied().unwrap_or(1.0)
    }

    /// A random truth for `count` actuators on a plate of `half_extent`:
    /// attachment offsets uniform in ±10 mm per axis, direction errors in
    /// ±5 mrad, sensor scales in ±5 %, plate mass in ±10 %, and a friction
    /// map whose greatest deviation from 1 over the plate is uniform in
    /// 10–30 %. Seeded; the same seed gives the same truth.
    pub fn random(seed: u64, count: usize, half_extent: [f64; 2]) -> Self {
        let mut rng = SplitMix64::new(seed ^ 0x7275_7468_u64);
        let mut u = |a: f64| a * (2.0 * rng.uniform() - 1.0);
        let mut t = Self::NOMINAL;
        for i in 0..count.min(MAX_ACTUATORS) {
            t.attach_offset[i] = [u(10e-3), u(10e-3)];
            t.direction_error[i] = u(5e-3);
            t.sensor_scale_error[i] = u(0.05);
        }
        t.plate_mass_error = u(0.10);
        let mut c = [0.0; FRICTION_MAP_TERMS];
        for ck in &mut c {
            *ck = u(1.0);
        }
        let spread = 0.2 + u(0.1);
        let map = FrictionMap { coefficients: c };
        let (lo, hi) = map.range(half_extent);
        let dev = (1.0 - lo).max(hi - 1.0);
        if dev > 0.0 {
            t.friction_map = FrictionMap { coefficients: c.map(|ck| ck * spread / dev) };
        }
        t
    }

    /// The friction scale of part class `class` in [`PlateTruth::random`]'s
    /// draw `seed`: uniform in 0.7–1.3, one per class.
    pub fn random_class_friction(seed: u64, class: u32) -> f64 {
        let mut rng = SplitMix64::new(seed ^ 0x636c_6173_u64 ^ (u64::from(class) << 32));
        0.7 + 0.6 * rng.uniform()
    }

    /// True when this is the model exactly.
    pub fn is_nominal(&self) -> bool {
        *self == Self::NOMINAL
    }

    pub fn validate(&self, half_extent: [f64; 2]) -> Result<(), TruthError> {
        for i in 0..MAX_ACTUATORS {
            let [dx, dy] = self.attach_offset[i];
            if !(dx.is_finite() && dy.is_finite() && dx.hypot(dy) <= 0.05) {
                return Err(TruthError::AttachOffset { actuator: i });
            }
            if !(self.direction_error[i].abs() <= 0.1) {
                return Err(TruthError::DirectionError { actuator: i });
            }
            if !(self.sensor_scale_error[i].abs() <= 0.2) {
                return Err(TruthError::SensorScaleError { actuator: i });
            }
        }
        if !(-0.5..=1.0).contains(&self.plate_mass_error) {
            return Err(TruthError::PlateMassError);
        }
        if let Some(term) = self.friction_map.coefficients.iter().position(|c| !c.is_finite()) {
            return Err(TruthError::FrictionCoefficient { term });
        }
        let (least, greatest) = self.friction_map.range(half_extent);
        if !(friction_scale_ok(least) && friction_scale_ok(greatest)) {
            return Err(TruthError::FrictionMap { least, greatest });
        }
        Ok(())
    }

    /// The rig the plate really is: `nominal` with the attachments moved,
    /// the directions turned and the plate's mass scaled.
    pub fn plant_rig(&self, nominal: &RigParams) -> RigParams {
        let mut p = *nominal;
        for (i, a) in p.actuators.iter_mut().enumerate().take(p.count) {
            let [ox, oy] = self.attach_offset[i];
            a.attach = [a.attach[0] + ox, a.attach[1] + oy];
            let (s, c) = self.direction_error[i].sin_cos();
            let [ux, uy] = a.direction;
            a.direction = [c * ux - s * uy, s * ux + c * uy];
        }
        p.plate_mass *= 1.0 + self.plate_mass_error;
        p.plate_inertia *= 1.0 + self.plate_mass_error;
        p
    }

    /// The twist a commanded twist becomes, to first order: its strokes
    /// on `nominal`, read by this plate's scaled sensors, through this
    /// plate's geometry. None if `nominal` is not a valid rig.
    pub fn true_twist(&self, nominal: &RigParams, xi: Twist) -> Option<Twist> {
        let [model, plant] = self.model_and_plant(nominal)?;
        Some(self.turned(&model, &plant, xi))
    }

    /// The map M of commanded twist → true twist (rows x, y, θ), to first
    /// order: a perfect calibration's correction is M⁻¹. For evaluation
    /// only: the controller never sees a truth. None if `nominal` is not a
    /// valid rig.
    pub fn twist_map(&self, nominal: &RigParams) -> Option<[[f64; 3]; 3]> {
        let [model, plant] = self.model_and_plant(nominal)?;
        let axes = [
            Twist { x: 1.0, ..Twist::default() },
            Twist { y: 1.0, ..Twist::default() },
            Twist { theta: 1.0, ..Twist::default() },
        ];
        let [x, y, t] = axes.map(|e| self.turned(&model, &plant, e));
        Some([[x.x, y.x, t.x], [x.y, y.y, t.y], [x.theta, y.theta, t.theta]])
    }

    fn model_and_plant(&self, nominal: &RigParams) -> Option<[Rig; 2]> {
        Some([Rig::new(*nominal).ok()?, Rig::new(self.plant_rig(nominal)).ok()?])
    }

    fn turned(&self, model: &Rig, plant: &Rig, xi: Twist) -> Twist {
        let mut v = [0.0; MAX_ACTUATORS];
        model.actuator_velocities(&Pose::HOME, &xi, &mut v);
        for (vi, e) in v.iter_mut().zip(self.sensor_scale_error) {
            *vi /= 1.0 + e;
        }
        plant.twist_from_actuators_exact(&Pose::HOME, &v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HALF: [f64; 2] = [1.0, 0.5];

    #[test]
    fn presets_are_valid_and_random_draws_stay_in_their_ranges() {
        assert!(PlateTruth::NOMINAL.is_nominal());
        PlateTruth::worn().validate(HALF).expect("worn");
        let (lo, hi) = PlateTruth::worn().friction_map.range(HALF);
        assert!(lo < 0.95 && hi > 1.2, "{lo} {hi}");
        for seed in 0..200 {
            let t = PlateTruth::random(seed, 4, HALF);
            t.validate(HALF).expect("random");
            assert_eq!(t, PlateTruth::random(seed, 4, HALF));
            let (lo, hi) = t.friction_map.range(HALF);
            let dev = (1.0 - lo).max(hi - 1.0);
            assert!((0.1 - 1e-9..=0.3 + 1e-9).contains(&dev), "seed {seed}: {dev}");
            assert!(t.attach_offset[..4].iter().flatten().all(|o| o.abs() <= 10e-3));
            assert!(t.sensor_scale_error[..4].iter().all(|e| e.abs() <= 0.05));
            assert!(t.attach_offset[4..].iter().flatten().all(|&o| o == 0.0));
            for class in 0..8 {
                let s = PlateTruth::random_class_friction(seed, class);
                assert!((0.7..=1.3).contains(&s));
            }
        }
        assert_ne!(PlateTruth::random(1, 4, HALF), PlateTruth::random(2, 4, HALF));
    }

    #[test]
    fn the_map_averages_to_one_and_bad_truths_name_their_field() {
        let m = FrictionMap { coefficients: [0.1, -0.2, 0.3, 0.2, -0.1] };
        let n = 200;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = HALF[0] * (2.0 * (i as f64 + 0.5) / n as f64 - 1.0);
                let y = HALF[1] * (2.0 * (j as f64 + 0.5) / n as f64 - 1.0);
                sum += m.scale_at(HALF, x, y);
            }
        }
        assert!((sum / (n * n) as f64 - 1.0).abs() < 1e-4);
        let mut t = PlateTruth::NOMINAL;
        t.attach_offset[2] = [0.04, 0.04];
        assert_eq!(t.validate(HALF), Err(TruthError::AttachOffset { actuator: 2 }));
        let mut t = PlateTruth::NOMINAL;
        t.sensor_scale_error[1] = f64::NAN;
        assert_eq!(t.validate(HALF), Err(TruthError::SensorScaleError { actuator: 1 }));
        let mut t = PlateTruth::NOMINAL;
        t.friction_map.coefficients[3] = 4.0;
        let e = t.validate(HALF).expect_err("steep map");
        assert!(e.to_string().starts_with("sim.truth.friction_map spans"), "{e}");
    }

    #[test]
    fn the_plant_rig_moves_turns_and_weighs() {
        let nominal = RigParams::default();
        assert_eq!(PlateTruth::NOMINAL.plant_rig(&nominal), nominal);
        let p = PlateTruth::worn().plant_rig(&nominal);
        assert!((p.actuators[0].attach[0] - (nominal.actuators[0].attach[0] + 4e-3)).abs() < 1e-15);
        let d = p.actuators[1].direction;
        assert!((d[0].hypot(d[1]) - 1.0).abs() < 1e-12 && (d[1] - (-4e-3f64).sin()).abs() < 1e-12);
        assert!((p.plate_mass - 1.08).abs() < 1e-12);
    }
}
