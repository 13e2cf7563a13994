//! `yokai serve` over HTTP: scripted players play whole games, every request is checked
//! against the rules, records are valid replays of the games shown, games survive a
//! restart of the server, and hot seat hides the board. The load, crash and fuzz tests are
//! in `serve_load.rs` and `serve_fuzz.rs`.

#[path = "common/server.rs"]
mod server;

use serde_json::{json, Value};
use server::{first_not_end, id, play_out, report, tempdir, Server};
use std::process::Command;
use yokai_engine::Replay;

#[test]
fn a_scripted_player_plays_a_whole_game_and_its_record_is_the_game_shown() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,belief", &[]);
    // The page itself, built into the binary.
    let page = ureq::get(&format!("{}/", server.base)).call().unwrap();
    assert_eq!(page.status(), 200);
    assert!(page.into_string().unwrap().contains("<title>Yōkai</title>"));
    let player = server.session();
    let game = server.new_game(&player, json!({ "seed": 11 }));
    assert_eq!(game["seats"], json!(["human", "belief"]));
    // Only seat 0's own knowledge is sent: no colour before it observes anything.
    assert!(game["board"]["cards"]
        .as_array()
        .unwrap()
        .iter()
        .all(|c| c["colour"].is_null()));
    let end = play_out(&server, game, 1);
    let steps = end["board"]["step"].as_u64().unwrap() as usize;
    assert_eq!(
        end["log"].as_array().unwrap().len(),
        steps,
        "one log line per step"
    );
    // The record on disk and the replay the server serves are the game shown.
    let path = tmp.path().join(&player).join(format!("{}.jsonl", id(&end)));
    let record = Replay::from_jsonl(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let served = ureq::get(&format!(
        "{}/api/games/{}/replay?session={player}",
        server.base,
        id(&end)
    ))
    .call()
    .unwrap()
    .into_string()
    .unwrap();
    assert_eq!(Replay::from_jsonl(&served).unwrap(), record);
    assert_eq!(record.header.seats, vec!["human", "belief"]);
    assert_eq!(record.steps.len(), steps);
    let outcome = serde_json::to_value(record.outcome.unwrap()).unwrap();
    assert_eq!(outcome, end["board"]["outcome"]);
    for (line, step) in end["log"].as_array().unwrap().iter().zip(&record.steps) {
        assert!(
            line.as_str().unwrap().ends_with(&step.name),
            "{line} / {}",
            step.name
        );
    }
    // At the end every colour is shown.
    assert!(end["board"]["cards"]
        .as_array()
        .unwrap()
        .iter()
        .all(|c| c["colour"].is_string()));
    // The replay viewer gets a board per step plus the deal.
    let (status, frames) = server.post("/api/replay", &served);
    assert_eq!(status, 200);
    assert_eq!(frames["frames"].as_array().unwrap().len(), steps + 1);
    // The session's summary counts the game in the paper's metrics.
    let (_, summary) = server.get(&format!("/api/summary?session={player}"));
    assert_eq!(summary["finished"], 1);
    assert_eq!(
        summary["metrics"]["reward"],
        outcome["reward"].as_f64().unwrap()
    );
}

#[test]
fn every_bad_request_is_refused_clearly_and_changes_nothing() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,random", &[]);
    let s1 = server.session();
    let game = server.new_game(&s1, json!({ "seed": 2 }));
    let g = id(&game).to_string();
    let step = game["board"]["step"].clone();
    let legal: Vec<u64> = game["board"]["legal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["index"].as_u64().unwrap())
        .collect();
    let illegal = (0..777).find(|i| !legal.contains(i)).unwrap();
    let other = server.session();
    let cases = [
        (
            json!({"session": s1, "seat": 0, "action": illegal}).to_string(),
            400,
            "is not legal now",
        ),
        (
            json!({"session": s1, "seat": 1, "action": legal[0]}).to_string(),
            400,
            "turn",
        ),
        (
            json!({"session": s1, "seat": 0, "action": 100000}).to_string(),
            400,
            "out of range",
        ),
        (
            json!({"session": s1, "seat": 0}).to_string(),
            400,
            "missing field `action`",
        ),
        (
            json!({"session": s1, "seat": 0, "action": -1}).to_string(),
            400,
            "not valid",
        ),
        ("{not json".to_string(), 400, "not valid"),
        // Another session's game is not found; an id the server never issued is refused.
        (
            json!({"session": other, "seat": 0, "action": legal[0]}).to_string(),
            404,
            "no such game",
        ),
        (
            json!({"session": "s1", "seat": 0, "action": legal[0]}).to_string(),
            403,
            "unknown session",
        ),
        (
            json!({"session": "../x", "seat": 0, "action": legal[0]}).to_string(),
            403,
            "unknown session",
        ),
    ];
    for (body, code, message) in cases {
        let (status, answer) = server.post(&format!("/api/games/{g}/actions"), &body);
        assert_eq!(status, code, "{body}: {answer}");
        let text = answer["error"].as_str().unwrap_or_default();
        assert!(text.contains(message), "{body}: {text}");
        let (_, now) = server.get(&format!("/api/games/{g}?session={s1}"));
        assert_eq!(now["board"]["step"], step, "{body} changed the game");
    }
    let (status, answer) = server.get(&format!("/api/games/0123?session={s1}"));
    assert_eq!((status, answer["error"].is_string()), (404, true));
    let (status, answer) = server.post(
        "/api/games",
        &json!({"session": s1, "seats": ["human", "nobody"]}).to_string(),
    );
    assert_eq!(status, 400);
    let text = answer["error"].as_str().unwrap();
    assert!(
        text.contains("\"nobody\" is not offered")
            && text.contains("human, belief, greedy, random"),
        "{answer}"
    );
    let (status, answer) = server.post("/api/replay", "not a replay");
    assert_eq!(status, 400, "{answer}");
}

