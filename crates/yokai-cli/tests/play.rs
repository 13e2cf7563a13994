//! `yokai play`, `yokai replay` and `yokai train` from the outside.

mod common;
use common::{yokai, yokai_err, yokai_ok};

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn yokai_with_input(args: &[&str], input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    // The game may end before all input is read; a closed pipe is fine then.
    let _ = child.stdin.take().unwrap().write_all(input.as_bytes());
    child.wait_with_output().expect("finishes")
}

/// A fresh directory under the system's temporary folder, removed when the guard drops
/// (also when the test fails), so test runs leave nothing behind.
fn tempdir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("yokai-cli-{name}-"))
        .tempdir()
        .unwrap()
}

/// A tiny training config (compact network, 8 games × 8 steps, 2 updates) in `dir`, with
/// `extra` TOML appended; its path.
fn tiny_config(dir: &std::path::Path, extra: &str) -> std::path::PathBuf {
    let path = dir.join("tiny.toml");
    std::fs::write(
        &path,
        format!(
            "game = \"9c-2p-perfect\"\n[network]\npreset = \"compact\"\nhidden = 16\n\
             [ppo]\nnum_envs = 8\nrollout_steps = 8\nminibatches = 2\nepochs = 1\n\
             total_steps = 128\n{extra}"
        ),
    )
    .unwrap();
    path
}

/// `yokai train CONFIG --seeds SEEDS --threads 1 --out OUT` with `more` arguments.
fn train(config: &std::path::Path, seeds: &str, out: &std::path::Path, more: &[&str]) -> Output {
    let base = [
        "train",
        config.to_str().unwrap(),
        "--seeds",
        seeds,
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    yokai(&[&base[..], more].concat())
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn scripted_line_mode_game_finishes_and_saves_a_replay_that_renders() {
    let tmp = tempdir("play");
    let dir = tmp.path();
    let save = dir.join("game.jsonl");
    // Observe card by name first, then always the first listed action (a game of both
    // seats: the human's turns and the belief bot's in between), with one bad line.
    let input = format!("observe card 4\nfoo\n999\n{}", "0\n".repeat(400));
    let out = yokai_with_input(
        &[
            "play",
            "--line",
            "--seats",
            "human,belief",
            "--seed",
            "3",
            "--save",
            save.to_str().unwrap(),
        ],
        &input,
    );
    let all = text(&out);
    assert!(out.status.success(), "{all}");
    assert!(all.contains("seat 0 (human): observe card 4"), "{all}");
    assert!(all.contains("not one of the listed numbers"), "{all}");
    assert!(
        all.contains("type a listed number or an action's name"),
        "{all}"
    );
    assert!(all.contains("game over after"), "{all}");
    assert!(all.contains("seat 1 (belief):"), "the bot played: {all}");

    // The replay renders one SVG per state, each with all 9 cards of the true board, and
    // with --png the same pictures as PNG.
    let svg_dir = dir.join("svg");
    let png_dir = dir.join("png");
    let out = yokai(&[
        "replay",
        save.to_str().unwrap(),
        "--svg",
        svg_dir.to_str().unwrap(),
        "--png",
        png_dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out));
    let steps = std::fs::read_to_string(&save)
        .unwrap()
        .lines()
        .filter(|l| l.contains("\"type\":\"step\""))
        .count();
    let mut files: Vec<_> = std::fs::read_dir(&svg_dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), steps + 1);
    for f in &files {
        let svg = std::fs::read_to_string(f).unwrap();
        assert_eq!(
            svg.matches("class=\"card truth\"").count(),
            9,
            "{}",
            f.display()
        );
        // Its PNG twin: the SVG's declared size, and a picture, not a blank page.
        let png = png_dir.join(f.with_extension("png").file_name().unwrap());
        let image = resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&png).unwrap()).unwrap();
        let declared = |attr: &str| -> u32 {
            let at = svg.find(&format!(" {attr}=\"")).unwrap() + attr.len() + 3;
            svg[at..].split('"').next().unwrap().parse().unwrap()
        };
        assert_eq!(
            (image.width(), image.height()),
            (declared("width"), declared("height")),
            "{}",
            png.display()
        );
        let distinct: std::collections::BTreeSet<_> = image
            .pixels()
            .iter()
            .map(|p| (p.red(), p.green(), p.blue()))
            .collect();
        assert!(
            distinct.len() >= 4,
            "{}: {} colours",
            png.display(),
            distinct.len()
        );
    }
    assert_eq!(std::fs::read_dir(&png_dir).unwrap().count(), steps + 1);
    // The whole game on one sheet: a column per turn, each with the 9 cards twice (truth
    // and view), the outcome in its title; as SVG and as PNG.
    let sheet = dir.join("sheet.svg");
    let out = yokai(&[
        "replay",
        save.to_str().unwrap(),
        "--sheet",
        sheet.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out));
    let svg = std::fs::read_to_string(&sheet).unwrap();
    let turns = svg.matches("<g class=\"turn\"").count();
    assert!(
        turns >= 2 && turns <= steps,
        "{turns} turns for {steps} steps"
    );
    assert_eq!(svg.matches("class=\"card truth\"").count(), 9 * turns);
    assert_eq!(svg.matches("class=\"card view\"").count(), 9 * turns);
    assert!(
        svg.contains(&format!("in {steps} steps")),
        "the title says the outcome"
    );
    let png = dir.join("sheet.png");
    let out = yokai(&[
        "replay",
        save.to_str().unwrap(),
        "--sheet",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&png).unwrap()).is_ok());
    // Text mode prints every state.
    let out =
        String::from_utf8(yokai_ok(&["replay", save.to_str().unwrap(), "--seat", "1"])).unwrap();
    assert_eq!(out.matches("── 9c-2p-perfect").count(), steps + 1);
}

