//! `yokai random` and `yokai show` from the outside: the README's reference table is made
//! with the first, and the second is how a person looks at a deal.

mod common;
use common::{yokai_err, yokai_ok};

fn random(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["random", "--json"];
    all.extend_from_slice(args);
    serde_json::from_slice(&yokai_ok(&all)).unwrap()
}

/// Random legal play scores what the independent reference implementation scores
/// (docs/spec/rules.md §4: R −4.01 in 9c-2p, −4.27 never choosing END), within 4 standard
/// errors over 20,000 games, whatever the thread count.
#[test]
fn random_play_reproduces_the_reference_figures_on_any_thread_count() {
    for (extra, reference) in [(None, -4.01), (Some("--never-end"), -4.27)] {
        let mut args = vec!["--games", "20000", "--seed", "0"];
        args.extend(extra);
        let got = random(&args);
        let (r, se) = (
            got["reward"].as_f64().unwrap(),
            got["reward_se"].as_f64().unwrap(),
        );
        assert_eq!(got["games"], 20000);
        assert!(se > 0.0 && se < 0.05, "{got}");
        assert!(
            (r - reference).abs() < 4.0 * se,
            "{extra:?}: R {r} ± {se}, reference {reference}"
        );
        if extra.is_some() {
            assert_eq!(got["early_end"], 0.0, "never END means no early end");
        }
        let one_thread = std::process::Command::new(env!("CARGO_BIN_EXE_yokai"))
            .args([&["random", "--json"], &args[..]].concat())
            .env("RAYON_NUM_THREADS", "1")
            .output()
            .unwrap();
        assert!(one_thread.status.success());
        let again: serde_json::Value = serde_json::from_slice(&one_thread.stdout).unwrap();
        assert_eq!(again, got, "results do not depend on the thread count");
    }
    let e = yokai_err(&["random", "--games", "0"]);
    assert!(e.contains("--games"), "{e}");
    let e = yokai_err(&["random", "--config", "7c-2p"]);
    assert!(e.contains("7c-2p"), "{e}");
}

/// `yokai show` prints the deal of a seed with every colour face up: the engine's own
/// rendering of that game, and another seed deals another board.
#[test]
fn show_prints_the_deal_of_its_seed() {
    let shown = String::from_utf8(yokai_ok(&[
        "show",
        "--config",
        "9c-2p-perfect",
        "--seed",
        "5",
    ]))
    .unwrap();
    let config = yokai_engine::Config::from_name("9c-2p-perfect").unwrap();
    let game = yokai_engine::Game::new(config, 5);
    assert_eq!(shown, yokai_engine::render_truth(&game));
    let other = String::from_utf8(yokai_ok(&["show", "--seed", "6"])).unwrap();
    assert_ne!(shown, other);
}
