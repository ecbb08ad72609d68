//! The suite every plate driver passes, on the example's stepper plate.

use upm_example_driver::StepperPlate;
use upm_hardware::conformance::{self, Tolerances};
use upm_motion::RigParams;

fn stepper() -> StepperPlate {
    StepperPlate::new(RigParams::default(), 10_000.0).expect("the default rig")
}

#[test]
fn the_stepper_plate_conforms() {
    // It lands on its command within the tick, to a whole step (1 µm).
    conformance::run_all_with(stepper, Tolerances { settle: 0, home: 1e-6, latency_ticks: 0 });
}
