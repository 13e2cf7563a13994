//! The games the server holds: a table per game (a [`Session`] with its seats), looked up
//! by id, each recorded to a replay file after every action so that a game survives a
//! reload of the page and a restart of the server.

use crate::eval::Entry;
use crate::play::session::{Player, Session};
use anyhow::{anyhow, bail, Context};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use yokai_engine::{Action, Config, MetricsAccumulator, Replay, Seat};

/// Seats and game the server offers when a page does not ask for others.
#[derive(Clone, Debug)]
pub struct Defaults {
    pub config: Config,
    pub seats: Vec<String>,
}

/// One game at one table.
pub struct Table {
    pub id: String,
    /// The person's session (a browser's id): records are filed under it.
    pub session_id: String,
    pub session: Session,
    pub seed: u64,
}

/// A game's key: the session it belongs to and its id.
type GameKey = (String, String);

/// Every game of the server.
pub struct Tables {
    defaults: Defaults,
    records: PathBuf,
    /// By (session, game id): a lookup never waits on a game whose bots are thinking.
    games: Mutex<HashMap<GameKey, Arc<Mutex<Table>>>>,
    next: Mutex<u64>,
}

/// An id of letters and digits only: it becomes a file name.
pub fn check_id(what: &str, id: &str) -> anyhow::Result<()> {
    if id.is_empty() || id.len() > 64 || !id.chars().all(|c| c.is_ascii_alphanumeric() || c == '-')
    {
        bail!("{what} `{id}` is not 1–64 letters, digits or dashes");
    }
    Ok(())
}

impl Tables {
    pub fn new(defaults: Defaults, records: PathBuf) -> Tables {
        let seed = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        Tables {
            defaults,
            records,
            games: Mutex::new(HashMap::new()),
            next: Mutex::new(seed),
        }
    }

    pub fn defaults(&self) -> &Defaults {
        &self.defaults
    }

    /// Seat the default seats once (a bad policy path fails at start, not in the page).
    pub fn check_defaults(&self) -> anyhow::Result<()> {
        players(&self.defaults.config, &self.defaults.seats, 0).map(|_| ())
    }

    /// A new game for `session_id` with `seats` (default: the server's) of `config`.
    pub fn create(
        &self,
        session_id: &str,
        config: Option<&str>,
        seats: Option<Vec<String>>,
        seed: Option<u64>,
    ) -> anyhow::Result<Arc<Mutex<Table>>> {
        check_id("session", session_id)?;
        let config = match config {
            Some(name) => Config::resolve(name)?,
            None => self.defaults.config,
        };
        let seats = seats.unwrap_or_else(|| self.defaults.seats.clone());
        // Every game gets a fresh id (and, unless asked for one, a fresh seed) from a
        // counter started at the server's start time: two games never share a record.
        let (id, fresh_seed) = {
            let mut next = self.next.lock().unwrap_or_else(|e| e.into_inner());
            loop {
                *next = yokai_engine::derive_seed(*next, 1);
                let id = format!("{:016x}", yokai_engine::derive_seed(*next, 0x5E7));
                if !self.record_path(session_id, &id).exists() {
                    break (id, *next);
                }
            }
        };
        let seed = seed.unwrap_or(fresh_seed);
        let session = Session::new(config, seed, players(&config, &seats, seed)?)?;
        let table = Arc::new(Mutex::new(Table {
            id: id.clone(),
            session_id: session_id.to_string(),
            session,
            seed,
        }));
        self.save(&table.lock().unwrap_or_else(|e| e.into_inner()))?;
        self.games
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert((session_id.to_string(), id), table.clone());
        Ok(table)
    }

