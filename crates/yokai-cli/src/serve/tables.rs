//! The games the server holds: a table per game (a [`Session`] with its seats), looked up
//! by session and id, recorded after every action so that a game survives a reload of the
//! page, being dropped from memory, and a restart of the server.

use super::catalog::Catalog;
use super::error::{ApiError, ApiResult};
use super::limits::Limits;
use super::records;
use super::sessions::Sessions;
use crate::play::session::Session;
use anyhow::Context;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};
use yokai_engine::{Action, Config, Seat};

/// One game at one table.
pub struct Table {
    pub id: String,
    /// The session the game belongs to: its record is filed under it.
    pub session_id: String,
    pub session: Session,
    pub seed: u64,
}

pub type Shared = Arc<Mutex<Table>>;

/// A game's key: the session it belongs to and its id.
type GameKey = (String, String);

/// The games in memory, the least recently used dropped first beyond the limit.
#[derive(Default)]
struct Cache {
    games: HashMap<GameKey, (Shared, u64)>,
    clock: u64,
}

impl Cache {
    fn get(&mut self, key: &GameKey) -> Option<Shared> {
        self.clock += 1;
        let clock = self.clock;
        self.games.get_mut(key).map(|(t, used)| {
            *used = clock;
            t.clone()
        })
    }

    /// Keep `table` under `key` (or the one a concurrent request put there first).
    fn insert(&mut self, key: GameKey, table: Shared, capacity: usize) -> Shared {
        self.clock += 1;
        let clock = self.clock;
        let kept = self.games.entry(key).or_insert((table, clock)).0.clone();
        self.shrink(capacity);
        kept
    }

    /// Drop idle games, least recently used first, until at most `capacity` are kept. A
    /// game some request holds is never dropped: that request may be about to write its
    /// record, and a second copy read from the old record would fork the game.
    fn shrink(&mut self, capacity: usize) {
        while self.games.len() > capacity {
            let idle = self
                .games
                .iter()
                .filter(|(_, (t, _))| Arc::strong_count(t) == 1)
                .min_by_key(|(_, (_, used))| *used)
                .map(|(k, _)| k.clone());
            match idle {
                Some(key) => self.games.remove(&key),
                None => break,
            };
        }
    }
}

/// Every game of the server.
pub struct Tables {
    catalog: Catalog,
    default_seats: Vec<String>,
    records: PathBuf,
    limits: Limits,
    pub sessions: Sessions,
    cache: Mutex<Cache>,
    next: Mutex<u64>,
}

/// A game id: the server's own, 16 hex digits; it becomes a file name.
fn check_game_id(id: &str) -> ApiResult<()> {
    if id.len() == 16 && id.bytes().all(|b| b.is_ascii_hexdigit()) {
        Ok(())
    } else {
        Err(ApiError::NotFound("no such game in this session".into()))
    }
}

pub fn lock(table: &Shared) -> MutexGuard<'_, Table> {
    table.lock().unwrap_or_else(|e| e.into_inner())
}

impl Tables {
    /// The server's tables over `records`, with the sessions and unfinished games a
    /// previous run left there. Every default seat must be in the catalog.
    pub fn new(
        catalog: Catalog,
        default_seats: Vec<String>,
        records: PathBuf,
        limits: Limits,
    ) -> anyhow::Result<Tables> {
        let config = catalog.default_config();
        catalog
            .players(&config, &default_seats, 0)
            .map_err(|e| anyhow::anyhow!("--seats: {e}"))?;
        let seed = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        Ok(Tables {
            catalog,
            default_seats,
            sessions: Sessions::load(&records, limits.clone()),
            records,
            limits,
            cache: Mutex::new(Cache::default()),
            next: Mutex::new(seed),
        })
    }

    pub fn catalog(&self) -> &Catalog {
        &self.catalog
    }

