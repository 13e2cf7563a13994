//! The server's limits, each a command-line option with a default sized for a study of a
//! few hundred participants on one machine (docs/play.md, "Limits").

use std::collections::VecDeque;
use std::time::{Duration, Instant};

#[derive(clap::Args, Clone, Debug)]
pub struct Limits {
    /// Largest request body, in bytes (the largest legitimate one is a replay sent to the
    /// replay viewer: a few tens of kilobytes).
    #[arg(long, default_value_t = 1 << 20)]
    pub max_body: usize,
    /// Unfinished games one session may have at once.
    #[arg(long, default_value_t = 8)]
    pub max_open_per_session: usize,
    /// Unfinished games the server holds at once, over all sessions.
    #[arg(long, default_value_t = 2000)]
    pub max_open: usize,
    /// Games kept in memory; the least recently used idle ones are dropped beyond it and
    /// read back from their records when asked for (finished games are dropped at once).
    #[arg(long, default_value_t = 1000)]
    pub max_in_memory: usize,
    /// New games one session may open in any 60 seconds.
    #[arg(long, default_value_t = 20)]
    pub games_per_minute: usize,
    /// Sessions the server issues (and keeps) in all.
    #[arg(long, default_value_t = 10_000)]
    pub max_sessions: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_body: 1 << 20,
            max_open_per_session: 8,
            max_open: 2000,
            max_in_memory: 1000,
            games_per_minute: 20,
            max_sessions: 10_000,
        }
    }
}

/// At most `limit` events in any `window`: the times of the last `limit` events.
#[derive(Debug, Default)]
pub struct Window {
    times: VecDeque<Instant>,
}

impl Window {
    /// Record an event at `now` if fewer than `limit` happened in the `window` before it;
    /// otherwise how long until one may.
    pub fn admit(&mut self, now: Instant, limit: usize, window: Duration) -> Result<(), Duration> {
        while self
            .times
            .front()
            .is_some_and(|&t| now.duration_since(t) >= window)
        {
            self.times.pop_front();
        }
        if self.times.len() >= limit {
            let oldest = self.times[0];
            return Err(window - now.duration_since(oldest));
        }
        self.times.push_back(now);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_admits_limit_events_then_waits_for_the_oldest_to_leave() {
        let mut w = Window::default();
        let t0 = Instant::now();
        let minute = Duration::from_secs(60);
        for k in 0..3 {
            assert!(w.admit(t0 + Duration::from_secs(k), 3, minute).is_ok());
        }
        let wait = w
            .admit(t0 + Duration::from_secs(10), 3, minute)
            .unwrap_err();
        assert_eq!(wait, Duration::from_secs(50));
        // The refused event was not counted: once the first leaves, one more is admitted.
        assert!(w.admit(t0 + Duration::from_secs(60), 3, minute).is_ok());
        assert!(w.admit(t0 + Duration::from_secs(60), 3, minute).is_err());
    }
}
