//! The state of one game and its transition function (RULES §2).
//!
//! [`Game`] is a plain `Copy`-free value of a few hundred bytes with fixed-size arrays, so a
//! batched environment can keep thousands of them contiguous and step them without touching
//! the heap. Every card set is a `u32` mask over card ids and the board is a [`Bitboard`].

use crate::action::{Action, IndexOutOfRange};
use crate::bitboard::{Bitboard, Cell};
use crate::config::{Config, Memory};
use crate::deal::{Deal, DealError};
use crate::types::{
    Card, CardSet, Colour, ColourSet, HintSlot, Seat, MAX_CARDS, MAX_COLOURS, MAX_HINTS,
    MAX_PLAYERS,
};

/// Marks "no card" in hint-slot tables.
pub(crate) const NO_CARD: u8 = u8::MAX;

/// Which of the four substeps of a turn the acting seat is in.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
pub enum Substep {
    /// OBSERVE an unhinted card, or END the game.
    FirstObserve = 0,
    /// OBSERVE a second, different unhinted card.
    SecondObserve = 1,
    /// MOVE an unhinted card (NOOP when no card can move).
    Move = 2,
    /// REVEAL the next hint or PLACE a revealed one.
    Hint = 3,
}

impl Substep {
    fn from_index(i: u8) -> Substep {
        match i {
            0 => Substep::FirstObserve,
            1 => Substep::SecondObserve,
            2 => Substep::Move,
            _ => Substep::Hint,
        }
    }
    pub fn index(self) -> usize {
        self as usize
    }
    fn allowed(self) -> &'static str {
        match self {
            Substep::FirstObserve => "OBSERVE or END",
            Substep::SecondObserve => "OBSERVE",
            Substep::Move => "MOVE (or NOOP when no card can move)",
            Substep::Hint => "REVEAL or PLACE",
        }
    }
}

/// Whether the game goes on, and how it ended.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
pub enum Phase {
    Playing,
    /// A player chose END at substep 0.
    EndedEarly,
    /// The last hint was placed.
    Finished,
}

/// Why an action is not legal now. The messages finish the sentence
/// "seat 1 cannot play `observe card 3`: …".
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Illegal {
    #[error("the game is over")]
    GameOver,
    #[error("it is {acting}'s turn; other seats must submit NOOP")]
    NotYourTurn { acting: Seat },
    #[error("substep {substep} allows only {allowed}")]
    WrongSubstep { substep: u8, allowed: &'static str },
    #[error("NOOP is legal for the acting seat only when no card can move")]
    NoopNotAllowed,
    #[error("there is no such card in this configuration ({cards} cards)")]
    NoSuchCard { cards: u8 },
    #[error("the card carries a hint and is locked")]
    CardHinted,
    #[error("the card was already observed this turn; the second OBSERVE must name another card")]
    ObservedTwice,
    #[error("the cell is outside the {side}×{side} grid")]
    OffGrid { side: u8 },
    #[error("the card is already on that cell; a MOVE must change the card's cell")]
    SameCell,
    #[error("the cell is occupied by another card")]
    CellOccupied,
    #[error("afterwards the cards would not form one 4-connected group")]
    Disconnects,
    #[error("no face-down hint is left to reveal")]
    NoFaceDownHint,
    #[error("there is no hint slot {slot} in this configuration")]
    NoSuchHint { slot: u8 },
    #[error("that hint is still face-down; REVEAL it first")]
    HintFaceDown,
    #[error("that hint is already placed")]
    HintPlaced,
}

/// An action the engine refused; the state is unchanged.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ActionError {
    #[error("{seat} cannot play `{action}`: {reason}")]
    Illegal {
        seat: Seat,
        action: Action,
        reason: Illegal,
    },
    #[error("{seat}: {source}")]
    Index {
        seat: Seat,
        #[source]
        source: IndexOutOfRange,
    },
    #[error("expected one action per seat ({expected}), got {got}")]
    WrongCount { expected: usize, got: usize },
    #[error("there is no {seat} in a {players}-player game")]
    NoSuchSeat { seat: Seat, players: usize },
}

/// Why a hand-made layout was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LayoutError {
    #[error(transparent)]
    Deal(#[from] DealError),
    #[error("the layout places {got} cards but the config has {expected}")]
    CardCount { expected: usize, got: usize },
    #[error("card {card} is placed on {cell}, outside the grid")]
    OffGrid { card: usize, cell: Cell },
    #[error("cards {other} and {card} are both placed on {cell}")]
    Overlap {
        card: usize,
        other: usize,
        cell: Cell,
    },
    #[error("the cards do not form one 4-connected group")]
    NotConnected,
}

