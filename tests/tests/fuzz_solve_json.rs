//! Fuzz: the `upm solve` JSON. Random text, byte-level mutations of the
//! paper's examples, and structural mutations (a value replaced by null, a
//! string, a huge literal, a nested array; a key removed or added). The
//! parse → solve → print path must give a one-line error naming the field
//! or a finite answer that prints as JSON, and never panic.

use proptest::prelude::*;
use upm_paper::solve_json::{InputError, parse, solve};

const EXAMPLES: [&str; 2] =
    [include_str!("../../examples/paper-3-1.json"), include_str!("../../examples/paper-3-3.json")];

/// What `upm solve` does with a text, minus the file reading.
fn solve_text(text: &str) -> Result<(), TestCaseError> {
    let outcome = parse(text).and_then(|input| solve(&input));
    match outcome {
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(!msg.is_empty() && !msg.contains('\n'), "error not one line: {:?}", msg);
            if let InputError::Json { path, .. } = &e {
                prop_assert!(!path.is_empty(), "error names no field: {}", msg);
            }
        }
        Ok(out) => {
            let json = serde_json::to_string(&out);
            prop_assert!(json.is_ok(), "answer does not print: {:?}", json);
            let numbers = out.k.iter().chain(&out.priority).chain(out.achieved.forces.iter().flatten());
            for v in numbers.chain(&out.achieved.curls).chain([&out.residual, &out.condition]) {
                prop_assert!(v.is_finite(), "non-finite number in the answer: {:?}", out);
            }
        }
    }
    Ok(())
}

/// Characters that make JSON interesting: structure, digits, exponents.
fn json_char() -> impl Strategy<Value = char> {
    prop_oneof![
        4 => prop::sample::select("{}[],:\"-+.eE0123456789 ".chars().collect::<Vec<_>>()),
        1 => any::<char>(),
    ]
}

/// A JSON value to put where a number was.
fn replacement() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("null".to_owned()),
        Just("1e999".to_owned()),
        Just("-1e999".to_owned()),
        Just("\"1.0\"".to_owned()),
        Just("true".to_owned()),
        Just("[]".to_owned()),
        Just("{}".to_owned()),
        Just("[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[0]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]".to_owned()),
        Just("18446744073709551616".to_owned()),
        Just("0".to_owned()),
        Just("-0.0".to_owned()),
        any::<f64>().prop_filter("finite", |v| v.is_finite()).prop_map(|v| format!("{v:e}")),
        (-5.0..5.0f64).prop_map(|v| v.to_string()),
    ]
}

/// Every place a value sits in a JSON tree, as a path of keys/indices.
fn value_paths(v: &serde_json::Value, at: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    out.push(at.clone());
    match v {
        serde_json::Value::Object(m) => {
            for (k, child) in m {
                at.push(k.clone());
                value_paths(child, at, out);
                at.pop();
            }
        }
        serde_json::Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                at.push(i.to_string());
                value_paths(child, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

fn pointer(path: &[String]) -> String {
    path.iter().map(|p| format!("/{p}")).collect()
}

proptest! {
    #![proptest_config(upm_tests::fuzz_config(20_000, 1))]

    #[test]
    fn random_text_never_panics(text in prop::collection::vec(json_char(), 0..200)) {
        solve_text(&text.into_iter().collect::<String>())?;
    }

    #[test]
    fn byte_mutated_examples_never_panic(
        which in 0usize..2,
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, json_char()), 1..6),
    ) {
        let mut text: Vec<char> = EXAMPLES[which].chars().collect();
        for (at, kind, c) in edits {
            let i = at.index(text.len().max(1)).min(text.len());
            match kind {
                0 if i < text.len() => text[i] = c,
                1 => text.insert(i, c),
                _ if i < text.len() => { text.remove(i); }
                _ => text.push(c),
            }
        }
        solve_text(&text.into_iter().collect::<String>())?;
    }

    #[test]
    fn structurally_mutated_examples_never_panic(
        which in 0usize..2,
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, replacement()), 1..4),
    ) {
        let mut doc: serde_json::Value = serde_json::from_str(EXAMPLES[which]).expect("example parses");
        for (at, kind, value) in edits {
            let mut paths = Vec::new();
            value_paths(&doc, &mut Vec::new(), &mut paths);
            let path = &paths[at.index(paths.len())];
            match kind {
                // Replace by a raw literal: spliced as text so 1e999 stays 1e999.
                0 => {
                    let marker = "\"__upm_fuzz_marker__\"";
                    if let Some(slot) = doc.pointer_mut(&pointer(path)) {
                        *slot = serde_json::Value::String("__upm_fuzz_marker__".into());
                    }
                    let text = serde_json::to_string(&doc).expect("prints").replacen(marker, &value, 1);
                    solve_text(&text)?;
                    continue;
                }
                1 => {
                    if let Some((last, parent)) = path.split_last()
                        && let Some(p) = doc.pointer_mut(&pointer(parent))
                    {
                        match p {
                            serde_json::Value::Object(m) => { m.remove(last); }
                            serde_json::Value::Array(a) => {
                                if let Ok(i) = last.parse::<usize>() && i < a.len() { a.remove(i); }
                            }
                            _ => {}
                        }
                    }
                }
                _ => {
                    if let Some(serde_json::Value::Object(m)) = doc.pointer_mut(&pointer(path)) {
                        m.insert("unknown_field".into(), serde_json::Value::Bool(true));
                    } else if let Some(serde_json::Value::Array(a)) = doc.pointer_mut(&pointer(path)) {
                        let copy = a.first().cloned().unwrap_or(serde_json::Value::Null);
                        a.push(copy);
                    }
                }
            }
            solve_text(&serde_json::to_string(&doc).expect("prints"))?;
        }
    }
}

/// The mutations must reach the solver, or the properties above would only
/// ever test the parser.
#[test]
fn examples_solve_cleanly() {
    for text in EXAMPLES {
        let input = parse(text).expect("example parses");
        assert!(solve(&input).is_ok());
    }
}
