//! The state of a game with people and policies at the table, without any terminal: keys
//! in, actions out. The TUI and the line mode are thin front ends over it, and tests drive
//! it directly.

use anyhow::{anyhow, bail};
use yokai_agents::Policy;
use yokai_engine::{derive_seed, Action, Config, EpisodeRecord, Game, RecordedGame, Replay, Seat};

/// Who holds a seat.
pub enum Player {
    Human,
    Bot(Box<dyn Policy>),
}

/// A key press, already decoded from the terminal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Key {
    Up,
    Down,
    PageUp,
    PageDown,
    Enter,
    Char(char),
    Esc,
}

/// What a key did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Effect {
    Nothing,
    /// The selection moved.
    Selected(usize),
    /// The hot-seat curtain was lifted for this seat.
    Revealed(Seat),
    /// The human to act played this action (bots may have played after it).
    Played(Action),
    Quit,
}

/// A game in progress at a table of humans and bots.
pub struct Session {
    game: RecordedGame,
    players: Vec<Player>,
    names: Vec<String>,
    seed: u64,
    /// Every action so far in words, with who played it.
    log: Vec<String>,
    /// Index into the acting human's legal actions.
    selected: usize,
    /// Hot seat: with several humans, the board stays hidden until the next human says
    /// they are the one at the screen.
    curtain: bool,
    /// The human who saw the board last (the curtain drops when another human is to act).
    last_human: Option<Seat>,
}

impl Session {
    /// A new game dealt from `seed`; bots are reset with seeds derived from it.
    pub fn new(
        config: Config,
        seed: u64,
        players: Vec<(String, Player)>,
    ) -> anyhow::Result<Session> {
        let mut session = Session::seated(config, seed, players)?;
        session.run_bots()?;
        Ok(session)
    }

    /// The game dealt from `seed` continued through `actions` (a record's), every seat shown
    /// every action (bots observe the recorded actions; they do not choose them), then the
    /// bots play on if it is their turn.
    pub fn resume(
        config: Config,
        seed: u64,
        players: Vec<(String, Player)>,
        actions: &[Action],
    ) -> anyhow::Result<Session> {
        let mut session = Session::seated(config, seed, players)?;
        for (step, &action) in actions.iter().enumerate() {
            let seat = session.game().current_seat();
            session.game().check(seat, action).map_err(|reason| {
                anyhow!("recorded step {step}, `{action}` by {seat}: {reason}")
            })?;
            if matches!(session.players[seat.index()], Player::Human) {
                session.last_human = Some(seat);
            }
            session.apply(seat, action);
        }
        session.run_bots()?;
        Ok(session)
    }

    fn seated(
        config: Config,
        seed: u64,
        players: Vec<(String, Player)>,
    ) -> anyhow::Result<Session> {
        if players.len() != config.players() {
            return Err(anyhow!(
                "{config} has {} seats, but {} players were given",
                config.players(),
                players.len()
            ));
        }
        let (names, mut players): (Vec<String>, Vec<Player>) = players.into_iter().unzip();
        for (s, p) in players.iter_mut().enumerate() {
            if let Player::Bot(b) = p {
                b.reset(derive_seed(seed, s as u64));
            }
        }
        Ok(Session {
            game: RecordedGame::new(config, seed),
            players,
            names,
            seed,
            log: Vec::new(),
            selected: 0,
            curtain: false,
            last_human: None,
        })
    }

    pub fn game(&self) -> &Game {
        self.game.game()
    }
    pub fn names(&self) -> &[String] {
        &self.names
    }
    pub fn log(&self) -> &[String] {
        &self.log
    }
    pub fn selected(&self) -> usize {
        self.selected
    }
    pub fn is_over(&self) -> bool {
        self.game().is_over()
    }
    /// True when the board is hidden between two humans' turns.
    pub fn curtain(&self) -> bool {
        self.curtain
    }
    fn humans(&self) -> usize {
        self.players
            .iter()
            .filter(|p| matches!(p, Player::Human))
            .count()
    }

    /// Whether a person holds `seat`.
    pub fn is_human(&self, seat: Seat) -> bool {
        matches!(self.players.get(seat.index()), Some(Player::Human))
    }

