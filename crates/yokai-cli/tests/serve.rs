//! `yokai serve` over HTTP: scripted players play whole games, every request is checked
//! against the rules, records are valid replays of the games shown, games survive a
//! restart of the server, hot seat hides the board, and 50 games at once all finish.

use serde_json::{json, Value};
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use yokai_engine::Replay;

/// A running `yokai serve` on a free port, stopped when dropped.
struct Server {
    child: Child,
    base: String,
}

impl Server {
    fn start(records: &Path, seats: &str) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_yokai"))
            .args(["serve", "--port", "0", "--seats", seats, "--records"])
            .arg(records)
            .stderr(Stdio::piped())
            .spawn()
            .expect("starts");
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let first = lines.next().expect("a start line").unwrap();
        let base = first
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("no address in `{first}`"))
            .trim_end_matches('/')
            .to_string();
        // Keep reading the log so the server never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Server { child, base }
    }

    fn get(&self, path: &str) -> (u16, Value) {
        answer(ureq::get(&format!("{}{path}", self.base)).call())
    }

    fn post(&self, path: &str, body: &str) -> (u16, Value) {
        answer(
            ureq::post(&format!("{}{path}", self.base))
                .set("Content-Type", "application/json")
                .send_string(body),
        )
    }

    fn new_game(&self, session: &str, extra: Value) -> Value {
        let mut body = json!({ "session": session });
        body.as_object_mut()
            .unwrap()
            .extend(extra.as_object().unwrap().clone());
        let (status, game) = self.post("/api/games", &body.to_string());
        assert_eq!(status, 200, "{game}");
        game
    }

    fn act(&self, game: &Value, action: u64) -> (u16, Value) {
        let body = json!({
            "session": game["session"],
            "seat": game["board"]["viewer"],
            "action": action,
        });
        self.post(
            &format!("/api/games/{}/actions", id(game)),
            &body.to_string(),
        )
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn answer(r: Result<ureq::Response, ureq::Error>) -> (u16, Value) {
    match r {
        Ok(res) => (res.status(), res.into_json().unwrap_or(Value::Null)),
        Err(ureq::Error::Status(code, res)) => (code, res.into_json().unwrap_or(Value::Null)),
        Err(e) => panic!("request failed: {e}"),
    }
}

fn id(game: &Value) -> &str {
    game["id"].as_str().unwrap()
}

/// Play legal actions (the `k`-th of each list, cycling) until the game ends; the last
/// game JSON.
fn play_out(server: &Server, mut game: Value, k: usize) -> Value {
    let mut moves = 0;
    while !game["board"]["over"].as_bool().unwrap() {
        let legal = game["board"]["legal"].as_array().unwrap().clone();
        assert!(
            !legal.is_empty(),
            "the human to act has legal actions: {game}"
        );
        let pick = legal[(k + moves) % legal.len()]["index"].as_u64().unwrap();
        let (status, next) = server.act(&game, pick);
        assert_eq!(status, 200, "{next}");
        // One board per step played since (this action and the bots' after it), the last
        // one the board now.
        let (before, now) = (
            game["board"]["step"].as_u64(),
            next["board"]["step"].as_u64(),
        );
        let frames = next["frames"].as_array().unwrap();
        assert_eq!(
            frames.len() as u64,
            now.unwrap() - before.unwrap(),
            "{next}"
        );
        assert_eq!(frames.last(), Some(&next["board"]));
        game = next;
        moves += 1;
        assert!(moves < 500, "the game does not end");
    }
    game
}

/// The first legal action that does not end the game.
fn first_not_end(game: &Value) -> u64 {
    let legal = game["board"]["legal"].as_array().unwrap();
    let pick = legal.iter().find(|a| a["kind"] != "end").unwrap();
    pick["index"].as_u64().unwrap()
}

fn tempdir() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("yokai-serve-")
        .tempdir()
        .unwrap()
}