#[test]
fn input_that_ends_too_early_and_bad_seats_are_clear_errors() {
    let out = yokai_with_input(&["play", "--line", "--seats", "human,random"], "1\n");
    assert!(!out.status.success());
    assert!(text(&out).contains("input ended before the game finished"));
    let err = yokai_err(&["play", "--line", "--seats", "human,wizard"]);
    assert!(err.contains("unknown policy `wizard`"), "{err}");
    let err = yokai_err(&["play", "--line", "--seats", "human,human,human"]);
    assert!(err.contains("3 seats given"), "{err}");
}

/// A pretrained agent built into the binary takes a seat of `yokai play` by name.
#[test]
fn a_pretrained_agent_plays_beside_a_human_in_line_mode() {
    // Listed actions 1 and 0 in turn (0 is END at the start of a turn, and some substeps
    // list one action only): the human's turn completes, then the agent plays.
    let input = "1\n0\n".repeat(200);
    let out = yokai_with_input(
        &[
            "play",
            "--line",
            "--seats",
            "human,pretrained:quick/0",
            "--seed",
            "5",
        ],
        &input,
    );
    let all = text(&out);
    assert!(out.status.success(), "{all}");
    assert!(
        all.contains("seat 1 (pretrained:quick/0 (END > 0.6, T = 0.25)): observe card"),
        "the agent played: {all}"
    );
    assert!(all.contains("game over after"), "{all}");
}

#[test]
fn a_broken_replay_names_the_file_and_line() {
    let tmp = tempdir("broken");
    let dir = tmp.path();
    let path = dir.join("bad.jsonl");
    std::fs::write(&path, "{\"type\":\"step\"}\n").unwrap();
    let err = yokai_err(&["replay", path.to_str().unwrap()]);
    assert!(err.contains("bad.jsonl") && err.contains("line 1"), "{err}");
}