    /// The game `id` of `session_id`: in memory, else read back from its record (after a
    /// restart of the server), its seats seated again and its actions replayed.
    pub fn get(&self, session_id: &str, id: &str) -> anyhow::Result<Arc<Mutex<Table>>> {
        check_id("session", session_id)?;
        check_id("game", id)?;
        let key = (session_id.to_string(), id.to_string());
        if let Some(t) = self
            .games
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            return Ok(t.clone());
        }
        let path = self.record_path(session_id, id);
        let text = std::fs::read_to_string(&path)
            .map_err(|_| anyhow!("no game `{id}` in this session"))?;
        let replay =
            Replay::from_jsonl(&text).with_context(|| format!("the record {}", path.display()))?;
        let seed = replay
            .header
            .seed
            .with_context(|| format!("the record {} has no seed", path.display()))?;
        let config = replay.header.config;
        let actions = replay
            .steps
            .iter()
            .map(|s| config.decode(s.action as usize))
            .collect::<Result<Vec<Action>, _>>()?;
        let seats = replay.header.seats.clone();
        let session = Session::resume(config, seed, players(&config, &seats, seed)?, &actions)?;
        let table = Arc::new(Mutex::new(Table {
            id: id.to_string(),
            session_id: session_id.to_string(),
            session,
            seed,
        }));
        // Two requests may have read the record at once: the first one in is the game.
        let mut games = self.games.lock().unwrap_or_else(|e| e.into_inner());
        Ok(games.entry(key).or_insert(table).clone())
    }

    /// Play `action` (an index) for `seat`, which must be the human to act; then the bots.
    pub fn act(&self, table: &mut Table, seat: u8, action: usize) -> anyhow::Result<()> {
        let config = *table.session.game().config();
        let action = config.decode(action)?;
        match table.session.human_to_act() {
            Some(s) if s == Seat(seat) => {}
            Some(s) => bail!("it is {s}'s turn, not seat {seat}'s"),
            None if table.session.is_over() => bail!("the game is over"),
            None => bail!("it is not a human's turn"),
        }
        table.session.choose(action)?;
        self.save(table)
    }

    /// Write the game's record (after every action: a reload or a restart continues it).
    pub fn save(&self, table: &Table) -> anyhow::Result<()> {
        let path = self.record_path(&table.session_id, &table.id);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
        }
        let tmp = path.with_extension("jsonl.tmp");
        std::fs::write(&tmp, table.session.replay().to_jsonl())
            .with_context(|| format!("cannot write {}", tmp.display()))?;
        std::fs::rename(&tmp, &path).with_context(|| format!("cannot write {}", path.display()))
    }

    pub fn record_path(&self, session_id: &str, id: &str) -> PathBuf {
        self.records.join(session_id).join(format!("{id}.jsonl"))
    }

    /// The paper's metrics over the finished games of `session_id`.
    pub fn summary(&self, session_id: &str) -> anyhow::Result<serde_json::Value> {
        check_id("session", session_id)?;
        summarise(&self.records.join(session_id))
    }
}

/// The seats named `seats` at a game of `config`: `human`, or anything `yokai eval` seats.
fn players(config: &Config, seats: &[String], seed: u64) -> anyhow::Result<Vec<(String, Player)>> {
    if seats.len() != config.players() {
        bail!(
            "{config} has {} seats, but {} were given",
            config.players(),
            seats.len()
        );
    }
    seats
        .iter()
        .enumerate()
        .map(|(s, name)| {
            if name == "human" {
                return Ok((name.clone(), Player::Human));
            }
            let entry = Entry::parse(name)?;
            entry.check_game(config)?;
            Ok((entry.name(), Player::Bot(entry.build(seed ^ s as u64))))
        })
        .collect()
}

/// The replay files (`*.jsonl`) in `dir`, read and checked; none if `dir` does not exist.
fn records_in(dir: &Path) -> anyhow::Result<Vec<Replay>> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for entry in entries.flatten() {
        let path = entry.path();
        if path.extension().and_then(|e| e.to_str()) == Some("jsonl") {
            let text = std::fs::read_to_string(&path)?;
            out.push(Replay::from_jsonl(&text).with_context(|| format!("{}", path.display()))?);
        }
    }
    Ok(out)
}

/// R, win rate, EE, SEE, WEE, LEN over the finished games recorded in `dir`.
pub fn summarise(dir: &Path) -> anyhow::Result<serde_json::Value> {
    let mut acc = MetricsAccumulator::default();
    let mut unfinished = 0;
    for replay in records_in(dir)? {
        match replay.outcome {
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
    let sessions =
        std::fs::read_dir(records).with_context(|| format!("cannot list {}", records.display()))?;
    for session in sessions.flatten().filter(|e| e.path().is_dir()) {
        let name = session.file_name().to_string_lossy().to_string();
        for replay in records_in(&session.path())? {
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
