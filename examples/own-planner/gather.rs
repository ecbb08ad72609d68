//! An external planner in ~50 lines: a separate process that plugs into a
//! running rig through the `Planner` trait. It gathers every part towards
//! the plate's centre, at most 2 cm/s.
//!
//! cargo run --release -p upm-planner --example gather -- --prefix upm_run_1234_

pub mod gather {
    use ipc_types::{ForceEntry, ForceRequest, PartStates};
    use upm_planner::Planner;

    /// Every part gets m·k·(v_desired − v) towards (0, 0), clamped.
    #[derive(Debug)]
    pub struct Gather {
        pub mass: f64,
        pub max_force: f64,
    }

    impl Planner for Gather {
        fn name(&self) -> &'static str {
            "gather"
        }

        fn plan(&mut self, parts: &PartStates, _t: f64, out: &mut ForceRequest) -> bool {
            out.clear();
            for p in parts.parts() {
                let (dx, dy) = (-p.x, -p.y);
                let d = dx.hypot(dy).max(1e-9);
                let speed = (0.5 * d).min(0.02);
                let (vx, vy) = (speed * dx / d, speed * dy / d);
                let f = [self.mass * 8.0 * (vx - p.vx), self.mass * 8.0 * (vy - p.vy)];
                let n = f[0].hypot(f[1]);
                let s = if n > self.max_force { self.max_force / n } else { 1.0 };
                if out.push(ForceEntry::force(p.id, [f[0] * s, f[1] * s])).is_err() {
                    break;
                }
            }
            !out.is_empty()
        }
    }
}

#[allow(dead_code)] // the test includes this file for the planner only
fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let prefix = args.iter().position(|a| a == "--prefix").and_then(|i| args.get(i + 1)).cloned();
    let prefix = prefix.unwrap_or_else(|| rig_config::ServiceSection::default().prefix);
    let mut planner = gather::Gather { mass: 0.1 / (0.25 * 9.81), max_force: 0.01 };
    let sent = upm_planner::run::run_planner(&mut planner, &prefix, None)?;
    eprintln!("external planner: {sent} requests");
    Ok(())
}
