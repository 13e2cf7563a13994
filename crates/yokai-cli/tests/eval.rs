//! `yokai eval` from the outside: determinism, outputs, clear errors.

mod common;
use common::yokai;

#[test]
fn same_policies_and_seed_give_the_same_tables() {
    let args = [
        "eval", "greedy", "belief", "random", "--games", "200", "--seed", "3",
    ];
    let a = yokai(&args);
    let b = yokai(&[&args[..], &["--threads", "1"]].concat());
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    assert_eq!(
        a.stdout, b.stdout,
        "results must not depend on the thread count"
    );
    let text = String::from_utf8(a.stdout).unwrap();
    assert!(text.contains("| greedy + belief |"));
    assert!(text.contains("| belief + random |"));
}

#[test]
fn outputs_land_in_the_directory() {
    let dir = std::env::temp_dir().join(format!("yokai-eval-{}", std::process::id()));
    let out = yokai(&[
        "eval",
        "greedy",
        "random",
        "--games",
        "100",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success());
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
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_policies_are_clear_errors() {
    let out = yokai(&["eval", "grandmaster"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown policy `grandmaster`"));
    let out = yokai(&["eval", "Cargo.toml"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("Cargo.toml is not a Yōkai checkpoint or policy file"),
        "{err}"
    );
}