    /// The human whose turn it is (`None` when the game is over).
    pub fn human_to_act(&self) -> Option<Seat> {
        let seat = self.game().current_seat();
        (!self.is_over() && matches!(self.players[seat.index()], Player::Human)).then_some(seat)
    }

    /// The seat whose knowledge the screen shows: the acting human, else the last human
    /// (or seat 0 at a table of bots).
    pub fn viewer(&self) -> Seat {
        self.human_to_act().or(self.last_human).unwrap_or(Seat(0))
    }

    /// The acting human's legal actions, in index order. Only these can be chosen.
    pub fn legal(&self) -> Vec<Action> {
        match self.human_to_act() {
            Some(seat) => self.game().legal_actions(seat),
            None => Vec::new(),
        }
    }

    /// Decode one key.
    pub fn handle(&mut self, key: Key) -> anyhow::Result<Effect> {
        if matches!(key, Key::Char('q') | Key::Esc) {
            return Ok(Effect::Quit);
        }
        if self.curtain {
            if let (Key::Enter | Key::Char(' '), Some(seat)) = (key, self.human_to_act()) {
                self.curtain = false;
                self.last_human = Some(seat);
                return Ok(Effect::Revealed(seat));
            }
            return Ok(Effect::Nothing);
        }
        let n = self.legal().len();
        if n == 0 {
            return Ok(Effect::Nothing);
        }
        let moved = |to: usize| Ok(Effect::Selected(to));
        match key {
            Key::Up | Key::Char('k') => {
                self.selected = (self.selected + n - 1) % n;
                moved(self.selected)
            }
            Key::Down | Key::Char('j') => {
                self.selected = (self.selected + 1) % n;
                moved(self.selected)
            }
            Key::PageUp => {
                self.selected = self.selected.saturating_sub(10);
                moved(self.selected)
            }
            Key::PageDown => {
                self.selected = (self.selected + 10).min(n - 1);
                moved(self.selected)
            }
            Key::Enter => {
                let action = self.legal()[self.selected];
                self.choose(action)?;
                Ok(Effect::Played(action))
            }
            _ => Ok(Effect::Nothing),
        }
    }

    /// A mouse click on legal action `index`: the first click selects it, a click on the
    /// selected action plays it.
    pub fn click(&mut self, index: usize) -> anyhow::Result<Effect> {
        if self.curtain || index >= self.legal().len() {
            return Ok(Effect::Nothing);
        }
        if index != self.selected {
            self.selected = index;
            return Ok(Effect::Selected(index));
        }
        self.handle(Key::Enter)
    }

    /// Play `action` for the acting human; anything not legal for them is refused with the
    /// rules' reason, and nothing changes.
    pub fn choose(&mut self, action: Action) -> anyhow::Result<()> {
        let Some(seat) = self.human_to_act() else {
            return Err(if self.is_over() {
                anyhow!("the game is over")
            } else {
                anyhow!("it is not a human's turn")
            });
        };
        if self.curtain {
            bail!("the board is hidden: the next player must reveal it first");
        }
        self.game()
            .check(seat, action)
            .map_err(|reason| anyhow!("`{action}` is not legal now: {reason}"))?;
        self.last_human = Some(seat);
        self.apply(seat, action);
        self.run_bots()
    }

    fn apply(&mut self, seat: Seat, action: Action) {
        for (s, p) in self.players.iter_mut().enumerate() {
            if let Player::Bot(b) = p {
                b.observe(&self.game.game().view(Seat(s as u8)), seat, action);
            }
        }
        self.log
            .push(format!("{seat} ({}): {action}", self.names[seat.index()]));
        self.game.apply(action).expect("checked before");
        self.selected = 0;
    }