/// The two requests that once read the server's files: a path as the game, a path as a
/// seat. Both are refused by naming what is offered, and nothing of the file comes back.
#[test]
fn a_path_from_the_page_is_refused_and_nothing_of_the_file_is_sent() {
    let tmp = tempdir();
    let secret = tmp.path().join("secrets.toml");
    std::fs::write(&secret, "token = \"hunter2-s3cr3t\"\nuser = \"operator\"\n").unwrap();
    let server = Server::start(&tmp.path().join("records"), "human,belief", &[]);
    let session = server.session();
    let secret = secret.display().to_string();
    for body in [
        json!({"session": session, "config": secret}),
        json!({"session": session, "config": "/etc/passwd"}),
        json!({"session": session, "seats": ["human", secret]}),
        json!({"session": session, "seats": ["human", "/etc/passwd"]}),
    ] {
        let (status, answer) = server.post("/api/games", &body.to_string());
        assert_eq!(status, 400, "{body}: {answer}");
        let text = answer["error"].as_str().unwrap();
        assert!(
            text.contains("is not offered by this server; it offers:"),
            "{text}"
        );
        for leak in ["hunter2", "operator", "root:", "TOML", "checkpoint"] {
            assert!(!text.contains(leak), "{body}: {text}");
        }
    }
}

#[test]
fn a_game_continues_after_the_server_restarts() {
    let tmp = tempdir();
    let (s2, g, log) = {
        let server = Server::start(tmp.path(), "human,greedy", &[]);
        let s2 = server.session();
        let mut game = server.new_game(&s2, json!({ "seed": 5 }));
        for _ in 0..6 {
            game = server.act(&game, first_not_end(&game)).1;
        }
        (s2, id(&game).to_string(), game["log"].clone())
    };
    let server = Server::start(tmp.path(), "human,greedy", &[]);
    let (status, game) = server.get(&format!("/api/games/{g}?session={s2}"));
    assert_eq!(status, 200, "{game}");
    assert_eq!(game["log"], log);
    let end = play_out(&server, game, 0);
    let record = std::fs::read_to_string(tmp.path().join(&s2).join(format!("{g}.jsonl"))).unwrap();
    let replay = Replay::from_jsonl(&record).unwrap();
    assert!(replay.outcome.is_some());
    assert_eq!(
        replay.steps.len() as u64,
        end["board"]["step"].as_u64().unwrap()
    );
}

#[test]
fn hot_seat_hides_the_board_until_the_next_player_reveals_it() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,human", &[]);
    let s3 = server.session();
    let mut game = server.new_game(&s3, json!({ "seed": 8 }));
    // Seat 0 plays its turn (4 substeps); then seat 1 is to act behind the curtain.
    while game["to_act"] == 0 {
        game = server.act(&game, first_not_end(&game)).1;
    }
    assert_eq!(game["to_act"], 1);
    assert_eq!(game["curtain"], true);
    assert!(game["board"].is_null(), "no board behind the curtain");
    let (_, shown) = server.post(
        &format!("/api/games/{}/reveal", id(&game)),
        &json!({ "session": s3 }).to_string(),
    );
    assert_eq!(shown["curtain"], false);
    assert_eq!(shown["board"]["viewer"], 1);
}

