//! The one TOML config of a rig (`upm-core --config F`), validated at
//! start-up. Every section and field is optional and has a default; unknown
//! fields are errors, and every message names the field.

use std::path::Path;

use drivers::{ActuatorModel, SimConfig};
use rt_core::motion::{MotionLimits, MotionParams, RigParams};
use rt_core::runtime::{CoreParams, RtParams};
use serde::{Deserialize, Serialize};

#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("reading {path}: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    #[error("{path}: {message}")]
    Invalid { path: String, message: String },
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
#[derive(Default)]
pub struct Config {
    pub service: ServiceSection,
    pub plate: PlateSection,
    pub motion: MotionSection,
    pub rt: RtSection,
    pub safety: SafetySection,
    pub telemetry: TelemetrySection,
    pub sim: SimSection,
    pub vision: VisionSection,
}

/// The simulated camera and its tracker (`upm-vision`).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct VisionSection {
    pub frame_hz: f64,
    pub noise_mm: f64,
    pub noise_deg: f64,
    pub latency_ms: f64,
    pub drop_probability: f64,
    pub seed: u64,
    pub alpha: f64,
    pub beta: f64,
    pub gate_mm: f64,
    pub max_missed_frames: u32,
}

impl Default for VisionSection {
    fn default() -> Self {
        let c = crate::vision::CameraParams::default();
        let t = crate::vision::TrackerParams::default();
        Self {
            frame_hz: c.frame_hz,
            noise_mm: c.noise_m * 1e3,
            noise_deg: c.noise_rad.to_degrees(),
            latency_ms: c.latency_s * 1e3,
            drop_probability: c.drop_probability,
            seed: c.seed,
            alpha: t.alpha,
            beta: t.beta,
            gate_mm: t.gate_m * 1e3,
            max_missed_frames: t.max_missed,
        }
    }
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct ServiceSection {
    /// iceoryx2 prefix: one per rig, so rigs (and tests) never see each other.
    pub prefix: String,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PlateSection {
    pub half_extent: [f64; 2],
    pub mu_m_g: f64,
    pub centers: Vec<[f64; 2]>,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct MotionSection {
    pub tick_hz: f64,
    pub slot_ticks: u32,
    pub displacement_mm: f64,
    pub k_max: f64,
    pub max_angle: f64,
    pub max_angular_velocity: f64,
    pub max_angular_acceleration: f64,
    pub max_point_speed: f64,
    pub max_point_acceleration: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct RtSection {
    pub motor_priority: u8,
    pub solver_priority: u8,
    /// CPU to pin the motor thread to; -1 = not pinned.
    pub motor_cpu: i64,
    pub solver_cpu: i64,
    pub lock_memory: bool,
    pub solver_poll_us: u64,
    /// How the core's receiver thread waits for clients.
    pub receiver: Receiver,
    /// SCHED_FIFO priority of the receiver in event mode; 0 = normal.
    pub receiver_priority: u8,
    /// PM QoS request held on /dev/cpu_dma_latency (µs), or "leave".
    pub cpu_dma_latency_us: DmaLatency,
    /// Keep normal-priority work (the core's io thread, the clients `upm
    /// run` starts) off the motor's CPU.
    pub isolate_motor_cpu: bool,
}

/// `rt.cpu_dma_latency_us`: a bound in µs, or `"leave"` the host's policy.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, Eq)]
#[serde(untagged)]
pub enum DmaLatency {
    Us(u32),
    Keyword(String),
}

/// `rt.receiver`: sleep on the clients' wake-up event, or busy-poll.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum Receiver {
    #[default]
    Event,
    Spin,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SafetySection {
    pub parts_max_age_ms: f64,
    pub request_max_age_ms: f64,
    pub max_future_skew_ms: f64,
    /// A driver-fault hold ends by itself after this many ms of healthy
    /// driver reads; 0 = only `upm resume` ends it.
    pub auto_resume_ms: f64,
    /// After a core thread dies, how long the core reports it (plate held)
    /// before it exits with an error.
    pub fault_exit_ms: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct TelemetrySection {
    pub period_ms: f64,
    /// Where upm-core writes `*.hgrm` at exit ("" = not written).
    pub histogram_dir: String,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SimSection {
    pub seed: u64,
    pub mu_static: f64,
    pub mu_kinetic: f64,
    /// "second_order" or "ideal".
    pub actuator: String,
    pub bandwidth_hz: f64,
    pub damping: f64,
    pub substeps: u32,
    /// Parts on the simulated plate (the simulated camera sees these).
    pub parts: Vec<SimPartSection>,
}

/// One `[[sim.parts]]` entry.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimPartSection {
    pub id: u32,
    #[serde(default)]
    pub class: u32,
    /// "point", "disc" or "square".
    pub shape: String,
    /// Disc radius or square side (m); a point's radius for contacts.
    pub size: f64,
    pub mass: f64,
    pub position: [f64; 2],
    #[serde(default)]
    pub angle: f64,
}

/// The simulator's parts with the ids and classes the camera reports.
#[derive(Debug, Clone, Default)]
pub struct SimParts {
    pub specs: Vec<drivers::PartSpec>,
    pub ids: Vec<u32>,
    pub classes: Vec<u32>,
}

impl Default for ServiceSection {
    fn default() -> Self {
        Self { prefix: "upm_".into() }
    }
}

impl Default for PlateSection {
    fn default() -> Self {
        let c = CoreParams::default();
        Self { half_extent: c.motion.plate_half_extent, mu_m_g: c.mu_m_g, centers: c.centers }
    }
}

impl Default for MotionSection {
    fn default() -> Self {
        let m = MotionParams::default();
        Self {
            tick_hz: m.tick_hz,
            slot_ticks: m.slot_ticks,
            displacement_mm: m.displacement * 1e3,
            k_max: m.k_max,
            max_angle: m.limits.max_angle,
            max_angular_velocity: m.limits.max_angular_velocity,
            max_angular_acceleration: m.limits.max_angular_acceleration,
            max_point_speed: m.limits.max_point_speed,
            max_point_acceleration: m.limits.max_point_acceleration,
        }
    }
}

impl Default for RtSection {
    fn default() -> Self {
        let r = RtParams::default();
        let cpu = |c: Option<usize>| c.map_or(-1, |c| c as i64);
        Self {
            motor_priority: r.motor_priority,
            solver_priority: r.solver_priority,
            motor_cpu: cpu(r.motor_cpu),
            solver_cpu: cpu(r.solver_cpu),
            lock_memory: r.lock_memory,
            solver_poll_us: CoreParams::default().solver_poll_ns / 1000,
            receiver: Receiver::Event,
            receiver_priority: r.receiver_priority,
            cpu_dma_latency_us: r
                .cpu_dma_latency_us
                .map_or(DmaLatency::Keyword("leave".into()), DmaLatency::Us),
            isolate_motor_cpu: r.isolate_motor_cpu,
        }
    }
}

impl Default for SafetySection {
    fn default() -> Self {
        let c = CoreParams::default();
        Self {
            parts_max_age_ms: c.parts_max_age_ns as f64 / 1e6,
            request_max_age_ms: c.request_max_age_ns as f64 / 1e6,
            max_future_skew_ms: c.max_future_skew_ns as f64 / 1e6,
            auto_resume_ms: c.auto_resume_ns as f64 / 1e6,
            fault_exit_ms: c.fault_exit_ns as f64 / 1e6,
        }
    }
}

impl Default for TelemetrySection {
    fn default() -> Self {
        Self {
            period_ms: CoreParams::default().telemetry_period_ns as f64 / 1e6,
            histogram_dir: String::new(),
        }
    }
}

impl Default for SimSection {
    fn default() -> Self {
        let s = SimConfig::default();
        let (bandwidth_hz, damping) = match s.actuator {
            ActuatorModel::SecondOrder { bandwidth_hz, damping } => (bandwidth_hz, damping),
            ActuatorModel::Ideal => (1000.0, 0.7),
        };
        Self {
            seed: s.seed,
            mu_static: s.mu_static,
            mu_kinetic: s.mu_kinetic,
            actuator: "second_order".into(),
            bandwidth_hz,
            damping,
            substeps: s.substeps,
            parts: Vec::new(),
        }
    }
}

/// Milliseconds (finite, > 0) to nanoseconds, or a message naming `field`.
fn ms_to_ns(ms: f64, field: &str) -> Result<u64, String> {
    if ms.is_finite() && ms > 0.0 && ms < 1e9 {
        Ok((ms * 1e6).round() as u64)
    } else {
        Err(format!("{field} must be a positive number of milliseconds, got {ms}"))
    }
}

/// Like [`ms_to_ns`], but 0 is allowed (it turns the feature off).
fn ms_to_ns_or_zero(ms: f64, field: &str) -> Result<u64, String> {
    if ms == 0.0 {
        return Ok(0);
    }
    ms_to_ns(ms, field)
        .map_err(|_| format!("{field} must be 0 or a positive number of milliseconds, got {ms}"))
}

/// A CPU to pin to: one this process may run on (its affinity mask), or -1.
fn cpu(c: i64, field: &str) -> Result<Option<usize>, String> {
    let allowed = rt_core::runtime::rt_setup::allowed_cpus();
    match c {
        -1 => Ok(None),
        c if c >= 0 && allowed.contains(&(c as usize)) => Ok(Some(c as usize)),
        c => Err(format!("{field} = {c}: this process may run on CPUs {allowed:?} (or -1 for no pinning)")),
    }
}

impl Config {
    /// Parse TOML text; errors name the field (`motion.tick_hz: invalid type …`).
    pub fn parse(text: &str, path: &str) -> Result<Self, ConfigError> {
        let de = toml::Deserializer::parse(text)
            .map_err(|e| ConfigError::Parse { path: path.into(), message: one_line(&e.to_string()) })?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let message = one_line(&e.into_inner().to_string());
            ConfigError::Parse {
                path: path.into(),
                message: if field == "." { message } else { format!("{field}: {message}") },
            }
        })
    }

    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|source| ConfigError::Read { path: shown.clone(), source })?;
        Self::parse(&text, &shown)
    }

    /// The validated core parameters.
    pub fn core_params(&self, path: &str) -> Result<CoreParams, ConfigError> {
        self.core_params_inner().map_err(|message| ConfigError::Invalid { path: path.into(), message })
    }

    fn core_params_inner(&self) -> Result<CoreParams, String> {
        let m = &self.motion;
        let motion = MotionParams {
            tick_hz: m.tick_hz,
            slot_ticks: m.slot_ticks,
            displacement: m.displacement_mm * 1e-3,
            plate_half_extent: self.plate.half_extent,
            k_max: m.k_max,
            limits: MotionLimits {
                max_angle: m.max_angle,
                max_angular_velocity: m.max_angular_velocity,
                max_angular_acceleration: m.max_angular_acceleration,
                max_point_speed: m.max_point_speed,
                max_point_acceleration: m.max_point_acceleration,
            },
            ..MotionParams::default()
        };
        if !(self.telemetry.period_ms.is_finite() && self.telemetry.period_ms >= 1.0) {
            return Err(format!("telemetry.period_ms must be at least 1, got {}", self.telemetry.period_ms));
        }
        if self.rt.solver_poll_us == 0 {
            return Err("rt.solver_poll_us must be positive".into());
        }
        if self.service.prefix.is_empty()
            || !self.service.prefix.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        {
            return Err(format!(
                "service.prefix {:?} must be non-empty ASCII letters, digits, '_' or '-'",
                self.service.prefix
            ));
        }
        let params = CoreParams {
            motion,
            rig: RigParams::default(),
            centers: self.plate.centers.clone(),
            mu_m_g: self.plate.mu_m_g,
            parts_max_age_ns: ms_to_ns(self.safety.parts_max_age_ms, "safety.parts_max_age_ms")?,
            request_max_age_ns: ms_to_ns(self.safety.request_max_age_ms, "safety.request_max_age_ms")?,
            max_future_skew_ns: ms_to_ns(self.safety.max_future_skew_ms, "safety.max_future_skew_ms")?,
            solver_poll_ns: self.rt.solver_poll_us.saturating_mul(1000),
            telemetry_period_ns: ms_to_ns(self.telemetry.period_ms, "telemetry.period_ms")?,
            auto_resume_ns: ms_to_ns_or_zero(self.safety.auto_resume_ms, "safety.auto_resume_ms")?,
            fault_exit_ns: ms_to_ns_or_zero(self.safety.fault_exit_ms, "safety.fault_exit_ms")?,
            rt: RtParams {
                motor_priority: self.rt.motor_priority,
                solver_priority: self.rt.solver_priority,
                motor_cpu: cpu(self.rt.motor_cpu, "rt.motor_cpu")?,
                solver_cpu: cpu(self.rt.solver_cpu, "rt.solver_cpu")?,
                lock_memory: self.rt.lock_memory,
                receiver: match self.rt.receiver {
                    Receiver::Event => rt_core::runtime::ReceiverWake::Event,
                    Receiver::Spin => rt_core::runtime::ReceiverWake::Spin,
                },
                receiver_priority: self.rt.receiver_priority,
                isolate_motor_cpu: self.rt.isolate_motor_cpu,
                cpu_dma_latency_us: match &self.rt.cpu_dma_latency_us {
                    DmaLatency::Us(us) => Some(*us),
                    DmaLatency::Keyword(k) if k == "leave" => None,
                    DmaLatency::Keyword(k) => {
                        return Err(format!(
                            "rt.cpu_dma_latency_us must be a number of µs or \"leave\", got {k:?}"
                        ));
                    }
                },
            },
        };
        // Complete validation: the core would refuse an unplayable rig at start.
        params.playable_k_max().map_err(|e| e.to_string())?;
        Ok(params)
    }

    /// The simulator's configuration, consistent with the core's.
    pub fn sim_config(&self, path: &str) -> Result<SimConfig, ConfigError> {
        let s = &self.sim;
        let actuator = match s.actuator.as_str() {
            "second_order" => ActuatorModel::SecondOrder { bandwidth_hz: s.bandwidth_hz, damping: s.damping },
            "ideal" => ActuatorModel::Ideal,
            other => {
                return Err(ConfigError::Invalid {
                    path: path.into(),
                    message: format!("sim.actuator {other:?}: expected \"second_order\" or \"ideal\""),
                });
            }
        };
        let cfg = SimConfig {
            tick_hz: self.motion.tick_hz,
            substeps: s.substeps,
            mu_static: s.mu_static,
            mu_kinetic: s.mu_kinetic,
            actuator,
            rig: RigParams::default(),
            plate_half_extent: self.plate.half_extent,
            seed: s.seed,
            ..SimConfig::default()
        };
        cfg.validate().map_err(|e| ConfigError::Invalid { path: path.into(), message: e.to_string() })?;
        Ok(cfg)
    }

    /// `[[sim.parts]]` as simulator part specs; ids must be unique.
    pub fn sim_parts(&self, path: &str) -> Result<SimParts, ConfigError> {
        let invalid = |message: String| ConfigError::Invalid { path: path.into(), message };
        let mut out = SimParts::default();
        for (i, p) in self.sim.parts.iter().enumerate() {
            let field = format!("sim.parts[{i}]");
            if out.ids.contains(&p.id) {
                return Err(invalid(format!("{field}.id {} is used twice", p.id)));
            }
            if !(p.size.is_finite() && p.size > 0.0) {
                return Err(invalid(format!("{field}.size must be finite and positive")));
            }
            let shape = match p.shape.as_str() {
                "point" => drivers::Shape::Point { radius: p.size },
                "disc" => drivers::Shape::Disc { radius: p.size },
                "square" => {
                    let h = 0.5 * p.size;
                    let mut vertices = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
                    vertices[..4].copy_from_slice(&[[-h, -h], [h, -h], [h, h], [-h, h]]);
                    drivers::Shape::Polygon { vertices, count: 4 }
                }
                other => {
                    return Err(invalid(format!(
                        "{field}.shape {other:?}: expected \"point\", \"disc\" or \"square\""
                    )));
                }
            };
            out.specs.push(drivers::PartSpec { shape, mass: p.mass, position: p.position, angle: p.angle });
            out.ids.push(p.id);
            out.classes.push(p.class);
        }
        // The simulator checks mass, position and capacity; name the part.
        if let Err(e) = drivers::Simulator::new(SimConfig::default(), &out.specs) {
            return Err(invalid(format!("sim.parts: {e}")));
        }
        Ok(out)
    }

    /// Camera and tracker parameters; errors name the field.
    pub fn vision_params(
        &self,
        path: &str,
    ) -> Result<(crate::vision::CameraParams, crate::vision::TrackerParams), ConfigError> {
        let v = &self.vision;
        let cam = crate::vision::CameraParams {
            frame_hz: v.frame_hz,
            noise_m: v.noise_mm * 1e-3,
            noise_rad: v.noise_deg.to_radians(),
            latency_s: v.latency_ms * 1e-3,
            drop_probability: v.drop_probability,
            seed: v.seed,
        };
        crate::vision::Camera::new(cam)
            .map_err(|message| ConfigError::Invalid { path: path.into(), message })?;
        if !(v.alpha > 0.0 && v.alpha <= 1.0 && v.beta > 0.0 && v.beta < 2.0) {
            return Err(ConfigError::Invalid {
                path: path.into(),
                message: "vision: need 0 < alpha <= 1 and 0 < beta < 2".into(),
            });
        }
        if !(v.gate_mm.is_finite() && v.gate_mm > 0.0) {
            return Err(ConfigError::Invalid {
                path: path.into(),
                message: "vision.gate_mm must be positive".into(),
            });
        }
        let tracker = crate::vision::TrackerParams {
            alpha: v.alpha,
            beta: v.beta,
            gate_m: v.gate_mm * 1e-3,
            max_missed: v.max_missed_frames,
        };
        Ok((cam, tracker))
    }

    /// The motor thread's CPU, if it is pinned (and the number is valid).
    /// The motor's CPU if normal-priority work should stay off it.
    pub fn cpu_to_avoid(&self) -> Option<usize> {
        self.rt.isolate_motor_cpu.then(|| self.rt_motor_cpu()).flatten()
    }

    pub fn rt_motor_cpu(&self) -> Option<usize> {
        cpu(self.rt.motor_cpu, "rt.motor_cpu").ok().flatten()
    }

    pub fn histogram_dir(&self) -> Option<&Path> {
        (!self.telemetry.histogram_dir.is_empty()).then(|| Path::new(&self.telemetry.histogram_dir))
    }
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