/// What one environment step returns.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Step {
    /// The game reward: 0 until the terminal step, then R (RULES §4).
    pub reward: i32,
    /// The shaping reward of this step, shared by all seats (RULES §4).
    pub shaping: i32,
    pub done: bool,
}

/// One game of Yōkai.
#[derive(Clone, PartialEq, Eq)]
pub struct Game {
    pub(crate) config: Config,
    /// Bit index of the cell of each card.
    pub(crate) cell_of: [u8; MAX_CARDS],
    pub(crate) occupied: Bitboard,
    pub(crate) colour_of: [Colour; MAX_CARDS],
    /// The cards of each colour.
    pub(crate) colour_cards: [CardSet; MAX_COLOURS],
    pub(crate) hint_colours: [ColourSet; MAX_HINTS],
    /// Slots `0..revealed` are face up.
    pub(crate) revealed: u8,
    /// The card each slot is placed on, or `NO_CARD`.
    pub(crate) hint_card: [u8; MAX_HINTS],
    pub(crate) placed: u8,
    /// The slot placed on each card (meaningful only for cards in `hinted`).
    pub(crate) card_hint: [u8; MAX_CARDS],
    pub(crate) hinted: CardSet,
    /// Cards each seat has observed at least once this episode.
    pub(crate) ever_observed: [CardSet; MAX_PLAYERS],
    /// Cards the acting seat has observed in this turn.
    pub(crate) turn_observed: CardSet,
    pub(crate) current: u8,
    pub(crate) substep: u8,
    pub(crate) steps: u16,
    pub(crate) phase: Phase,
    pub(crate) last_action: Option<(Seat, Action)>,
}

impl Game {
    /// A new game dealt from a seed.
    pub fn new(config: Config, seed: u64) -> Game {
        let (cards, hints) = crate::deal::draw(&config, seed);
        Game::from_valid_deal(config, &cards[..config.cards()], &hints[..config.hints()])
    }

    /// A new game from an explicit deal (validated against the config).
    pub fn from_deal(config: Config, deal: &Deal) -> Result<Game, DealError> {
        deal.validate(&config)?;
        Ok(Game::from_valid_deal(
            config,
            &deal.card_colours,
            &deal.hint_colours,
        ))
    }

    /// A new game from an explicit deal with the cards on explicit cells instead of the
    /// start square: for hand-made scenarios and tests. The cells must be distinct, on the
    /// grid and form one 4-connected group.
    pub fn from_layout(config: Config, deal: &Deal, cells: &[Cell]) -> Result<Game, LayoutError> {
        let mut game = Game::from_deal(config, deal)?;
        if cells.len() != config.cards() {
            return Err(LayoutError::CardCount {
                expected: config.cards(),
                got: cells.len(),
            });
        }
        let geo = *config.geometry();
        let mut occupied = Bitboard::EMPTY;
        for (k, &cell) in cells.iter().enumerate() {
            if !geo.contains(cell) {
                return Err(LayoutError::OffGrid { card: k, cell });
            }
            let index = geo.index(cell);
            if occupied.contains(index) {
                let other = cells.iter().position(|&c| c == cell).unwrap_or(k);
                return Err(LayoutError::Overlap {
                    card: k,
                    other,
                    cell,
                });
            }
            occupied |= Bitboard::from_index(index);
            game.cell_of[k] = index as u8;
        }
        if !geo.is_connected(occupied) {
            return Err(LayoutError::NotConnected);
        }
        game.occupied = occupied;
        Ok(game)
    }

    fn from_valid_deal(
        config: Config,
        card_colours: &[Colour],
        hint_colours: &[ColourSet],
    ) -> Game {
        let geo = *config.geometry();
        let (row0, col0, side) = config.start_square();
        let mut cell_of = [0u8; MAX_CARDS];
        let mut occupied = Bitboard::EMPTY;
        for (k, cell) in cell_of[..config.cards()].iter_mut().enumerate() {
            let index = geo.index(Cell::new(row0 + k / side, col0 + k % side));
            *cell = index as u8;
            occupied |= Bitboard::from_index(index);
        }
        let mut hints = [ColourSet(0); MAX_HINTS];
        hints[..config.hints()].copy_from_slice(hint_colours);
        let mut game = Game {
            config,
            cell_of,
            occupied,
            colour_of: [Colour(0); MAX_CARDS],
            colour_cards: [CardSet::EMPTY; MAX_COLOURS],
            hint_colours: hints,
            revealed: 0,
            hint_card: [NO_CARD; MAX_HINTS],
            placed: 0,
            card_hint: [0; MAX_CARDS],
            hinted: CardSet::EMPTY,
            ever_observed: [CardSet::EMPTY; MAX_PLAYERS],
            turn_observed: CardSet::EMPTY,
            current: 0,
            substep: 0,
            steps: 0,
            phase: Phase::Playing,
            last_action: None,
        };
        game.set_card_colours(card_colours);
        game
    }

