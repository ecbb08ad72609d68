//! `upm_ipc.max_force` (clients/python) against `solver::max_force_in`: a
//! Python planner reading `RigInfo` gets the reach the solver has, on the
//! paper's cycle and on sparse cycles. Needs `python3` (ctypes only).

use std::process::Command;

use ipc_types::WireMessage;
use rt_core::{CoreParams, rig_info};
use upm_solver::max_force_in;

const MESSAGES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../clients/python/upm_ipc/messages.py");

#[test]
fn python_max_force_is_the_solvers_reach() {
    let points = [[0.0, 0.0], [0.5, 0.0], [-0.75, 0.25], [0.93, -0.41], [0.05, 0.45]];
    let directions: Vec<[f64; 2]> =
        (0..7).map(|a| [(a as f64 * 0.9).cos(), (a as f64 * 0.9).sin()]).collect();
    for cycle_slots in [0, 12] {
        let mut params = CoreParams::default();
        params.motion.cycle_slots = cycle_slots;
        params.plate.centers.extend([[0.2, 0.3], [-0.4, -0.2], [0.7, 0.05]]);
        let bounds = params.playable_k_bounds().expect("playable");
        let info = rig_info(&params, &bounds, "upm_py_", 30.0);
        let file =
            std::env::temp_dir().join(format!("upm_rig_info_{}_{cycle_slots}.bin", std::process::id()));
        std::fs::write(&file, info.as_bytes()).expect("write");
        let mut queries = String::new();
        let mut want = Vec::new();
        for p in points {
            for d in &directions {
                queries += &format!("{} {} {} {}\n", p[0], p[1], d[0], d[1]);
                want.push(max_force_in(
                    &params.plate.centers,
                    &bounds,
                    params.plate.mu_m_g,
                    cycle_slots,
                    info.keep_out_m,
                    p,
                    *d,
                ));
            }
        }
        let script = r#"
import importlib.util, sys
spec = importlib.util.spec_from_file_location("messages", sys.argv[1])
m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)
info = m.RigInfo.from_buffer_copy(open(sys.argv[2], "rb").read())
for line in sys.stdin:
    x, y, ux, uy = map(float, line.split())
    print(repr(m.max_force(info, x, y, ux, uy)))
"#;
        let mut child = Command::new("python3")
            .args(["-c", script, MESSAGES])
            .arg(&file)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("python3 runs");
        use std::io::Write;
        child.stdin.take().expect("stdin").write_all(queries.as_bytes()).expect("queries");
        let out = child.wait_with_output().expect("python3 ends");
        let _ = std::fs::remove_file(&file);
        assert!(out.status.success(), "python3: {}", String::from_utf8_lossy(&out.stderr));
        let got: Vec<f64> =
            String::from_utf8_lossy(&out.stdout).lines().map(|l| l.parse().expect("a number")).collect();
        assert_eq!(got.len(), want.len());
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!(
                (g - w).abs() <= 1e-12 * w.max(1e-3),
                "cycle_slots {cycle_slots}, query {i}: Python {g}, Rust {w}"
            );
        }
        assert!(want.iter().all(|&w| w > 0.0 && w <= info.max_part_force_n * (1.0 + 1e-12)));
    }
}
