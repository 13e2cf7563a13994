//! `yokai bench` from the outside: one row per (config, games, encoding, dtype), the
//! paper's figure beside the configs it measured, clear errors for bad options.

mod common;
use common::{yokai, yokai_err, yokai_ok};

#[test]
fn json_rows_cover_every_combination() {
    let stdout = yokai_ok(&[
        "bench",
        "--configs",
        "9c-2p-perfect,16c-3p",
        "--envs",
        "2048,64",
        "--encodings",
        "image-chw,graph",
        "--dtypes",
        "u8,f32",
        "--seconds",
        "0.02",
        "--threads",
        "2",
        "--json",
    ]);
    let rows: Vec<serde_json::Value> = String::from_utf8(stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), 2 * 2 * 2 * 2);
    for row in &rows {
        assert!(row["steps_per_second"].as_f64().unwrap() > 0.0, "{row}");
        assert_eq!(row["threads"], 2);
        let paper = &row["paper_h100"];
        match (
            row["config"].as_str().unwrap(),
            row["envs"].as_u64().unwrap(),
        ) {
            ("9c-2p-perfect", 2048) => assert_eq!(paper.as_f64(), Some(559_251.0)),
            // The paper measured 9c and 16c with two players at 512-2048 games only.
            _ => assert!(paper.is_null(), "{row}"),
        }
    }
    assert!(rows
        .iter()
        .any(|r| r["encoding"] == "graph" && r["dtype"] == "f32"));
}

#[test]
fn repeats_report_the_median_of_their_samples() {
    let stdout = yokai_ok(&[
        "bench",
        "--configs",
        "9c-2p",
        "--envs",
        "16",
        "--encodings",
        "none",
        "--dtypes",
        "u8",
        "--seconds",
        "0.02",
        "--repeats",
        "3",
        "--json",
    ]);
    let row: serde_json::Value = serde_json::from_slice(&stdout).unwrap();
    let samples: Vec<f64> = row["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_f64().unwrap())
        .collect();
    assert_eq!(samples.len(), 3);
    assert!(samples.windows(2).all(|w| w[0] <= w[1]), "{samples:?}");
    assert_eq!(row["steps_per_second"].as_f64(), Some(samples[1]));
    assert!(yokai_err(&["bench", "--repeats", "0"]).contains("--repeats must be at least 1"));
}

#[test]
fn bad_options_are_errors_that_say_what() {
    assert!(
        yokai_err(&["bench", "--encodings", "pixels", "--seconds", "0.01"])
            .contains("unknown observation encoding `pixels`")
    );
    let err = yokai_err(&[
        "bench",
        "--dtypes",
        "f16",
        "--seconds",
        "0.01",
        "--envs",
        "8",
    ]);
    assert!(err.contains("unknown dtype `f16`"), "{err}");
    // Every row is checked before any is measured: nothing is printed for the good dtype.
    let out = yokai(&[
        "bench",
        "--dtypes",
        "f32,f16",
        "--seconds",
        "0.01",
        "--envs",
        "8",
        "--json",
    ]);
    assert!(!out.status.success());
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(yokai_err(&["bench", "--envs", "8,0", "--seconds", "0.01"])
        .contains("--envs: every number of games must be at least 1"));
}

/// `--envs` beyond what the machine can address is an error that names the size.
#[test]
fn an_impossible_number_of_envs_is_an_error_not_an_abort() {
    let err = yokai_err(&["bench", "--envs", "1099511627776", "--repeats", "1"]);
    assert!(err.contains("num_envs = 1099511627776 needs"), "{err}");
    assert!(err.contains("use fewer environments"), "{err}");
}
