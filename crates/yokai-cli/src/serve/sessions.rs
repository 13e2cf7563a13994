//! Sessions: ids the server issues, and what it counts per session (unfinished games, games
//! opened lately).
//!
//! An id is 128 random bits from the operating system, written as 32 hex digits: knowing
//! it is what lets a browser read and play its games, so it must not be guessable. A
//! session's games are filed under RECORDS/ID/, which is also how a restarted server knows
//! the sessions it issued before (a session with no game yet is forgotten by a restart;
//! the page then asks for a new one).

use super::error::{ApiError, ApiResult};
use super::limits::{Limits, Window};
use super::records;
use std::collections::{BTreeSet, HashMap};
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// What the server knows of one session.
#[derive(Default)]
struct Session {
    /// Its unfinished games.
    open: BTreeSet<String>,
    /// When it opened its last games, for `--games-per-minute`.
    opened: Window,
}

#[derive(Default)]
struct Registry {
    sessions: HashMap<String, Session>,
}

impl Registry {
    /// Unfinished games over all sessions (counted, not kept: one map walk per new game).
    fn open(&self) -> usize {
        self.sessions.values().map(|s| s.open.len()).sum()
    }
}

pub struct Sessions {
    limits: Limits,
    registry: Mutex<Registry>,
}

/// Whether `id` has the form of an issued session id (32 lowercase hex digits).
pub fn is_session_id(id: &str) -> bool {
    id.len() == 32
        && id
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

fn new_id() -> anyhow::Result<String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes)
        .map_err(|e| anyhow::anyhow!("the operating system gave no random bytes: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

impl Sessions {
    /// The sessions with records under `records` (a restarted server's), with their
    /// unfinished games. A record that cannot be read is reported and left out.
    pub fn load(records_dir: &Path, limits: Limits) -> Sessions {
        let mut registry = Registry::default();
        for (id, dir) in records::session_dirs(records_dir) {
            if !is_session_id(&id) {
                continue;
            }
            let session = registry.sessions.entry(id).or_default();
            for (game, finished) in records::games_in(&dir) {
                if !finished {
                    session.open.insert(game);
                }
            }
        }
        Sessions {
            limits,
            registry: Mutex::new(registry),
        }
    }

    fn registry(&self) -> std::sync::MutexGuard<'_, Registry> {
        self.registry.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A new session, unless the server holds `--max-sessions` already.
    pub fn issue(&self) -> ApiResult<String> {
        let mut r = self.registry();
        if r.sessions.len() >= self.limits.max_sessions {
            return Err(ApiError::TooMany(format!(
                "the server holds {} sessions, its limit; ask its operator",
                r.sessions.len()
            )));
        }
        loop {
            let id = new_id()?;
            if !r.sessions.contains_key(&id) {
                r.sessions.insert(id.clone(), Session::default());
                return Ok(id);
            }
        }
    }

    /// Refuse an id this server did not issue.
    pub fn check(&self, id: &str) -> ApiResult<()> {
        if is_session_id(id) && self.registry().sessions.contains_key(id) {
            Ok(())
        } else {
            Err(ApiError::Forbidden(
                "unknown session: the page asks the server for one (POST /api/sessions)".into(),
            ))
        }
    }

    /// Count game `game` as opened by `session` now, within the limits: games per minute,
    /// unfinished games of the session and of the server.
    pub fn open(&self, session: &str, game: &str) -> ApiResult<()> {
        self.check(session)?;
        let limits = &self.limits;
        let mut r = self.registry();
        let total = r.open();
        let s = r.sessions.get_mut(session).expect("checked");
        if s.open.len() >= limits.max_open_per_session {
            let ids: Vec<&str> = s.open.iter().map(String::as_str).collect();
            return Err(ApiError::TooMany(format!(
                "this session has {} unfinished games, its limit: finish one first ({})",
                s.open.len(),
                ids.join(", ")
            )));
        }
        if total >= limits.max_open {
            return Err(ApiError::TooMany(format!(
                "the server holds {total} unfinished games, its limit; try again later"
            )));
        }
        let minute = Duration::from_secs(60);
        if let Err(wait) = s
            .opened
            .admit(Instant::now(), limits.games_per_minute, minute)
        {
            return Err(ApiError::TooMany(format!(
                "this session opened {} games in the last minute, its limit; wait {} s",
                limits.games_per_minute,
                wait.as_secs() + 1
            )));
        }
        s.open.insert(game.to_string());
        Ok(())
    }

    /// Game `game` of `session` is finished (or was never made): it no longer counts.
    pub fn close(&self, session: &str, game: &str) {
        if let Some(s) = self.registry().sessions.get_mut(session) {
            s.open.remove(game);
        }
    }

    /// Unfinished games over all sessions.
    pub fn open_games(&self) -> usize {
        self.registry().open()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sessions(limits: Limits) -> Sessions {
        let dir = tempfile::tempdir().unwrap();
        Sessions::load(dir.path(), limits)
    }

    #[test]
    fn issued_ids_are_distinct_and_only_they_are_accepted() {
        let s = sessions(Limits::default());
        let a = s.issue().unwrap();
        let b = s.issue().unwrap();
        assert!(is_session_id(&a) && is_session_id(&b) && a != b);
        assert!(s.check(&a).is_ok());
        for bad in ["player1", "../x", "", &"0".repeat(32)] {
            assert!(matches!(s.check(bad), Err(ApiError::Forbidden(_))), "{bad}");
        }
    }

    #[test]
    fn open_games_are_limited_per_session_and_in_all_and_closing_frees_them() {
        let limits = Limits {
            max_open_per_session: 2,
            max_open: 3,
            ..Limits::default()
        };
        let s = sessions(limits);
        let (a, b) = (s.issue().unwrap(), s.issue().unwrap());
        s.open(&a, "g1").unwrap();
        s.open(&a, "g2").unwrap();
        let Err(ApiError::TooMany(m)) = s.open(&a, "g3") else {
            panic!("a third game of one session")
        };
        assert!(m.contains("g1, g2"), "{m}");
        s.open(&b, "g4").unwrap();
        assert!(matches!(s.open(&b, "g5"), Err(ApiError::TooMany(_))));
        s.close(&a, "g1");
        s.close(&a, "g1");
        assert_eq!(s.open_games(), 2);
        s.open(&b, "g5").unwrap();
    }

    #[test]
    fn a_session_opens_at_most_games_per_minute() {
        let s = sessions(Limits {
            games_per_minute: 3,
            ..Limits::default()
        });
        let a = s.issue().unwrap();
        for g in 0..3 {
            s.open(&a, &format!("g{g}")).unwrap();
            s.close(&a, &format!("g{g}"));
        }
        let Err(ApiError::TooMany(m)) = s.open(&a, "g3") else {
            panic!("a fourth game in a minute")
        };
        assert!(m.contains("in the last minute"), "{m}");
    }

    #[test]
    fn sessions_are_limited_in_number() {
        let s = sessions(Limits {
            max_sessions: 2,
            ..Limits::default()
        });
        s.issue().unwrap();
        s.issue().unwrap();
        assert!(matches!(s.issue(), Err(ApiError::TooMany(_))));
    }
}