    pub fn default_seats(&self) -> &[String] {
        &self.default_seats
    }

    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    fn cache(&self) -> MutexGuard<'_, Cache> {
        self.cache.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A new game for `session_id` with `seats` (default: the server's) of the game called
    /// `config` (default: the server's), within the session's and the server's limits.
    pub fn create(
        &self,
        session_id: &str,
        config: Option<&str>,
        seats: Option<Vec<String>>,
        seed: Option<u64>,
    ) -> ApiResult<Shared> {
        self.sessions.check(session_id)?;
        let config: Config = match config {
            Some(name) => self.catalog.config(name)?,
            None => self.catalog.default_config(),
        };
        let seats = seats.unwrap_or_else(|| self.default_seats.clone());
        // Every game gets a fresh id (and, unless asked for one, a fresh seed) from a
        // counter started at the server's start time: two games never share a record.
        let (id, fresh_seed) = {
            let mut next = self.next.lock().unwrap_or_else(|e| e.into_inner());
            loop {
                *next = yokai_engine::derive_seed(*next, 1);
                let id = format!("{:016x}", yokai_engine::derive_seed(*next, 0x5E7));
                if !records::record_path(&self.records, session_id, &id).exists() {
                    break (id, *next);
                }
            }
        };
        let seed = seed.unwrap_or(fresh_seed);
        let players = self.catalog.players(&config, &seats, seed)?;
        self.sessions.open(session_id, &id)?;
        let made = Session::new(config, seed, players).map(|session| Table {
            id: id.clone(),
            session_id: session_id.to_string(),
            session,
            seed,
        });
        // A game that could not be made or recorded is not open.
        let saved = made
            .map_err(ApiError::from)
            .and_then(|table| self.save(&table).map(|()| table));
        match saved {
            Ok(table) => Ok(self.keep(table)),
            Err(e) => {
                self.sessions.close(session_id, &id);
                Err(e)
            }
        }
    }

    /// Hold `table` in memory, unless it is finished (a table of bots only plays to its end
    /// at once; a finished game read back is served once): its record holds it then.
    fn keep(&self, table: Table) -> Shared {
        let key = (table.session_id.clone(), table.id.clone());
        let finished = table.session.is_over();
        let shared = Arc::new(Mutex::new(table));
        if finished {
            return shared;
        }
        self.cache().insert(key, shared, self.limits.max_in_memory)
    }

    /// The game `id` of `session_id`: in memory, else read back from its record (after a
    /// restart of the server, or once dropped from memory), its seats seated again and its
    /// actions replayed.
    pub fn get(&self, session_id: &str, id: &str) -> ApiResult<Shared> {
        self.sessions.check(session_id)?;
        check_game_id(id)?;
        let key = (session_id.to_string(), id.to_string());
        if let Some(t) = self.cache().get(&key) {
            return Ok(t);
        }
        let path = records::record_path(&self.records, session_id, id);
        let Some(replay) = records::read(&path)? else {
            return Err(ApiError::NotFound("no such game in this session".into()));
        };
        let seed = replay
            .header
            .seed
            .with_context(|| format!("the record {} has no seed", path.display()))?;
        let config = replay.header.config;
        let actions = replay
            .steps
            .iter()
            .map(|s| config.decode(s.action as usize))
            .collect::<Result<Vec<Action>, _>>()
            .with_context(|| format!("the record {}", path.display()))?;
        let players = self
            .catalog
            .players(&config, &replay.header.seats, seed)
            .map_err(|e| anyhow::anyhow!("the record {}: {e}", path.display()))?;
        let session = Session::resume(config, seed, players, &actions)
            .with_context(|| format!("the record {}", path.display()))?;
        Ok(self.keep(Table {
            id: id.to_string(),
            session_id: session_id.to_string(),
            session,
            seed,
        }))
    }

    /// Play `action` (an index) for `seat`, which must be the human to act; then the bots.
    /// A game that ends here leaves memory (its record holds it).
    pub fn act(&self, table: &mut Table, seat: u8, action: usize) -> ApiResult<()> {
        let config = *table.session.game().config();
        let action = config
            .decode(action)
            .map_err(|e| ApiError::BadRequest(e.to_string()))?;
        // The session refuses a finished game or a bot's turn itself; it does not know
        // which seat the page speaks for.
        if let Some(s) = table.session.human_to_act().filter(|&s| s != Seat(seat)) {
            return Err(ApiError::BadRequest(format!(
                "it is {s}'s turn, not seat {seat}'s"
            )));
        }
        let before = table.session.game().steps();
        if let Err(e) = table.session.choose(action) {
            // The human's action was refused (nothing changed), or a bot failed after it.
            return Err(if table.session.game().steps() == before {
                ApiError::BadRequest(format!("{e:#}"))
            } else {
                ApiError::Internal(e)
            });
        }
        self.save(table)
    }

    /// Write the game's record; a finished game no longer counts as open and leaves memory.
    pub fn save(&self, table: &Table) -> ApiResult<()> {
        let path = records::record_path(&self.records, &table.session_id, &table.id);
        records::write(&path, &table.session.replay())?;
        if table.session.is_over() {
            self.sessions.close(&table.session_id, &table.id);
            let key = (table.session_id.clone(), table.id.clone());
            self.cache().games.remove(&key);
        }
        Ok(())
    }

    /// The paper's metrics over the finished games of `session_id`.
    pub fn summary(&self, session_id: &str) -> ApiResult<serde_json::Value> {
        self.sessions.check(session_id)?;
        Ok(records::summarise(&self.records.join(session_id))?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cache_drops_the_least_recently_used_idle_game_and_never_a_held_one() {
        let mut cache = Cache::default();
        let table = |n: &str| {
            let config = Config::from_name("9c-2p").unwrap();
            Arc::new(Mutex::new(Table {
                id: n.into(),
                session_id: "s".into(),
                session: Session::new(
                    config,
                    0,
                    vec![
                        ("human".into(), crate::play::session::Player::Human),
                        ("human".into(), crate::play::session::Player::Human),
                    ],
                )
                .unwrap(),
                seed: 0,
            }))
        };
        let key = |n: &str| ("s".to_string(), n.to_string());
        let held = cache.insert(key("a"), table("a"), 2);
        drop(cache.insert(key("b"), table("b"), 2));
        assert!(cache.get(&key("b")).is_some());
        // `a` is the least recently used, but held: `b` goes instead.
        drop(cache.insert(key("c"), table("c"), 2));
        assert!(cache.games.contains_key(&key("a")));
        assert!(!cache.games.contains_key(&key("b")));
        drop(held);
        drop(cache.insert(key("d"), table("d"), 2));
        assert!(!cache.games.contains_key(&key("a")));
        assert_eq!(cache.games.len(), 2);
    }
}