    /// Let bots play until a human must act or the game ends; then drop the curtain if a
    /// different human than the last one is to act.
    fn run_bots(&mut self) -> anyhow::Result<()> {
        while !self.is_over() {
            let seat = self.game().current_seat();
            let Player::Bot(bot) = &mut self.players[seat.index()] else {
                break;
            };
            let action = bot.act(&self.game.game().view(seat));
            if let Err(reason) = self.game().check(seat, action) {
                return Err(anyhow!(
                    "policy `{}` at {seat} chose `{action}`: {reason}",
                    self.names[seat.index()]
                ));
            }
            self.apply(seat, action);
        }
        if let Some(seat) = self.human_to_act() {
            if self.humans() > 1 && self.last_human.is_some_and(|h| h != seat) {
                self.curtain = true;
            }
        }
        Ok(())
    }

    /// The game so far: its deal and actions.
    pub fn record(&self) -> &EpisodeRecord {
        self.game.record()
    }

    /// The game so far as a replay file.
    pub fn replay(&self) -> Replay {
        Replay::from_record(self.game.record(), Some(self.seed), self.names.clone())
            .expect("a game played through the rules replays")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use yokai_agents::RandomPolicy;

    fn config(players: &str) -> Config {
        Config::from_name(&format!("9c-{players}p-perfect")).unwrap()
    }

    #[test]
    fn keys_select_among_legal_actions_only_and_enter_plays() {
        let mut s = Session::new(
            config("2"),
            4,
            vec![
                ("human".into(), Player::Human),
                ("random".into(), Player::Bot(Box::new(RandomPolicy::new(1)))),
            ],
        )
        .unwrap();
        assert_eq!(s.human_to_act(), Some(Seat(0)));
        let legal = s.legal();
        assert_eq!(s.handle(Key::Down).unwrap(), Effect::Selected(1));
        assert_eq!(s.handle(Key::Up).unwrap(), Effect::Selected(0));
        assert_eq!(
            s.handle(Key::Up).unwrap(),
            Effect::Selected(legal.len() - 1)
        );
        let want = legal[legal.len() - 1];
        assert_eq!(s.handle(Key::Enter).unwrap(), Effect::Played(want));
        assert_eq!(s.log()[0], format!("seat 0 (human): {want}"));
        // An illegal action is refused and changes nothing.
        let steps = s.game().steps();
        let illegal = (0..s.game().config().num_actions())
            .map(|i| s.game().config().decode(i).unwrap())
            .find(|a| !s.legal().contains(a))
            .unwrap();
        let e = s.choose(illegal).unwrap_err();
        assert!(e.to_string().contains("is not legal now"), "{e}");
        assert_eq!(s.game().steps(), steps);
        // A click selects; a click on the selected action plays it; beyond the list, nothing.
        let legal = s.legal();
        assert_eq!(s.click(legal.len()).unwrap(), Effect::Nothing);
        assert_eq!(s.click(1).unwrap(), Effect::Selected(1));
        assert_eq!(s.click(1).unwrap(), Effect::Played(legal[1]));
        assert_eq!(s.handle(Key::Char('q')).unwrap(), Effect::Quit);
    }

    #[test]
    fn a_game_of_humans_and_bots_finishes_and_replays() {
        for seed in 0..10 {
            let mut s = Session::new(
                config("3"),
                seed,
                vec![
                    ("human".into(), Player::Human),
                    (
                        "random".into(),
                        Player::Bot(Box::new(RandomPolicy::new(seed))),
                    ),
                    ("human".into(), Player::Human),
                ],
            )
            .unwrap();
            let mut presses = 0;
            while !s.is_over() {
                if s.curtain() {
                    // The curtain hides the board: choosing is refused until revealed.
                    let a = s.game().legal_actions(s.game().current_seat())[0];
                    assert!(s.choose(a).is_err());
                    assert!(matches!(s.handle(Key::Enter).unwrap(), Effect::Revealed(_)));
                    continue;
                }
                for _ in 0..presses % 3 {
                    s.handle(Key::Down).unwrap();
                }
                assert!(matches!(s.handle(Key::Enter).unwrap(), Effect::Played(_)));
                presses += 1;
            }
            let replay = s.replay();
            assert_eq!(replay.steps.len(), s.game().steps());
            assert_eq!(replay.record().replay().unwrap(), *s.game());
            assert_eq!(s.log().len(), s.game().steps());
        }
    }
}
