//! The server's records on disk: RECORDS/SESSION/GAME.jsonl, a replay file per game written
//! after every action, and the tables read from them.
//!
//! A record is written to GAME.jsonl.tmp and renamed over the old one, so a server killed
//! at any moment leaves either the record before the action or the one after it, never a
//! part of one.

use anyhow::Context;
use std::path::{Path, PathBuf};
use yokai_engine::{MetricsAccumulator, Replay};

/// Where game `game` of `session` is recorded. Both are checked ids (hex digits): they
/// cannot leave `records`.
pub fn record_path(records: &Path, session: &str, game: &str) -> PathBuf {
    records.join(session).join(format!("{game}.jsonl"))
}

/// Write `replay` as the record at `path`, atomically.
pub fn write(path: &Path, replay: &Replay) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let tmp = path.with_extension("jsonl.tmp");
    std::fs::write(&tmp, replay.to_jsonl())
        .with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
}

/// The record at `path`: `None` if there is none, an error if it cannot be read.
pub fn read(path: &Path) -> anyhow::Result<Option<Replay>> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", path.display())),
    };
    Replay::from_jsonl(&text)
        .map(Some)
        .with_context(|| format!("the record {}", path.display()))
}

/// The session folders under `records`: (name, path).
pub fn session_dirs(records: &Path) -> Vec<(String, PathBuf)> {
    let Ok(entries) = std::fs::read_dir(records) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|e| e.path().is_dir())
        .map(|e| (e.file_name().to_string_lossy().to_string(), e.path()))
        .collect()
}

/// The games recorded in a session folder: (id, finished). A record that cannot be read is
/// reported on the log and left out.
pub fn games_in(dir: &Path) -> Vec<(String, bool)> {
    replays_in(dir)
        .into_iter()
        .filter_map(|(path, replay)| match replay {
            Ok(r) => {
                let id = path.file_stem()?.to_string_lossy().to_string();
                Some((id, r.outcome.is_some()))
            }
            Err(e) => {
                eprintln!("yokai serve: left out: {e:#}");
                None
            }
        })
        .collect()
}

/// Every `*.jsonl` in `dir` with its replay or the reason it is none.
fn replays_in(dir: &Path) -> Vec<(PathBuf, anyhow::Result<Replay>)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut out: Vec<_> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("jsonl"))
        .map(|p| {
            let replay = read(&p).and_then(|r| r.context("vanished"));
            (p, replay)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// R, win rate, EE, SEE, WEE, LEN over the finished games recorded in `dir`.
pub fn summarise(dir: &Path) -> anyhow::Result<serde_json::Value> {
    let mut acc = MetricsAccumulator::default();
    let mut unfinished = 0;
    for (_, replay) in replays_in(dir) {
        match replay?.outcome {
            Some(o) => acc.add(&o),
            None => unfinished += 1,
        }
    }
    Ok(serde_json::json!({
        "finished": acc.games,
        "unfinished": unfinished,
        "metrics": acc.metrics(),
    }))
}

/// A Markdown table of the finished games under `records` (RECORDS/SESSION/GAME.jsonl),
/// one row per session and seating, in the paper's metrics: the human study's results.
pub fn report(records: &Path) -> anyhow::Result<String> {
    let mut groups: std::collections::BTreeMap<(String, String), MetricsAccumulator> =
        Default::default();
    let mut unfinished = 0;
    if !records.is_dir() {
        anyhow::bail!("cannot list {}: not a folder", records.display());
    }
    for (name, dir) in session_dirs(records) {
        for (_, replay) in replays_in(&dir) {
            let replay = replay?;
            let seating = replay.header.seats.join(" + ");
            match replay.outcome {
                Some(o) => groups.entry((name.clone(), seating)).or_default().add(&o),
                None => unfinished += 1,
            }
        }
    }
    let mut out = String::from(
        "| session | seats | games | R | SEE % | EE % | WEE % | LEN |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut all = MetricsAccumulator::default();
    let row = |session: &str, seats: &str, acc: &MetricsAccumulator| {
        let m = acc.metrics().expect("a group has games");
        let wee = m
            .win_given_early_end
            .map_or("–".to_string(), |w| format!("{:.0}", 100.0 * w));
        format!(
            "| {session} | {seats} | {} | {:.2} ± {:.2} | {:.0} | {:.0} | {wee} | {:.1} |\n",
            m.games,
            m.reward,
            m.reward_se,
            100.0 * m.successful_early_end,
            100.0 * m.early_end,
            m.length
        )
    };
    for ((session, seats), acc) in &groups {
        out += &row(session, seats, acc);
        all.merge(acc);
    }
    if groups.len() > 1 {
        out += &row("all", "", &all);
    }
    if groups.is_empty() {
        out = "No finished game.\n".into();
    }
    if unfinished > 0 {
        out += &format!("\n{unfinished} unfinished game(s) left out.\n");
    }
    Ok(out)
}
