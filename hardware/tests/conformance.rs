//! The conformance suite on the ideal mock: the reference every driver's
//! own instantiation is held to.

use upm_hardware::{IdealDriver, conformance};
use upm_motion::RigParams;

fn ideal() -> IdealDriver {
    IdealDriver::new(RigParams::default(), 10_000.0).expect("default rig")
}

#[test]
fn ideal_mock_conforms() {
    conformance::run_all(ideal, 0, 1e-12);
}