    /// Card `k` gets colour `card_colours[k]`: its colour and its colour's card set (the
    /// caller has validated the colours against the config).
    pub(crate) fn set_card_colours(&mut self, card_colours: &[Colour]) {
        self.colour_cards = [CardSet::EMPTY; MAX_COLOURS];
        for (k, &colour) in card_colours.iter().enumerate() {
            self.colour_of[k] = colour;
            self.colour_cards[colour.index()].insert(Card(k as u8));
        }
    }

    /// The deal this game started from (card colours never change; hint colours neither).
    pub fn deal(&self) -> Deal {
        Deal {
            card_colours: self.colour_of[..self.config.cards()].to_vec(),
            hint_colours: self.hint_colours[..self.config.hints()].to_vec(),
        }
    }

    // --- public state ------------------------------------------------------------------

    #[inline(always)]
    pub fn config(&self) -> &Config {
        &self.config
    }
    #[inline(always)]
    pub fn current_seat(&self) -> Seat {
        Seat(self.current)
    }
    #[inline(always)]
    pub fn substep(&self) -> Substep {
        Substep::from_index(self.substep)
    }
    #[inline(always)]
    pub fn phase(&self) -> Phase {
        self.phase
    }
    #[inline(always)]
    pub fn is_over(&self) -> bool {
        self.phase != Phase::Playing
    }
    /// Steps taken so far (one per substep, END included).
    #[inline(always)]
    pub fn steps(&self) -> usize {
        self.steps as usize
    }
    pub fn cell_of(&self, card: Card) -> Cell {
        self.config
            .geometry()
            .cell(self.cell_of[card.index()] as usize)
    }
    /// The card on a cell, if any.
    pub fn card_at(&self, cell: Cell) -> Option<Card> {
        let index = self.config.geometry().index(cell) as u8;
        (0..self.config.cards() as u8)
            .map(Card)
            .find(|c| self.cell_of[c.index()] == index)
    }
    #[inline(always)]
    pub fn occupied(&self) -> Bitboard {
        self.occupied
    }
    /// The cards carrying a hint.
    #[inline(always)]
    pub fn hinted_cards(&self) -> CardSet {
        self.hinted
    }
    pub fn is_hinted(&self, card: Card) -> bool {
        self.hinted.contains(card)
    }
    /// The hint slot placed on a card.
    pub fn hint_on(&self, card: Card) -> Option<HintSlot> {
        self.is_hinted(card)
            .then(|| HintSlot(self.card_hint[card.index()]))
    }
    /// Number of face-down hints left.
    pub fn face_down(&self) -> usize {
        self.config.hints() - self.revealed as usize
    }
    /// Number of revealed hints not yet placed.
    pub fn revealed_unplaced(&self) -> usize {
        (self.revealed - self.placed) as usize
    }
    /// Colours of a hint slot once it is face up (public); `None` while face down.
    pub fn revealed_hint(&self, slot: HintSlot) -> Option<ColourSet> {
        (slot.0 < self.revealed).then(|| self.hint_colours[slot.index()])
    }
    /// The card a hint slot is placed on.
    pub fn hint_card(&self, slot: HintSlot) -> Option<Card> {
        let c = self.hint_card[slot.index()];
        (c != NO_CARD).then_some(Card(c))
    }
    /// Cards the acting seat observed in this turn (public: everyone sees which).
    pub fn turn_observed(&self) -> CardSet {
        self.turn_observed
    }
    /// The last action taken, and by whom.
    pub fn last_action(&self) -> Option<(Seat, Action)> {
        self.last_action
    }

    /// Cards whose colour `seat` sees now, by the memory mode (RULES §5).
    #[inline(always)]
    pub fn known_cards(&self, seat: Seat) -> CardSet {
        match self.config.memory() {
            Memory::Perfect => self.ever_observed[seat.index()],
            Memory::Imperfect if seat.0 == self.current => self.turn_observed,
            Memory::Imperfect => CardSet::EMPTY,
        }
    }

