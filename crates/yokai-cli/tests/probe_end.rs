//! `yokai probe-end` from the outside: the same seed gives the same report, the JSON adds
//! up, and what it cannot study is refused with a reason.

mod common;
use common::{yokai_err, yokai_ok};

#[test]
fn a_pretrained_agents_end_chances_add_up_and_repeat() {
    let tmp = tempfile::Builder::new()
        .prefix("yokai-probe-end-")
        .tempdir()
        .unwrap();
    let dir = tmp.path().join("out");
    let args = [
        "probe-end",
        "pretrained:cpu-op/0",
        "--games",
        "64",
        "--seed",
        "5",
        "-o",
        dir.to_str().unwrap(),
    ];
    let a = yokai_ok(&args);
    assert_eq!(a, yokai_ok(&args), "one seed, one report");
    let text = String::from_utf8(a).unwrap();
    assert!(
        text.contains("| pretrained:cpu-op/0 (END > 0.6, T = 0.25) | 64 |"),
        "{text}"
    );
    assert!(text.contains("| 1: knows END wins |"), "{text}");
    assert_eq!(
        std::fs::read_to_string(dir.join("probe-end.md")).unwrap(),
        text
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("probe-end.json")).unwrap())
            .unwrap();
    let s = &json[0]["summary"];
    assert_eq!(s["games"], 64);
    assert_eq!(s["exact"], true);
    let rows = s["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 7);
    let chances: u64 = rows.iter().map(|r| r["chances"].as_u64().unwrap()).sum();
    assert_eq!(chances, s["chances"].as_u64().unwrap());
    // Every game has a first turn, where END is legal; a game has at most 8 turns.
    assert!((64..=8 * 64).contains(&chances), "{chances}");
    // This agent ENDs most of its games (93.5–94.7 % over 2,000).
    assert!(s["games_ended"].as_f64().unwrap() > 0.75, "{s}");
}

#[test]
fn bots_and_bad_input_are_refused_with_a_reason() {
    let err = yokai_err(&["probe-end", "greedy"]);
    assert!(err.contains("`greedy` is a built-in bot"), "{err}");
    let err = yokai_err(&["probe-end", "pretrained:cpu-op/0", "--games", "0"]);
    assert!(err.contains("--games must be at least 1"), "{err}");
    let err = yokai_err(&["probe-end", "pretrained:cpu-op/0", "--end", "2"]);
    assert!(err.contains("not an END rule"), "{err}");
}
