//! The conformance suite, instantiated for the simulator's actuator models.

use drivers::{ActuatorKind, BodyShape, PartSpec, SimConfig, Simulator};
use upm_hardware::conformance;

fn sim(model: ActuatorKind) -> impl Fn() -> Simulator {
    move || {
        let cfg = SimConfig { actuator: model, ..SimConfig::default() };
        let parts = [
            PartSpec {
                shape: BodyShape::Point { radius: 0.01 },
                mass: 0.04,
                position: [0.5, 0.0],
                angle: 0.0,
            },
            PartSpec {
                shape: BodyShape::Disc { radius: 0.05 },
                mass: 0.04,
                position: [-0.5, 0.1],
                angle: 0.0,
            },
        ];
        Simulator::new(cfg, &parts).expect("default sim")
    }
}

#[test]
fn simulator_ideal_actuators_conforms() {
    conformance::run_all(sim(ActuatorKind::Ideal), 0, 1e-12);
}

#[test]
fn simulator_second_order_conforms() {
    // 1 kHz servo: settles in well under 200 ticks; closed to 1 µm.
    conformance::run_all(sim(SimConfig::default().actuator), 200, 1e-6);
}