#[test]
fn a_scripted_player_plays_a_whole_game_and_its_record_is_the_game_shown() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,belief");
    // The page itself, built into the binary.
    let page = ureq::get(&format!("{}/", server.base)).call().unwrap();
    assert_eq!(page.status(), 200);
    assert!(page.into_string().unwrap().contains("<title>Yōkai</title>"));
    let game = server.new_game("player1", json!({ "seed": 11 }));
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
    let path = tmp
        .path()
        .join("player1")
        .join(format!("{}.jsonl", id(&end)));
    let record = Replay::from_jsonl(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let served = ureq::get(&format!(
        "{}/api/games/{}/replay?session=player1",
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
    let (_, summary) = server.get("/api/summary?session=player1");
    assert_eq!(summary["finished"], 1);
    assert_eq!(
        summary["metrics"]["reward"],
        outcome["reward"].as_f64().unwrap()
    );
}

#[test]
fn every_bad_request_is_refused_clearly_and_changes_nothing() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,random");
    let game = server.new_game("s1", json!({ "seed": 2 }));
    let g = id(&game).to_string();
    let step = game["board"]["step"].clone();
    let legal: Vec<u64> = game["board"]["legal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["index"].as_u64().unwrap())
        .collect();
    let illegal = (0..777).find(|i| !legal.contains(i)).unwrap();
    let cases = [
        (
            json!({"session": "s1", "seat": 0, "action": illegal}).to_string(),
            400,
            "is not legal now",
        ),
        (
            json!({"session": "s1", "seat": 1, "action": legal[0]}).to_string(),
            400,
            "turn",
        ),
        (
            json!({"session": "s1", "seat": 0, "action": 100000}).to_string(),
            400,
            "out of range",
        ),
        (
            json!({"session": "s1", "seat": 0}).to_string(),
            400,
            "missing field `action`",
        ),
        (
            json!({"session": "s1", "seat": 0, "action": -1}).to_string(),
            400,
            "not valid",
        ),
        ("{not json".to_string(), 400, "not valid"),
        (
            json!({"session": "other", "seat": 0, "action": legal[0]}).to_string(),
            404,
            "no game",
        ),
        (
            json!({"session": "../x", "seat": 0, "action": legal[0]}).to_string(),
            404,
            "letters",
        ),
    ];
    for (body, code, message) in cases {
        let (status, answer) = server.post(&format!("/api/games/{g}/actions"), &body);
        assert_eq!(status, code, "{body}: {answer}");
        let text = answer["error"].as_str().unwrap_or_default();
        assert!(text.contains(message), "{body}: {text}");
        let (_, now) = server.get(&format!("/api/games/{g}?session=s1"));
        assert_eq!(now["board"]["step"], step, "{body} changed the game");
    }
    let (status, answer) = server.get("/api/games/0123?session=s1");
    assert_eq!((status, answer["error"].is_string()), (404, true));
    let (status, answer) = server.post(
        "/api/games",
        r#"{"session":"s1","seats":["human","nobody"]}"#,
    );
    assert_eq!(status, 400);
    assert!(
        answer["error"].as_str().unwrap().contains("nobody"),
        "{answer}"
    );
    let (status, answer) = server.post("/api/replay", "not a replay");
    assert_eq!(status, 400, "{answer}");
}

#[test]
fn a_game_continues_after_the_server_restarts() {
    let tmp = tempdir();
    let (g, log) = {
        let server = Server::start(tmp.path(), "human,greedy");
        let mut game = server.new_game("s2", json!({ "seed": 5 }));
        for _ in 0..6 {
            game = server.act(&game, first_not_end(&game)).1;
        }
        (id(&game).to_string(), game["log"].clone())
    };
    let server = Server::start(tmp.path(), "human,greedy");
    let (status, game) = server.get(&format!("/api/games/{g}?session=s2"));
    assert_eq!(status, 200, "{game}");
    assert_eq!(game["log"], log);
    let end = play_out(&server, game, 0);
    let record = std::fs::read_to_string(tmp.path().join("s2").join(format!("{g}.jsonl"))).unwrap();
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
    let server = Server::start(tmp.path(), "human,human");
    let mut game = server.new_game("s3", json!({ "seed": 8 }));
    // Seat 0 plays its turn (4 substeps); then seat 1 is to act behind the curtain.
    while game["to_act"] == 0 {
        game = server.act(&game, first_not_end(&game)).1;
    }
    assert_eq!(game["to_act"], 1);
    assert_eq!(game["curtain"], true);
    assert!(game["board"].is_null(), "no board behind the curtain");
    let (_, shown) = server.post(
        &format!("/api/games/{}/reveal", id(&game)),
        r#"{"session":"s3"}"#,
    );
    assert_eq!(shown["curtain"], false);
    assert_eq!(shown["board"]["viewer"], 1);
}

/// Load: 50 games at once, each played to its end by its own scripted client; none is
/// lost and every record is a valid, finished replay.
#[test]
fn fifty_concurrent_games_all_finish_with_valid_records() {
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,random");
    let ends: Vec<Value> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..50)
            .map(|i| {
                let server = &server;
                scope.spawn(move || {
                    let game = server.new_game(&format!("load{}", i % 5), json!({}));
                    play_out(server, game, i)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut ids: Vec<&str> = ends.iter().map(id).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), 50, "50 distinct games");
    let mut files = 0;
    for end in &ends {
        let session = end["session"].as_str().unwrap();
        let path = tmp.path().join(session).join(format!("{}.jsonl", id(end)));
        let replay = Replay::from_jsonl(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(
            serde_json::to_value(replay.outcome.unwrap()).unwrap(),
            end["board"]["outcome"]
        );
        files += 1;
    }
    assert_eq!(files, 50);
    let (_, summary) = server.get("/api/summary?session=load0");
    assert_eq!(summary["finished"], 10);
    // The study's table: a row per session (5 sessions × 10 games) and one for all.
    let out = Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args(["serve", "--report", "--records"])
        .arg(tmp.path())
        .output()
        .unwrap();
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success(), "{table}");
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| load")).collect();
    assert_eq!(rows.len(), 5, "{table}");
    assert!(
        rows.iter().all(|r| r.contains("| human + random | 10 |")),
        "{table}"
    );
    assert!(table.contains("| all |  | 50 |"), "{table}");
}
