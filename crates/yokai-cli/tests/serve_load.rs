//! `yokai serve` under load and under a crash: 500 games at once played to their end with
//! the server's memory measured; the limits refusing with clear errors; and a server
//! killed with SIGKILL in the middle of many games, restarted, continuing every game from
//! its record.

#[path = "common/server.rs"]
mod server;

use serde_json::{json, Value};
use server::{answer, id, play_out, play_out_resyncing, report, tempdir, Server};
use std::collections::HashMap;
use std::sync::atomic::AtomicUsize;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use yokai_engine::Replay;

/// 500 games at once, each played to its end by its own client thread, with fewer games
/// allowed in memory than are open (so idle games are dropped and read back from their
/// records); none is lost, every record is a valid finished replay, no request is refused,
/// and the server's memory stays bounded.
#[test]
fn five_hundred_games_at_once_all_finish_with_valid_records_in_bounded_memory() {
    const SESSIONS: usize = 100;
    const PER_SESSION: usize = 5;
    let tmp = tempdir();
    let server = Server::start(tmp.path(), "human,random", &["--max-in-memory", "200"]);
    let sessions: Vec<String> = (0..SESSIONS).map(|_| server.session()).collect();
    let (_, idle_kib) = server.memory_kib();
    // Every game is opened before any is played on: 500 are open at once.
    let games: Vec<Value> = (0..SESSIONS * PER_SESSION)
        .map(|i| server.new_game(&sessions[i % SESSIONS], json!({})))
        .collect();
    let start = Instant::now();
    let resets = AtomicUsize::new(0);
    let ends: Vec<Value> = std::thread::scope(|scope| {
        let handles: Vec<_> = games
            .into_iter()
            .enumerate()
            .map(|(i, game)| {
                let (server, resets) = (&server, &resets);
                std::thread::Builder::new()
                    .stack_size(256 * 1024)
                    .spawn_scoped(scope, move || play_out_resyncing(server, game, i, resets))
                    .unwrap()
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let wall = start.elapsed();
    let (peak_kib, now_kib) = server.memory_kib();
    let mut ids: Vec<&str> = ends.iter().map(id).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), SESSIONS * PER_SESSION, "distinct games");
    let mut steps = 0;
    for end in &ends {
        let session = end["session"].as_str().unwrap();
        let path = tmp.path().join(session).join(format!("{}.jsonl", id(end)));
        let replay = Replay::from_jsonl(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(
            serde_json::to_value(replay.outcome.unwrap()).unwrap(),
            end["board"]["outcome"]
        );
        steps += replay.steps.len();
    }
    let refused = server
        .log
        .lock()
        .unwrap()
        .iter()
        .filter(|l| l.contains("refused") || l.contains("error #"))
        .count();
    eprintln!(
        "{} games at once: {steps} steps in {:.1} s; server memory idle {} MiB, peak {} MiB, at the end {} MiB; {refused} requests refused",
        ends.len(),
        wall.as_secs_f64(),
        idle_kib / 1024,
        peak_kib / 1024,
        now_kib / 1024
    );
    assert_eq!(refused, 0, "no request within the limits is refused");
    // A reset before any answer was the kernel's accept queue overflowing (tokio's default
    // backlog of 128 against 500 clients connecting at once on a busy machine; 34-102
    // resets in two of four runs beside three CPU hogs). The server now asks for 4096, so
    // no connection may be reset wherever the kernel grants that much.
    let resets = resets.into_inner();
    eprintln!("{resets} connections reset before an answer");
    match std::fs::read_to_string("/proc/sys/net/core/somaxconn") {
        Ok(max) if max.trim().parse::<u32>().is_ok_and(|m| m >= 1024) => {
            assert_eq!(
                resets,
                0,
                "connections reset with an accept queue of {}",
                max.trim()
            )
        }
        _ => eprintln!("the kernel caps the accept queue below 1024: resets not checked"),
    }
    // The measured peak was 74-96 MiB (docs/reliability.md); 256 MiB fails.
    assert!(peak_kib < 256 * 1024, "peak memory {peak_kib} KiB");
    let (_, summary) = server.get(&format!("/api/summary?session={}", sessions[0]));
    assert_eq!(summary["finished"], PER_SESSION);
    // The study's table: a row per session and one for all.
    let table = report(tmp.path());
    let rows: Vec<&str> = table
        .lines()
        .filter(|l| l.contains("| human + random | 5 |"))
        .collect();
    assert_eq!(rows.len(), SESSIONS, "{table}");
    assert!(table.contains("| all |  | 500 |"), "{table}");
}

/// Each limit refuses with its status and a message that names the limit.
#[test]
fn the_limits_refuse_with_clear_errors() {
    let tmp = tempdir();
    let server = Server::start(
        tmp.path(),
        "human,random",
        &[
            "--max-open-per-session",
            "2",
            "--max-open",
            "3",
            "--games-per-minute",
            "3",
            "--max-body",
            "2000",
            "--max-sessions",
            "3",
        ],
    );
    let (a, b) = (server.session(), server.session());
    let create = |s: &str| server.post("/api/games", &json!({ "session": s }).to_string());
    let g1 = create(&a).1;
    create(&a);
    let (status, answer) = create(&a);
    assert_eq!(status, 429, "{answer}");
    let text = answer["error"].as_str().unwrap();
    assert!(
        text.contains("2 unfinished games, its limit") && text.contains(id(&g1)),
        "{text}"
    );
    // A finished game frees its place, but the session has opened 3 games in a minute.
    play_out(&server, g1, 0);
    let (status, g3) = create(&a);
    assert_eq!(status, 200, "{g3}");
    play_out(&server, g3, 0);
    let (status, answer) = create(&a);
    assert_eq!(status, 429);
    assert!(
        answer["error"]
            .as_str()
            .unwrap()
            .contains("in the last minute"),
        "{answer}"
    );
    // Three games are open in all (one of a, two of b): the server's limit.
    create(&b);
    create(&b);
    let c = server.session();
    let (status, answer) = create(&c);
    assert_eq!(status, 429);
    assert!(
        answer["error"]
            .as_str()
            .unwrap()
            .contains("3 unfinished games"),
        "{answer}"
    );
    // A body over --max-body.
    let big = json!({ "session": b, "config": "x".repeat(3000) }).to_string();
    let (status, answer) = server.post("/api/games", &big);
    assert_eq!(status, 413, "{answer}");
    assert!(
        answer["error"].as_str().unwrap().contains("--max-body"),
        "{answer}"
    );
    // Sessions: three were issued, the limit.
    let (status, answer) = server.post("/api/sessions", "");
    assert_eq!(status, 429);
    assert!(
        answer["error"].as_str().unwrap().contains("sessions"),
        "{answer}"
    );
}

/// One client playing one game as fast as the server answers, noting the last step the
/// server acknowledged, until the server stops answering.
fn play_until_killed(server_base: &str, game: Value, acked: &Mutex<u64>, stop: &AtomicBool) {
    let mut game = game;
    let mut k = 0;
    while !stop.load(Ordering::Relaxed) && !game["board"]["over"].as_bool().unwrap() {
        let legal = game["board"]["legal"].as_array().unwrap();
        // Never END: the games must still be running when the server is killed.
        let choices: Vec<&Value> = legal.iter().filter(|a| a["kind"] != "end").collect();
        let pick = &choices[k % choices.len()]["index"];
        k += 1;
        let body =
            json!({"session": game["session"], "seat": game["board"]["viewer"], "action": pick});
        let sent = ureq::post(&format!("{server_base}/api/games/{}/actions", id(&game)))
            .send_string(&body.to_string());
        match sent {
            Ok(res) => {
                game = res.into_json().unwrap();
                *acked.lock().unwrap() = game["board"]["step"].as_u64().unwrap();
            }
            Err(ureq::Error::Transport(_)) => return,
            Err(e) => panic!("{e}"),
        }
    }
}

/// Games of 16 cards: long enough to be in the middle of when the server is killed.
const LONG_GAMES: &[&str] = &["--config", "16c-2p-perfect"];

/// SIGKILL in the middle of 30 games, three times; after each restart every game is there,
/// at or after the last step the server acknowledged, with a record that is a whole valid
/// replay; then every game is played to its end.
#[test]
fn a_server_killed_mid_game_continues_every_game_from_its_record() {
    const GAMES: usize = 30;
    let tmp = tempdir();
    let mut server = Server::start(tmp.path(), "human,greedy", LONG_GAMES);
    let mut games: Vec<(String, String)> = (0..GAMES)
        .map(|i| {
            let session = server.session();
            let game = server.new_game(&session, json!({ "seed": i }));
            (session, id(&game).to_string())
        })
        .collect();
    let mut acked: HashMap<String, u64> = HashMap::new();
    for round in 0..3 {
        let stop = AtomicBool::new(false);
        let before: Vec<u64> = games
            .iter()
            .map(|(_, g)| acked.get(g).copied().unwrap_or(0))
            .collect();
        let progress: Vec<Mutex<u64>> = before.iter().map(|&s| Mutex::new(s)).collect();
        std::thread::scope(|scope| {
            for (i, (session, g)) in games.iter().enumerate() {
                let (base, progress, stop) = (&server.base, &progress[i], &stop);
                let (_, game) = server.get(&format!("/api/games/{g}?session={session}"));
                scope.spawn(move || play_until_killed(base, game, progress, stop));
            }
            // Kill while the clients are mid-game: once a third of them have played on in
            // this round, at a different moment each round.
            let deadline = Instant::now() + Duration::from_secs(20);
            while (0..GAMES)
                .filter(|&i| *progress[i].lock().unwrap() > before[i])
                .count()
                < GAMES / 3
            {
                assert!(
                    Instant::now() < deadline,
                    "round {round}: the clients do not play"
                );
                std::thread::sleep(Duration::from_millis(2));
            }
            std::thread::sleep(Duration::from_millis(10 + 25 * round));
            server.child.kill().unwrap();
            server.child.wait().unwrap();
            stop.store(true, Ordering::Relaxed);
        });
        for (i, (_, g)) in games.iter().enumerate() {
            acked.insert(g.clone(), *progress[i].lock().unwrap());
        }
        // A temporary file left by the kill is not a record; every record is whole.
        for (session, g) in &games {
            let path = tmp.path().join(session).join(format!("{g}.jsonl"));
            let text = std::fs::read_to_string(&path).unwrap();
            let replay = Replay::from_jsonl(&text)
                .unwrap_or_else(|e| panic!("round {round}: {} is broken: {e}", path.display()));
            assert!(
                replay.steps.len() as u64 >= acked[g],
                "round {round}: {g} lost steps"
            );
        }
        let unfinished = games
            .iter()
            .filter(|(session, g)| {
                let path = tmp.path().join(session).join(format!("{g}.jsonl"));
                let text = std::fs::read_to_string(path).unwrap();
                Replay::from_jsonl(&text).unwrap().outcome.is_none()
            })
            .count();
        let half_written = std::fs::read_dir(tmp.path())
            .unwrap()
            .flatten()
            .flat_map(|d| std::fs::read_dir(d.path()).unwrap().flatten())
            .filter(|f| f.path().extension().is_some_and(|e| e == "tmp"))
            .count();
        eprintln!("round {round}: killed with {unfinished} games unfinished, {half_written} records half written");
        assert!(
            unfinished > 0,
            "round {round}: every game had ended before the kill"
        );
        server = Server::start(tmp.path(), "human,greedy", LONG_GAMES);
        let start = server.log.lock().unwrap()[0].clone();
        assert!(
            start.contains(&format!(" {unfinished} unfinished games")),
            "{start}"
        );
        for (session, g) in &games {
            let (status, game) = server.get(&format!("/api/games/{g}?session={session}"));
            assert_eq!(status, 200, "round {round}: {game}");
            assert!(game["board"]["step"].as_u64().unwrap() >= acked[g]);
        }
    }
    // Every game plays on to its end on the last server.
    for (session, g) in games.drain(..) {
        let game =
            answer(ureq::get(&format!("{}/api/games/{g}?session={session}", server.base)).call()).1;
        let end = play_out(&server, game, 0);
        let text =
            std::fs::read_to_string(tmp.path().join(&session).join(format!("{g}.jsonl"))).unwrap();
        let replay = Replay::from_jsonl(&text).unwrap();
        assert!(replay.outcome.is_some());
        assert_eq!(
            replay.steps.len() as u64,
            end["board"]["step"].as_u64().unwrap()
        );
    }
    assert!(server.alive());
}
