//! End to end: `codesign dynamics` on one sample of `tests/data/dynamics_vectors.json`
//! prints an object with exactly the sample's keys and values (to 1e-9 of each field's scale), and
//! refuses bad input with a message naming the flag.

use crate::support;

use serde_json::{Map, Value};
use std::process::Output;
use support::root;

fn codesign(args: &[String]) -> Output {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    support::codesign(&args)
}

fn list(value: &Value) -> String {
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap().to_string())
        .collect::<Vec<_>>()
        .join(",")
}

/// Every number of `value`, in order.
fn numbers(value: &Value, out: &mut Vec<f64>) {
    match value {
        Value::Array(items) => items.iter().for_each(|item| numbers(item, out)),
        other => out.push(other.as_f64().unwrap()),
    }
}

#[test]
fn prints_a_reference_sample() {
    let path = root().join("tests/data/dynamics_vectors.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let vectors: Value = serde_json::from_str(&text).unwrap();
    let case = &vectors["cases"][1];
    let sample: &Map<String, Value> = case["samples"][3].as_object().unwrap();
    let payload = case["payload_kg"].as_f64().unwrap();
    let mut args = vec![
        "dynamics".to_owned(),
        "--payload".to_owned(),
        payload.to_string(),
    ];
    for (flag, key) in [
        ("--q", "q"),
        ("--v", "v"),
        ("--a", "a"),
        ("--lambda", "lambda_"),
    ] {
        args.push(flag.to_owned());
        args.push(list(&sample[key]));
    }
    let output = codesign(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let printed: Map<String, Value> = serde_json::from_slice(&output.stdout).unwrap();
    let mut printed_keys: Vec<&String> = printed.keys().collect();
    let mut sample_keys: Vec<&String> = sample.keys().collect();
    printed_keys.sort();
    sample_keys.sort();
    assert_eq!(printed_keys, sample_keys);
    for (key, want) in sample {
        let (mut got_numbers, mut want_numbers) = (Vec::new(), Vec::new());
        numbers(&printed[key], &mut got_numbers);
        numbers(want, &mut want_numbers);
        assert_eq!(got_numbers.len(), want_numbers.len(), "{key}");
        let scale = want_numbers.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (g, w) in got_numbers.iter().zip(&want_numbers) {
            assert!(
                (g - w).abs() <= 1e-9 * w.abs().max(scale),
                "{key}: got {g:e}, reference {w:e}"
            );
        }
    }
}

#[test]
fn bad_input_is_refused_naming_the_flag() {
    let cases = [
        (vec!["--q", "0.1,0.2,0.3"], "--q has 3 values"),
        (vec!["--q", "0,0,0,0", "--v", "1,NaN,0,0"], "--v: value 2"),
        (vec!["--q", "0,0,0,0", "--payload", "-2"], "--payload"),
        (
            vec!["--q", "0,0,0,0", "--robot", "absent.urdf"],
            "absent.urdf",
        ),
        (
            vec!["--q", "0,0,0,0", "--task", "absent.json"],
            "absent.json",
        ),
        (vec!["--q", "0,zero,0,0"], "--q"),
        // Issue 38, item 16: terms that overflow printed as null with exit 0.
        (
            vec!["--q", "0,0,0,0", "--v", "1e308,0,0,0"],
            "is not finite at this state",
        ),
        (
            vec!["--q", "0,0,0,0", "--ends", "hold"],
            "--ends hold: dynamics",
        ),
    ];
    for (flags, expected) in cases {
        let mut args = vec!["dynamics".to_owned()];
        args.extend(flags.iter().map(|f| f.to_string()));
        let output = codesign(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{flags:?}");
        assert!(output.stdout.is_empty(), "{flags:?}");
        assert!(stderr.contains(expected), "{flags:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{flags:?}: {stderr}");
    }
}