    /// Cards `seat` has observed at least once this episode, whatever the memory mode.
    pub fn ever_observed(&self, seat: Seat) -> CardSet {
        self.ever_observed[seat.index()]
    }

    // --- hidden state ------------------------------------------------------------------

    /// The true colour of a card. Hidden information: policies must not call this (the
    /// `SeatView` they receive does not offer it).
    #[inline(always)]
    pub fn colour_of(&self, card: Card) -> Colour {
        self.colour_of[card.index()]
    }
    /// The cards of a colour (hidden information).
    pub fn cards_of_colour(&self, colour: Colour) -> CardSet {
        self.colour_cards[colour.index()]
    }
    /// Colours of any hint slot, face down or not (hidden information).
    pub fn hint_colours(&self, slot: HintSlot) -> ColourSet {
        self.hint_colours[slot.index()]
    }

    // --- legality ----------------------------------------------------------------------

    /// Is `action` legal for `seat` now? `Err` says why not.
    pub fn check(&self, seat: Seat, action: Action) -> Result<(), Illegal> {
        if self.is_over() {
            return Err(Illegal::GameOver);
        }
        if seat.0 != self.current {
            return match action {
                Action::Noop => Ok(()),
                _ => Err(Illegal::NotYourTurn {
                    acting: self.current_seat(),
                }),
            };
        }
        let cards = self.config.cards();
        let card_ok = |card: Card| -> Result<(), Illegal> {
            if card.index() >= cards {
                Err(Illegal::NoSuchCard { cards: cards as u8 })
            } else if self.hinted.contains(card) {
                Err(Illegal::CardHinted)
            } else {
                Ok(())
            }
        };
        let substep = self.substep();
        match (substep, action) {
            (Substep::FirstObserve, Action::End) => Ok(()),
            (Substep::FirstObserve, Action::Observe(card)) => card_ok(card),
            (Substep::SecondObserve, Action::Observe(card)) => {
                card_ok(card)?;
                if self.turn_observed.contains(card) {
                    Err(Illegal::ObservedTwice)
                } else {
                    Ok(())
                }
            }
            (Substep::Move, Action::Move(card, cell)) => {
                card_ok(card)?;
                let geo = self.config.geometry();
                if !geo.contains(cell) {
                    return Err(Illegal::OffGrid {
                        side: geo.side() as u8,
                    });
                }
                let to = geo.index(cell);
                if to == self.cell_of[card.index()] as usize {
                    return Err(Illegal::SameCell);
                }
                if self.occupied.contains(to) {
                    return Err(Illegal::CellOccupied);
                }
                if !self.move_targets(card).contains(to) {
                    return Err(Illegal::Disconnects);
                }
                Ok(())
            }
            (Substep::Move, Action::Noop) => {
                if self.any_move() {
                    Err(Illegal::NoopNotAllowed)
                } else {
                    Ok(())
                }
            }
            (Substep::Hint, Action::Reveal) => {
                if self.face_down() == 0 {
                    Err(Illegal::NoFaceDownHint)
                } else {
                    Ok(())
                }
            }
            (Substep::Hint, Action::Place(slot, card)) => {
                if slot.index() >= self.config.hints() {
                    return Err(Illegal::NoSuchHint { slot: slot.0 });
                }
                if slot.0 >= self.revealed {
                    return Err(Illegal::HintFaceDown);
                }
                if self.hint_card[slot.index()] != NO_CARD {
                    return Err(Illegal::HintPlaced);
                }
                card_ok(card)
            }
            (_, Action::Noop) => Err(Illegal::NoopNotAllowed),
            _ => Err(Illegal::WrongSubstep {
                substep: self.substep,
                allowed: substep.allowed(),
            }),
        }
    }

    /// Is `action` legal for the acting seat?
    pub fn is_legal(&self, action: Action) -> bool {
        self.check(self.current_seat(), action).is_ok()
    }

    // --- transitions -------------------------------------------------------------------

    /// Play `action` for the acting seat. An illegal action leaves the game untouched.
    pub fn apply(&mut self, action: Action) -> Result<Step, ActionError> {
        let seat = self.current_seat();
        self.check(seat, action)
            .map_err(|reason| ActionError::Illegal {
                seat,
                action,
                reason,
            })?;
        Ok(self.apply_unchecked(action))
    }

    /// Play an action given by its index for the acting seat.
    pub fn apply_index(&mut self, index: usize) -> Result<Step, ActionError> {
        let seat = self.current_seat();
        let action = self
            .config
            .decode(index)
            .map_err(|source| ActionError::Index { seat, source })?;
        self.apply(action)
    }