/// `--policies DIR` offers every trained policy under DIR by its path inside it; the page
/// seats one by that name and plays a whole game against it.
#[test]
fn policies_under_a_folder_are_offered_by_name_and_play() {
    let tmp = tempdir();
    let config = tmp.path().join("tiny.toml");
    std::fs::write(
        &config,
        "game = \"9c-2p-perfect\"\n[network]\npreset = \"compact\"\nhidden = 16\n\
         [ppo]\nnum_envs = 8\nrollout_steps = 8\nminibatches = 2\nepochs = 1\ntotal_steps = 128\n",
    )
    .unwrap();
    let agents = tmp.path().join("agents");
    let trained = Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args([
            "train",
            config.to_str().unwrap(),
            "--seeds",
            "0",
            "--threads",
            "1",
        ])
        .args(["--eval-games", "0", "--out"])
        .arg(agents.join("tiny"))
        .output()
        .unwrap();
    assert!(
        trained.status.success(),
        "{}",
        String::from_utf8_lossy(&trained.stderr)
    );
    let server = Server::start(
        &tmp.path().join("records"),
        "human,belief",
        &["--policies", agents.to_str().unwrap()],
    );
    let (_, offer) = server.get("/api/config");
    let seats = offer["offered"]["seats"].as_array().unwrap();
    assert!(seats.contains(&json!("tiny/seed-0")), "{offer}");
    let session = server.session();
    let game = server.new_game(
        &session,
        json!({ "seats": ["human", "tiny/seed-0"], "seed": 3 }),
    );
    assert_eq!(game["seats"], json!(["human", "tiny/seed-0"]));
    let end = play_out(&server, game, 2);
    assert!(end["board"]["over"].as_bool().unwrap());
    // The folder itself, or the policy's real path, is not a seat.
    let path = agents.join("tiny").join("seed-0").display().to_string();
    let (status, _) = server.post(
        "/api/games",
        &json!({ "session": session, "seats": ["human", path] }).to_string(),
    );
    assert_eq!(status, 400);
}

/// `--seats human,pretrained:quick/0` seats a pretrained agent built into the binary,
/// and a whole game plays against it; an unknown one stops the server at start, naming it.
#[test]
fn a_pretrained_agent_is_a_seat_by_name() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,pretrained:quick/0", &[]);
    let (_, offer) = server.get("/api/config");
    let seats = offer["offered"]["seats"].as_array().unwrap();
    assert!(seats.contains(&json!("pretrained:quick/0")), "{offer}");
    let session = server.session();
    let game = server.new_game(
        &session,
        json!({ "seats": ["human", "pretrained:quick/0"], "seed": 4 }),
    );
    assert_eq!(game["seats"], json!(["human", "pretrained:quick/0"]));
    let end = play_out(&server, game, 3);
    assert!(end["board"]["over"].as_bool().unwrap());
    let out = Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args(["serve", "--port", "0", "--seats", "human,pretrained:nope/0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no pretrained agent `pretrained:nope/0`"),
        "{err}"
    );
}

/// `yokai serve --report` computes the study's figures from the records: its row's R,
/// EE and LEN are the means of the games' outcomes as the page showed them.
#[test]
fn the_report_computes_the_metrics_of_the_recorded_games() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,greedy", &[]);
    let session = server.session();
    let outcomes: Vec<Value> = (0..4)
        .map(|k| {
            let game = server.new_game(&session, json!({ "seed": 20 + k }));
            play_out(&server, game, k as usize)["board"]["outcome"].clone()
        })
        .collect();
    let mean = |key: &str| {
        outcomes
            .iter()
            .map(|o| {
                o[key]
                    .as_f64()
                    .unwrap_or(o[key].as_bool().map_or(0.0, f64::from))
            })
            .sum::<f64>()
            / outcomes.len() as f64
    };
    let table = report(tmp.path());
    let row = table
        .lines()
        .find(|l| l.starts_with(&format!("| {session} | human + greedy | 4 |")))
        .unwrap_or_else(|| panic!("no row for the session:\n{table}"));
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    let r: f64 = cells[4].split('±').next().unwrap().trim().parse().unwrap();
    assert!(
        (r - mean("reward")).abs() < 0.006,
        "{row}: R {}",
        mean("reward")
    );
    let ee: f64 = cells[6].parse().unwrap();
    assert!((ee - 100.0 * mean("early_end")).abs() < 0.51, "{row}");
    let len: f64 = cells[8].parse().unwrap();
    assert!(
        (len - mean("length")).abs() < 0.051,
        "{row}: LEN {}",
        mean("length")
    );
}
