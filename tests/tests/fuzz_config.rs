//! Fuzz: the rig config (TOML). Mutations of the shipped example and of
//! every scenario's config: a value replaced by any TOML value (nan, inf,
//! huge, negative, wrong type), a line dropped or repeated, an unknown key,
//! character edits. Parsing and validation must give a one-line error
//! naming the file, or a config the core can start and run from; never a
//! panic.

use drivers::Simulator;
use proptest::prelude::*;
use rt_core::lockstep::Lockstep;
use upm_commands::config::Config;
use upm_commands::scenario::Scenario;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
const PATH: &str = "fuzz.toml";

/// The shipped example plus the config every scenario runs with.
static BASE_TEXTS: std::sync::LazyLock<Vec<String>> = std::sync::LazyLock::new(base_texts);

fn base_texts() -> Vec<String> {
    let mut texts = vec![std::fs::read_to_string(format!("{ROOT}/examples/core.toml")).expect("example")];
    for name in ["track", "sort", "spin", "local"] {
        let path = std::path::PathBuf::from(format!("{ROOT}/scenarios/{name}.toml"));
        let config = Scenario::load(&path).and_then(|s| s.config(7, "upm_fuzz_")).expect("scenario config");
        texts.push(toml::to_string(&config).expect("config prints"));
    }
    texts
}

fn toml_value() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "nan",
            "inf",
            "-inf",
            "0",
            "-1",
            "0.0",
            "1e308",
            "-1e308",
            "1e-320",
            "9223372036854775807",
            "-9223372036854775808",
            "true",
            "\"\"",
            "\"x\"",
            "[]",
            "[1.0]",
            "[[0.0, 0.0]]",
            "{}",
            "{ a = 1 }",
            "1979-05-27",
            "[nan, inf]",
            "[1e308, 1e308]",
            "[[1e308, 0.0], [nan, 0.0]]",
        ])
        .prop_map(str::to_owned),
        any::<f64>().prop_map(|v| if v.is_finite() { format!("{v:e}") } else { "nan".to_owned() }),
        any::<i64>().prop_map(|v| v.to_string()),
        (-1e6..1e6f64).prop_map(|v| format!("{v:?}")),
    ]
}

#[derive(Debug, Clone)]
enum Edit {
    /// Replace the value of the n-th `key = value` line.
    Value(prop::sample::Index, String),
    Drop(prop::sample::Index),
    Repeat(prop::sample::Index),
    UnknownKey(prop::sample::Index),
    Char(prop::sample::Index, char),
}

fn edit() -> impl Strategy<Value = Edit> {
    let i = any::<prop::sample::Index>;
    prop_oneof![
        6 => (i(), toml_value()).prop_map(|(at, v)| Edit::Value(at, v)),
        1 => i().prop_map(Edit::Drop),
        1 => i().prop_map(Edit::Repeat),
        1 => i().prop_map(Edit::UnknownKey),
        1 => (i(), prop::sample::select("=[]{}\"#.,\n 0-e".chars().collect::<Vec<_>>())).prop_map(|(at, c)| Edit::Char(at, c)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    for e in edits {
        let values: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].contains(" = ")).collect();
        match e {
            Edit::Value(at, v) if !values.is_empty() => {
                let i = values[at.index(values.len())];
                let key = lines[i].split(" = ").next().unwrap_or_default().to_owned();
                lines[i] = format!("{key} = {v}");
            }
            Edit::Drop(at) if !lines.is_empty() => {
                lines.remove(at.index(lines.len()));
            }
            Edit::Repeat(at) if !lines.is_empty() => {
                let i = at.index(lines.len());
                lines.insert(i, lines[i].clone());
            }
            Edit::UnknownKey(at) => lines.insert(at.index(lines.len() + 1), "surprise = 1".to_owned()),
            Edit::Char(at, c) => {
                let mut joined = lines.join("\n");
                let mut i = at.index(joined.len() + 1);
                while !joined.is_char_boundary(i) {
                    i -= 1;
                }
                joined.insert(i, *c);
                lines = joined.lines().map(str::to_owned).collect();
            }
            _ => {}
        }
    }
    lines.join("\n")
}

fn one_line(e: &impl std::fmt::Display) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    prop_assert!(
        msg.contains(PATH) && !msg.contains('\n'),
        "error is not one line naming the file: {:?}",
        msg
    );
    Ok(())
}

/// Parse and validate every section; `Some(config)` if all of it is valid.
fn validate(text: &str) -> Result<Option<Config>, TestCaseError> {
    let config = match Config::parse(text, PATH) {
        Ok(c) => c,
        Err(e) => return one_line(&e).map(|()| None),
    };
    let mut valid = true;
    for verdict in [
        config.core_params(PATH).map(drop),
        config.sim_config(PATH).map(drop),
        config.sim_parts(PATH).map(drop),
        config.vision.validate().map_err(|m| upm_commands::config::ConfigError::invalid(PATH, m)),
        config.planner.build().map(drop).map_err(|m| upm_commands::config::ConfigError::invalid(PATH, m)),
    ] {
        if let Err(e) = verdict {
            one_line(&e)?;
            valid = false;
        }
    }
    Ok(valid.then_some(config))
}

proptest! {
    #![proptest_config(upm_tests::fuzz_config(20_000, 1))]

    #[test]
    fn mutated_configs_are_refused_with_a_one_line_error_or_accepted(
        which in 0usize..5,
        edits in prop::collection::vec(edit(), 1..4),
    ) {
        validate(&apply(&BASE_TEXTS[which], &edits))?;
    }
}

proptest! {
    // Starting a core costs milliseconds (solver workspace, simulator).
    #![proptest_config(upm_tests::fuzz_config(10_000, 50))]

    /// A config that passes validation starts a core that runs: the
    /// validation is complete, not just a parse.
    #[test]
    fn accepted_configs_start_and_run_a_core(
        which in 0usize..5,
        edits in prop::collection::vec(edit(), 1..3),
    ) {
        if let Some(config) = validate(&apply(&BASE_TEXTS[which], &edits))? {
            let params = config.core_params(PATH).expect("validated");
            let parts = config.sim_parts(PATH).expect("validated");
            let sim = Simulator::new(config.sim_config(PATH).expect("validated"), &parts.specs);
            prop_assert!(sim.is_ok(), "validated config, simulator refused: {:?}", sim.err());
            let core = Lockstep::new(&params, sim.expect("checked"), 1_000_000_000);
            prop_assert!(core.is_ok(), "validated config, core refused: {:?}", core.err());
            let mut core = core.expect("checked");
            core.run_ticks(params.motion.slot_ticks as u64 * 2, |_| {});
            let t = core.telemetry();
            prop_assert!([t.plate_x, t.plate_y, t.plate_theta].iter().all(|v| v.is_finite()));
        }
    }
}

#[test]
fn the_unmutated_configs_are_valid() {
    for text in BASE_TEXTS.iter() {
        assert!(matches!(validate(text), Ok(Some(_))), "a shipped config is invalid");
    }
}