    /// The simultaneous-action API (RULES §2): one action per seat, NOOP for every seat but
    /// the acting one. All actions are checked before anything changes.
    pub fn step_joint(&mut self, actions: &[Action]) -> Result<Step, ActionError> {
        if actions.len() != self.config.players() {
            return Err(ActionError::WrongCount {
                expected: self.config.players(),
                got: actions.len(),
            });
        }
        for (i, &action) in actions.iter().enumerate() {
            let seat = Seat(i as u8);
            self.check(seat, action)
                .map_err(|reason| ActionError::Illegal {
                    seat,
                    action,
                    reason,
                })?;
        }
        Ok(self.apply_unchecked(actions[self.current as usize]))
    }

    /// [`Game::step_joint`] with action indices.
    pub fn step_joint_indices(&mut self, indices: &[usize]) -> Result<Step, ActionError> {
        if indices.len() != self.config.players() {
            return Err(ActionError::WrongCount {
                expected: self.config.players(),
                got: indices.len(),
            });
        }
        let mut actions = [Action::Noop; MAX_PLAYERS];
        for (i, &index) in indices.iter().enumerate() {
            actions[i] = self
                .config
                .decode(index)
                .map_err(|source| ActionError::Index {
                    seat: Seat(i as u8),
                    source,
                })?;
        }
        self.step_joint(&actions[..indices.len()])
    }

    /// Play an action already known to be legal for the acting seat (checked in debug
    /// builds). Batched environments use this after validating against the legal mask.
    pub fn apply_unchecked(&mut self, action: Action) -> Step {
        debug_assert!(self.is_legal(action), "illegal {action} in\n{self:?}");
        let seat = self.current as usize;
        let mut shaping = 0;
        self.steps += 1;
        self.last_action = Some((Seat(self.current), action));
        match action {
            Action::End => self.phase = Phase::EndedEarly,
            Action::Observe(card) => {
                if !self.ever_observed[seat].contains(card) {
                    shaping += 1;
                }
                self.ever_observed[seat].insert(card);
                self.turn_observed.insert(card);
                self.substep += 1;
            }
            Action::Move(card, cell) => {
                let to = self.config.geometry().index(cell);
                let from = self.cell_of[card.index()] as usize;
                self.occupied ^= Bitboard::from_index(from) | Bitboard::from_index(to);
                self.cell_of[card.index()] = to as u8;
                self.substep = 3;
            }
            Action::Noop => self.substep = 3,
            Action::Reveal => {
                self.revealed += 1;
                self.end_turn();
            }
            Action::Place(slot, card) => {
                self.hint_card[slot.index()] = card.0;
                self.card_hint[card.index()] = slot.0;
                self.hinted.insert(card);
                self.placed += 1;
                if self.hint_colours[slot.index()].contains(self.colour_of[card.index()]) {
                    shaping += 1;
                }
                if self.placed as usize == self.config.hints() {
                    // The last PLACE ends the placer's turn as well as the game (RULES §2):
                    // with imperfect memory its final view no longer shows this turn's
                    // colours (RULES §5). The seat to act stays the placer's.
                    self.turn_observed = CardSet::EMPTY;
                    self.phase = Phase::Finished;
                } else {
                    self.end_turn();
                }
            }
        }
        let done = self.is_over();
        Step {
            reward: if done { self.outcome_reward() } else { 0 },
            shaping,
            done,
        }
    }

    fn end_turn(&mut self) {
        self.turn_observed = CardSet::EMPTY;
        self.substep = 0;
        self.current = (self.current + 1) % self.config.players() as u8;
    }

    /// All legal actions of a seat, in index order (NOOP alone for a non-acting seat,
    /// nothing once the game is over). Convenient, allocates; batched code writes masks.
    pub fn legal_actions(&self, seat: Seat) -> Vec<Action> {
        let mut out = Vec::new();
        self.for_each_legal(seat, |a| out.push(a));
        out
    }

    /// The cards without a hint.
    #[inline(always)]
    pub fn unhinted(&self) -> CardSet {
        CardSet::first(self.config.cards()) & !self.hinted
    }

    /// Mask of revealed, unplaced hint slots.
    #[inline(always)]
    pub(crate) fn placeable_slots(&self) -> u16 {
        let mut m = 0u16;
        for slot in 0..self.revealed as usize {
            if self.hint_card[slot] == NO_CARD {
                m |= 1 << slot;
            }
        }
        m
    }
}
