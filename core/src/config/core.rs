//! `[rt]`, `[safety]` and `[telemetry]` are read straight into
//! `rt_core::RtParams`, `SafetyParams` and `TelemetryParams`. What the file
//! cannot say by itself is checked here: whether this process may run on
//! the CPUs `[rt]` names.

use rt_core::RtParams;

/// The CPUs `[rt]` pins to, each one this process may run on (its
/// affinity mask); the message names the field.
pub(super) fn check_cpus(rt: &RtParams) -> Result<(), String> {
    let allowed = rt_core::rt_setup::allowed_cpus();
    for (cpu, field) in [(rt.motor_cpu, "rt.motor_cpu"), (rt.solver_cpu, "rt.solver_cpu")] {
        if let Some(c) = cpu.filter(|c| !allowed.contains(c)) {
            return Err(format!(
                "{field} = {c}: this process may run on CPUs {allowed:?} (or -1 for no pinning)"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::config::CoreConfig;

    #[test]
    fn rt_safety_and_telemetry_read_in_the_files_units_and_name_the_field() {
        let text = "[rt]\nsolver_poll_us = 250\nmotor_cpu = -1\ncpu_dma_latency_us = \"leave\"\n\
                    receiver = \"spin\"\n[safety]\nparts_max_age_ms = 50.5\n[telemetry]\nperiod_ms = 20\n";
        let c: CoreConfig = CoreConfig::parse(text, "x.toml").expect("parses");
        let p = c.core_params("x.toml").expect("valid");
        assert_eq!((p.rt.solver_poll_ns, p.rt.motor_cpu, p.rt.cpu_dma_latency_us), (250_000, None, None));
        assert_eq!(p.rt.receiver, rt_core::ReceiverWake::Spin);
        assert_eq!((p.safety.parts_max_age_ns, p.telemetry.period_ns), (50_500_000, 20_000_000));
        assert_eq!(p.safety.request_max_age_ns, rt_core::SafetyParams::default().request_max_age_ns);
        for (bad, field) in [
            ("[rt]\nsolver_poll_us = 0", "rt.solver_poll_us"),
            ("[rt]\nmotor_cpu = -3", "rt.motor_cpu"),
            ("[rt]\nmotor_cpu = 4096", "rt.motor_cpu"),
            ("[rt]\ncpu_dma_latency_us = \"soon\"", "rt.cpu_dma_latency_us"),
            ("[rt]\nreceiver = \"poll\"", "rt.receiver"),
            ("[safety]\nparts_max_age_ms = 0", "safety.parts_max_age_ms"),
            ("[safety]\nfault_exit_ms = -1", "safety.fault_exit_ms"),
            ("[safety]\nauto_resume_ms = nan", "safety.auto_resume_ms"),
            ("[telemetry]\nperiod_ms = 0.5", "telemetry.period_ms"),
        ] {
            let e = CoreConfig::<toml::Table>::parse(bad, "x.toml")
                .and_then(|c| c.core_params("x.toml").map(drop))
                .expect_err(bad)
                .to_string();
            assert!(e.contains(field) && !e.contains('\n'), "{bad}: {e}");
        }
    }
}