#[test]
fn train_then_eval_a_run_directory() {
    let tmp = tempdir("train");
    let dir = tmp.path();
    let config = tiny_config(dir, "");
    let out_dir = dir.join("runs");
    // Seeds 0 and 1 of the tiny config into `out`, with more options.
    let train_two = |out: &std::path::Path, more: &[&str]| {
        let base = [
            "train",
            config.to_str().unwrap(),
            "--seeds",
            "0..2",
            "--out",
            out.to_str().unwrap(),
        ];
        yokai(&[&base[..], more].concat())
    };
    let out = train_two(&out_dir, &["--eval-games", "40", "--threads", "1"]);
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    assert!(t.contains("## Paper table"), "{t}");
    assert!(
        t.contains(&format!("| {} | 2 |", out_dir.display())),
        "one row for the method, two seeds: {t}"
    );
    assert!(
        t.contains(
            "| paper: OP | 12 | 6.6 ± 0.2 | 84 ± 2 | 90 ± 2 | 93 ± 1 | 25.2 ± 0.2 | 4.8 ± 0.1 |"
        ),
        "paper reference rows: {t}"
    );
    assert!(out_dir.join("seed-1/policy.ykp").exists());
    // Two seeds side by side, one thread each, train exactly what one after the other does.
    let side_by_side = dir.join("jobs");
    let out = train_two(
        &side_by_side,
        &["--eval-games", "0", "--threads", "2", "--jobs", "2"],
    );
    assert!(out.status.success(), "{}", text(&out));
    assert!(
        text(&out).contains("2 at a time on 1 thread(s) each"),
        "{}",
        text(&out)
    );
    for seed in 0..2 {
        let path = format!("seed-{seed}");
        let (alone, beside) = (
            yokai_train::TrainedPolicy::load(&out_dir.join(&path)).unwrap(),
            yokai_train::TrainedPolicy::load(&side_by_side.join(&path)).unwrap(),
        );
        assert_eq!(alone.parameters(), beside.parameters(), "seed {seed}");
    }
    let eval = out_dir.join("eval");
    let report = std::fs::read_to_string(eval.join("report.md")).unwrap();
    assert!(
        report.contains("![cross-play heatmap](xp_heatmap.png)"),
        "{report}"
    );
    // The heatmap shows the evaluation's numbers: one cell per ordered pair of the 3
    // policies (2 seeds + random), each holding the R that matrix.json gives that pair
    // (either order: R is symmetric in the seating).
    let svg = std::fs::read_to_string(eval.join("xp_heatmap.svg")).unwrap();
    let matrix: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(eval.join("matrix.json")).unwrap()).unwrap();
    let names: Vec<&str> = {
        let mut v: Vec<&str> = Vec::new();
        for pair in matrix.as_array().unwrap() {
            for side in ["row", "col"] {
                let name = pair[side].as_str().unwrap();
                if !v.contains(&name) {
                    v.push(name);
                }
            }
        }
        v
    };
    assert_eq!(names.len(), 3, "{names:?}");
    let mut cells = 0;
    for pair in matrix.as_array().unwrap() {
        let at = |side: &str| names.iter().position(|&n| n == pair[side]).unwrap();
        let (i, j) = (at("row"), at("col"));
        let value = format!("{:.3}", pair["metrics"]["reward"].as_f64().unwrap());
        for (r, c) in [(i, j), (j, i)] {
            let cell = format!("data-row=\"{r}\" data-col=\"{c}\" data-value=\"{value}\"");
            assert!(svg.contains(&cell), "{cell} not in the heatmap");
            cells += 1;
        }
    }
    assert!(cells >= 9, "{cells} cells checked");
    assert_eq!(svg.matches("class=\"cell\"").count(), 9);
    // The PNG is that picture: the SVG's size, and not blank (white, cells, text).
    let png = std::fs::read(eval.join("xp_heatmap.png")).unwrap();
    let image = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
    let declared = |attr: &str| -> u32 {
        let at = svg.find(&format!("{attr}=\"")).unwrap() + attr.len() + 2;
        svg[at..].split('"').next().unwrap().parse().unwrap()
    };
    assert_eq!(
        (image.width(), image.height()),
        (declared("width"), declared("height"))
    );
    let colours: std::collections::BTreeSet<[u8; 4]> = image
        .pixels()
        .iter()
        .map(|p| [p.red(), p.green(), p.blue(), p.alpha()])
        .collect();
    assert!(colours.len() >= 4, "{} colours in the PNG", colours.len());
    let curves = std::fs::read_to_string(eval.join("learning_return.svg")).unwrap();
    assert_eq!(
        curves.matches("class=\"series\"").count(),
        2,
        "one line per seed"
    );
    assert!(eval.join("learning_see.png").exists());

    // compare reads the summary; a quoted glob and a method directory both expand to seeds.
    let out = yokai(&["compare", eval.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains(&format!("| {} | 2 |", out_dir.display())));
    // Beside another of the paper's tables; a table it does not have is refused.
    let e = eval.to_str().unwrap();
    let out = yokai(&["compare", e, "--paper-table", "4"]);
    let t = text(&out);
    assert!(t.starts_with("Beside the paper's Table 4: "), "{t}");
    assert!(
        t.contains("| paper: OP Φ_col (colours) | 12 | 7.6 ± 0.1 |") && !t.contains("paper: IPPO"),
        "{t}"
    );
    let out = yokai(&["compare", e, "--paper-table", "7"]);
    assert!(
        !out.status.success() && text(&out).contains("7 is not in 2..=6"),
        "{}",
        text(&out)
    );
    let glob = format!("{}/seed-*", out_dir.display());
    for arg in [glob.as_str(), out_dir.to_str().unwrap()] {
        let out = yokai(&["eval", arg, "--games", "10"]);
        let t = text(&out);
        assert!(out.status.success(), "{t}");
        assert!(
            t.contains("seed-0 + ") && t.contains("seed-1 |"),
            "{arg}: {t}"
        );
    }
    // A character class picks seeds; a broken pattern is an error that names it.
    let out = yokai(&[
        "eval",
        &format!("{}/seed-[1]", out_dir.display()),
        "--games",
        "4",
    ]);
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    assert!(t.contains("seed-1") && !t.contains("seed-0"), "{t}");
    let out = yokai(&["eval", &format!("{}/seed-[", out_dir.display())]);
    let t = text(&out);
    assert!(
        !out.status.success() && t.contains("is not a valid pattern"),
        "{t}"
    );
    let replays = eval.join("replays");
    assert!(
        std::fs::read_dir(&replays).unwrap().count() >= 2,
        "self-play replays saved"
    );

    // A trained policy carries its game: another config is refused, clearly.
    let run = out_dir.join("seed-0");
    let out = yokai(&["eval", run.to_str().unwrap(), "--config", "9c-3p-perfect"]);
    let t = text(&out);
    assert!(!out.status.success());
    assert!(
        t.contains("was trained on 9c-2p-perfect, not on 9c-3p-perfect"),
        "{t}"
    );
    // And a run directory plays against the built-in bots, with the same table every time.
    let args = ["eval", run.to_str().unwrap(), "random", "--games", "20"];
    let (a, b) = (yokai(&args), yokai(&args));
    assert!(a.status.success(), "{}", text(&a));
    assert_eq!(a.stdout, b.stdout, "same policies and seed, same table");
    // --end decides END: at a threshold of 0.99 the barely trained network never ends a
    // game early (its P(END) is a few per cent), drawing it ends some; the tables name
    // the rule, and a rule that is not one is refused.
    let early_ends = |rule: &str| {
        let out = yokai(&[
            "eval",
            run.to_str().unwrap(),
            "--games",
            "100",
            "--end",
            rule,
        ]);
        let t = text(&out);
        assert!(out.status.success(), "{t}");
        // The self-play row: | name | R | win % | SEE % | EE % | WEE % | LEN |.
        let row = t
            .lines()
            .find(|l| l.contains("seed-0") && !l.contains(" + "))
            .unwrap()
            .to_string();
        let ee: f64 = row.split('|').nth(5).unwrap().trim().parse().unwrap();
        (row, ee)
    };
    let (decided, ee) = early_ends("0.99");
    assert!(
        decided.contains("seed-0 (END > 0.99)") && ee == 0.0,
        "{decided}"
    );
    let (drawn, ee) = early_ends("draw");
    assert!(!drawn.contains("END >") && ee > 0.0, "{drawn}");
    let t = text(&yokai(&["eval", run.to_str().unwrap(), "--end", "1.5"]));
    assert!(t.contains("`1.5` is not an END rule"), "{t}");
    // --temperature 0 plays the most likely move, and the tables name it; a temperature
    // below 0 is refused, naming the field.
    let out = yokai(&[
        "eval",
        run.to_str().unwrap(),
        "--games",
        "20",
        "--temperature",
        "0",
    ]);
    let t = text(&out);
    assert!(out.status.success() && t.contains("seed-0 (T = 0)"), "{t}");
    let t = text(&yokai(&["eval", run.to_str().unwrap(), "--temperature=-1"]));
    assert!(t.contains("act.temperature must lie in [0, 100]"), "{t}");
    // Starting the same run again is refused; --resume with nothing left to do is fine.
    let args = [
        "train",
        config.to_str().unwrap(),
        "--seeds",
        "0",
        "--out",
        out_dir.to_str().unwrap(),
        "--eval-games",
        "0",
    ];
    let out = yokai(&args);
    assert!(text(&out).contains("already holds a run"), "{}", text(&out));
    let out = yokai(&[&args[..], &["--resume"]].concat());
    assert!(out.status.success(), "{}", text(&out));

    // --init-from a directory of seeds: seed N of the new runs starts from its seed-N.
    let tuned = dir.join("tuned");
    let from = [
        "--eval-games",
        "0",
        "--init-from",
        out_dir.to_str().unwrap(),
    ];
    let out = train_two(&tuned, &from);
    assert!(out.status.success(), "{}", text(&out));
    for seed in 0..2 {
        let saved =
            std::fs::read_to_string(tuned.join(format!("seed-{seed}/config.toml"))).unwrap();
        let from = out_dir.join(format!("seed-{seed}"));
        assert!(
            saved.contains(&format!("init_from = \"{}\"", from.display())),
            "{saved}"
        );
    }
    let out = train_two(&tuned, &[&from[..], &["--resume"]].concat());
    assert!(text(&out).contains("cannot be used with"), "{}", text(&out));
}

