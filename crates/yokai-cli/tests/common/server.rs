//! A running `yokai serve` for the tests of the web server: start it on a free port, talk
//! to it over HTTP, stop it when dropped. Each test file uses a part of it.
#![allow(dead_code)]

use serde_json::{json, Value};
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};

/// A running `yokai serve` on a free port, stopped when dropped.
pub struct Server {
    pub child: Child,
    pub base: String,
    /// Every line the server logged so far.
    pub log: Arc<Mutex<Vec<String>>>,
    /// Keeps connections open between requests, as a browser does (a load test that opened
    /// a connection per request would measure the operating system's port reuse).
    agent: ureq::Agent,
}

impl Server {
    /// `yokai serve --port 0 --seats SEATS --records RECORDS` and `extra` arguments.
    pub fn start(records: &Path, seats: &str, extra: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_yokai"))
            .args(["serve", "--port", "0", "--seats", seats, "--records"])
            .arg(records)
            .args(extra)
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
        let log = Arc::new(Mutex::new(vec![first]));
        let keep = log.clone();
        std::thread::spawn(move || {
            for line in lines.map_while(Result::ok) {
                keep.lock().unwrap().push(line);
            }
        });
        let agent = ureq::AgentBuilder::new()
            .max_idle_connections(1024)
            .max_idle_connections_per_host(1024)
            .build();
        Server {
            child,
            base,
            log,
            agent,
        }
    }

    pub fn get(&self, path: &str) -> (u16, Value) {
        answer(self.agent.get(&format!("{}{path}", self.base)).call())
    }

    pub fn post(&self, path: &str, body: &str) -> (u16, Value) {
        answer(
            self.agent
                .post(&format!("{}{path}", self.base))
                .set("Content-Type", "application/json")
                .send_string(body),
        )
    }

    /// A new session id from the server.
    pub fn session(&self) -> String {
        let (status, answer) = self.post("/api/sessions", "");
        assert_eq!(status, 200, "{answer}");
        answer["session"].as_str().unwrap().to_string()
    }

    pub fn new_game(&self, session: &str, extra: Value) -> Value {
        let mut body = json!({ "session": session });
        body.as_object_mut()
            .unwrap()
            .extend(extra.as_object().unwrap().clone());
        let (status, game) = self.post("/api/games", &body.to_string());
        assert_eq!(status, 200, "{game}");
        game
    }

    pub fn act(&self, game: &Value, action: u64) -> (u16, Value) {
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

    /// The server's peak and current resident memory in KiB (Linux: /proc).
    pub fn memory_kib(&self) -> (u64, u64) {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        let field = |name: &str| {
            status
                .lines()
                .find(|l| l.starts_with(name))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse().ok())
                .unwrap()
        };
        (field("VmHWM:"), field("VmRSS:"))
    }

    /// Whether the process still runs.
    pub fn alive(&mut self) -> bool {
        self.child.try_wait().unwrap().is_none()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        // A server that stopped on its own (not killed by a test) says why.
        if let Ok(Some(status)) = self.child.try_wait() {
            let log = self.log.lock().unwrap();
            let tail = &log[log.len().saturating_sub(5)..];
            eprintln!(
                "the server had exited ({status}); its last lines:\n{}",
                tail.join("\n")
            );
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

pub fn answer(r: Result<ureq::Response, ureq::Error>) -> (u16, Value) {
    match r {
        Ok(res) => (res.status(), res.into_json().unwrap_or(Value::Null)),
        Err(ureq::Error::Status(code, res)) => (code, res.into_json().unwrap_or(Value::Null)),
        Err(e) => panic!("request failed: {e}"),
    }
}

pub fn id(game: &Value) -> &str {
    game["id"].as_str().unwrap()
}

/// Play legal actions (the `k`-th of each list, cycling) until the game ends; the last
/// game JSON.
pub fn play_out(server: &Server, mut game: Value, k: usize) -> Value {
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

/// Like [`play_out`], but a request whose connection is reset before any answer is not
/// fatal: the game is read again and play goes on from it, as the page does after an
/// error. Each such reset is counted in `resets`.
pub fn play_out_resyncing(
    server: &Server,
    mut game: Value,
    k: usize,
    resets: &std::sync::atomic::AtomicUsize,
) -> Value {
    let mut moves = 0;
    while !game["board"]["over"].as_bool().unwrap() {
        let legal = game["board"]["legal"].as_array().unwrap().clone();
        let pick = legal[(k + moves) % legal.len()]["index"].as_u64().unwrap();
        let body =
            json!({"session": game["session"], "seat": game["board"]["viewer"], "action": pick});
        let url = format!("{}/api/games/{}/actions", server.base, id(&game));
        game = match server.agent.post(&url).send_string(&body.to_string()) {
            Ok(res) => res.into_json().unwrap(),
            Err(ureq::Error::Transport(_)) => {
                resets.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let path = format!(
                    "/api/games/{}?session={}",
                    id(&game),
                    game["session"].as_str().unwrap()
                );
                (0..3)
                    .find_map(|_| {
                        match server.agent.get(&format!("{}{path}", server.base)).call() {
                            Ok(res) => Some(res.into_json().unwrap()),
                            Err(_) => None,
                        }
                    })
                    .expect("the game can be read again")
            }
            Err(e) => panic!("{e}"),
        };
        moves += 1;
        assert!(moves < 500, "the game does not end");
    }
    game
}

/// The first legal action that does not end the game.
pub fn first_not_end(game: &Value) -> u64 {
    let legal = game["board"]["legal"].as_array().unwrap();
    let pick = legal.iter().find(|a| a["kind"] != "end").unwrap();
    pick["index"].as_u64().unwrap()
}

/// The table `yokai serve --report` prints for the records under `records` (it must
/// succeed).
pub fn report(records: &Path) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_yokai"))
        .args(["serve", "--report", "--records"])
        .arg(records)
        .output()
        .unwrap();
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success(), "{table}");
    table
}

pub fn tempdir() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("yokai-serve-")
        .tempdir()
        .unwrap()
}
