//! `yokai eval` from the outside: determinism, outputs, clear errors.

mod common;
use common::{yokai, yokai_err, yokai_ok};

#[test]
fn same_policies_and_seed_give_the_same_tables() {
    let args = [
        "eval", "greedy", "belief", "random", "--games", "200", "--seed", "3",
    ];
    let a = yokai_ok(&args);
    let b = yokai(&[&args[..], &["--threads", "1"]].concat());
    assert_eq!(a, b.stdout, "results must not depend on the thread count");
    let text = String::from_utf8(a).unwrap();
    assert!(text.contains("| greedy + belief |"));
    assert!(text.contains("| belief + random |"));
}

#[test]
fn outputs_land_in_the_directory() {
    let tmp = tempfile::Builder::new()
        .prefix("yokai-eval-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    yokai_ok(&[
        "eval",
        "greedy",
        "random",
        "--games",
        "100",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let csv = std::fs::read_to_string(dir.join("matrix.csv")).unwrap();
    // Header plus three pairs: greedy+greedy, greedy+random, random+random.
    assert_eq!(csv.lines().count(), 4);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("matrix.json")).unwrap()).unwrap();
    assert_eq!(json.as_array().unwrap().len(), 3);
    assert_eq!(json[1]["metrics"]["games"], 100);
    assert!(std::fs::read_to_string(dir.join("report.md"))
        .unwrap()
        .starts_with("# Evaluation"));
}

#[test]
fn bad_policies_are_clear_errors() {
    assert!(yokai_err(&["eval", "grandmaster"]).contains("unknown policy `grandmaster`"));
    let err = yokai_err(&["eval", "Cargo.toml"]);
    assert!(
        err.contains("Cargo.toml is not a Yōkai checkpoint or policy file"),
        "{err}"
    );
}