#[test]
fn train_device_errors_name_the_device_and_leave_no_run() {
    let tmp = tempdir("train-device");
    let dir = tmp.path();
    let out = dir.join("runs");
    let e = yokai_err(&[
        "train",
        "quick",
        "--device",
        "tpu",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains("unknown device `tpu`") && e.contains("cpu, vulkan or cuda"),
        "{e}"
    );
    // This test binary is built without GPU features: asking for one says how to build it
    // (with a GPU feature but no GPU, the error says what the runtime lacks instead).
    if !cfg!(feature = "vulkan") {
        let e = yokai_err(&[
            "train",
            "quick",
            "--device",
            "vulkan",
            "--seeds",
            "0",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(e.contains("--features vulkan"), "{e}");
    }
    if !cfg!(feature = "cuda") {
        let e = yokai_err(&["train", "quick", "--device", "cuda", "--seeds", "0"]);
        assert!(e.contains("not built into this binary"), "{e}");
    }
    assert!(!out.join("seed-0").join("checkpoint.ykc").exists());
}

#[test]
fn playthrough_prints_the_engines_golden_game() {
    let golden = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../yokai-engine/tests/playthroughs/16c-3p-imperfect-seed2-never-end.txt");
    let out = yokai_ok(&[
        "playthrough",
        "16c-3p-imperfect",
        "--seed",
        "2",
        "--never-end",
    ]);
    assert_eq!(
        String::from_utf8(out).unwrap(),
        std::fs::read_to_string(golden).unwrap()
    );
    let err = yokai_err(&["playthrough", "7c-2p"]);
    assert!(err.contains("7c-2p"), "{err}");
}

#[test]
fn soak_plays_every_preset_and_replays_a_sample_against_the_reference() {
    let out = yokai_ok(&["soak", "--steps", "24000", "--envs", "16", "--sample", "5"]);
    let text = String::from_utf8(out).unwrap();
    assert_eq!(text.matches("no violation").count(), 12, "{text}");
    assert!(text.contains("all 12 configs: 24000 steps"), "{text}");
    let replayed: u64 = text
        .lines()
        .last()
        .and_then(|l| l.split(", ").nth(2))
        .and_then(|p| p.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!(replayed >= 12 * 10, "{text}");
    let err = yokai_err(&["soak", "--steps", "lots"]);
    assert!(err.contains("lots"), "{err}");
}

/// `yokai train --levels 1..3` trains OBL level 1, then level 2 on it (its belief trained on
/// level 1's self-play, reported in its metrics), each level a set of run directories that
/// `yokai eval` reads; a non-OBL config or level 0 is refused with the reason.
#[test]
fn train_obl_levels_in_sequence() {
    let tmp = tempdir("levels");
    let dir = tmp.path();
    let config = tiny_config(
        dir,
        "[obl]\nlevel = 1\nbelief_updates = 2\nbelief_hidden = 8\n",
    );
    let out = dir.join("runs");
    let o = train(
        &config,
        "0",
        &out,
        &["--levels", "1..3", "--eval-games", "20"],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("nats per unseen card (first-hand baseline"),
        "level 2's summary shows its belief: {}",
        text(&o)
    );
    for level in [1, 2] {
        let run = out.join(format!("level-{level}/seed-0"));
        assert!(run.join("policy.ykp").exists(), "level {level}");
        let saved = std::fs::read_to_string(run.join("config.toml")).unwrap();
        assert!(saved.contains(&format!("level = {level}")), "{saved}");
        let metrics = std::fs::read_to_string(run.join("metrics.jsonl")).unwrap();
        assert_eq!(
            metrics.contains("obl_belief_cross_entropy"),
            level == 2,
            "level {level}: the belief's figures are logged from level 2 on"
        );
        assert!(out.join(format!("level-{level}/eval/report.md")).exists());
        // The belief model's curve is drawn for level 2 (one line per seed), not level 1.
        let belief = out.join(format!("level-{level}/eval/learning_belief.svg"));
        assert_eq!(belief.exists(), level == 2, "level {level}");
        if level == 2 {
            let curve = std::fs::read_to_string(&belief).unwrap();
            assert_eq!(curve.matches("class=\"series\"").count(), 1, "{curve}");
            let report = std::fs::read_to_string(out.join("level-2/eval/report.md")).unwrap();
            assert!(report.contains("(learning_belief.png)"), "{report}");
        }
    }
    let level_two = std::fs::read_to_string(out.join("level-2/seed-0/config.toml")).unwrap();
    assert!(
        level_two.contains("level-1"),
        "level 2 names level 1: {level_two}"
    );
    assert!(
        level_two.contains("init_from") && level_two.contains("level-1/seed-0"),
        "level 2 starts from level 1's seed 0: {level_two}"
    );
    let e = yokai_err(&[
        "train",
        "quick",
        "--levels",
        "1..2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains("--levels with") && e.contains("obl.level is 0"),
        "{e}"
    );
    let e = yokai_err(&["train", config.to_str().unwrap(), "--levels", "0..2"]);
    assert!(e.contains("levels count from 1"), "{e}");
}

/// `yokai probe` on trained runs writes per-step accuracies (self-play on held-out
/// episodes, and with a partner) beside the oracle, as CSV, JSON and a plot; a missing run
/// is an error that names it.
#[test]
fn probe_trained_runs() {
    let tmp = tempdir("probe");
    let dir = tmp.path();
    let config = tiny_config(dir, "");
    let runs = dir.join("runs");
    let o = train(&config, "0..2", &runs, &["--eval-games", "0"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = dir.join("probe");
    let (a, b) = (runs.join("seed-0"), runs.join("seed-1"));
    let o = yokai(&[
        "probe",
        a.to_str().unwrap(),
        "--partners",
        b.to_str().unwrap(),
        "--games",
        "100",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("| self-play |"), "{}", text(&o));
    let csv = std::fs::read_to_string(out.join("probe.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("run,setting,step,cards,accuracy,oracle,rows,head")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().any(|r| r[1] == "self-play" && r[3] == "unseen"));
    assert!(rows
        .iter()
        .any(|r| r[1].starts_with("with ") && r[3] == "all"));
    for r in &rows {
        let (acc, oracle): (f64, f64) = (r[4].parse().unwrap(), r[5].parse().unwrap());
        let rows: f64 = r[6].parse().unwrap();
        assert!(rows > 0.0, "{r:?}");
        assert_eq!(
            r[7], "",
            "a network without a colour layer guesses nothing: {r:?}"
        );
        if r[2] == "0" && r[3] == "all" {
            // Nothing is seen at the first state: the oracle names one colour for all, which
            // is right for exactly a third of a game's cards, and the memory knows no more,
            // so the probe's held-out accuracy is chance up to sampling noise (5 SD of
            // 9 · rows guesses at 1/3).
            assert!((oracle - 1.0 / 3.0).abs() < 1e-3, "{r:?}");
            let sd = (2.0 / 9.0 / (9.0 * rows)).sqrt();
            assert!((acc - 1.0 / 3.0).abs() < 5.0 * sd, "{r:?}: sd {sd}");
        }
    }
    for file in ["probe.json", "probe.svg", "probe.png"] {
        assert!(out.join(file).exists(), "{file}");
    }
    let e = yokai_err(&["probe", dir.join("nothing").to_str().unwrap()]);
    assert!(e.contains("nothing"), "{e}");
    let e = yokai_err(&["probe", a.to_str().unwrap(), "--games", "10"]);
    assert!(
        e.contains("--games: 10 self-play games per run are too few"),
        "{e}"
    );
    assert!(text(&o).contains("chance 33.3 %"), "{}", text(&o));
    // A 4-colour game: chance is a quarter; it cannot be probed beside a 9c run.
    let sixteen = dir.join("sixteen.toml");
    let toml = std::fs::read_to_string(&config).unwrap();
    std::fs::write(&sixteen, toml.replace("9c-2p-perfect", "16c-2p-perfect")).unwrap();
    let runs16 = dir.join("runs16");
    let o = train(&sixteen, "0", &runs16, &["--eval-games", "0"]);
    assert!(o.status.success(), "{}", text(&o));
    let c = runs16.join("seed-0");
    let o = yokai(&[
        "probe",
        c.to_str().unwrap(),
        "--games",
        "50",
        "--out",
        dir.join("probe16").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("chance 25.0 %"), "{}", text(&o));
    let e = yokai_err(&[
        "probe",
        a.to_str().unwrap(),
        "--partners",
        c.to_str().unwrap(),
    ]);
    assert!(e.contains("16c"), "{e}");
}
