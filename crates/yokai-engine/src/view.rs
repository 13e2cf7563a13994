//! [`SeatView`]: everything one seat may know, and nothing else.
//!
//! Policies (scripted bots, networks, people) receive a `SeatView`, never a [`Game`]. It
//! wraps the game privately and offers only public facts and the seat's own colour
//! knowledge, so a policy cannot read a hidden colour by construction: there is no method
//! that would return one.

use crate::action::Action;
use crate::bitboard::Cell;
use crate::config::Config;
use crate::game::{Game, Phase, Substep};
use crate::observation::{BufferError, Part, Scalar};
use crate::types::{Card, Colour, ColourSet, HintSlot, Seat};

/// What `seat` is allowed to see of a game.
#[derive(Clone, Copy)]
pub struct SeatView<'a> {
    game: &'a Game,
    seat: Seat,
}

impl Game {
    /// The view of one seat, for policies.
    pub fn view(&self, seat: Seat) -> SeatView<'_> {
        SeatView { game: self, seat }
    }
}

impl<'a> SeatView<'a> {
    pub fn seat(&self) -> Seat {
        self.seat
    }
    pub fn config(&self) -> &Config {
        self.game.config()
    }
    pub fn is_my_turn(&self) -> bool {
        !self.game.is_over() && self.game.current_seat() == self.seat
    }
    pub fn current_seat(&self) -> Seat {
        self.game.current_seat()
    }
    pub fn substep(&self) -> Substep {
        self.game.substep()
    }
    pub fn phase(&self) -> Phase {
        self.game.phase()
    }
    pub fn steps(&self) -> usize {
        self.game.steps()
    }
    pub fn cell_of(&self, card: Card) -> Cell {
        self.game.cell_of(card)
    }
    pub fn card_at(&self, cell: Cell) -> Option<Card> {
        self.game.card_at(cell)
    }
    pub fn hint_on(&self, card: Card) -> Option<HintSlot> {
        self.game.hint_on(card)
    }
    pub fn is_hinted(&self, card: Card) -> bool {
        self.game.is_hinted(card)
    }
    pub fn hint_card(&self, slot: HintSlot) -> Option<Card> {
        self.game.hint_card(slot)
    }
    /// A hint's colours once it is face up.
    pub fn revealed_hint(&self, slot: HintSlot) -> Option<ColourSet> {
        self.game.revealed_hint(slot)
    }
    pub fn face_down(&self) -> usize {
        self.game.face_down()
    }
    /// Cards the acting seat observed this turn (public: everyone sees which).
    pub fn turn_observed(&self) -> u32 {
        self.game.turn_observed()
    }
    pub fn last_action(&self) -> Option<(Seat, Action)> {
        self.game.last_action()
    }
    /// Mask of the cards whose colour this seat sees now.
    pub fn known_cards(&self) -> u32 {
        self.game.known_cards(self.seat)
    }
    /// The colour of a card, if this seat sees it now.
    pub fn known_colour(&self, card: Card) -> Option<Colour> {
        (self.known_cards() & card.bit() != 0).then(|| self.game.colour_of(card))
    }
    pub fn legal_actions(&self) -> Vec<Action> {
        self.game.legal_actions(self.seat)
    }
    pub fn for_each_legal(&self, f: impl FnMut(Action)) {
        self.game.for_each_legal(self.seat, f)
    }
    pub fn write_legal_mask<T: Scalar>(&self, out: &mut [T]) {
        self.game.write_legal_mask(self.seat, out)
    }
    pub fn write_image<T: Scalar>(&self, part: Part, out: &mut [T]) -> Result<(), BufferError> {
        self.game.write_image(self.seat, part, out)
    }
    pub fn write_nodes<T: Scalar>(&self, part: Part, out: &mut [T]) -> Result<(), BufferError> {
        self.game.write_nodes(self.seat, part, out)
    }
    pub fn write_adjacency<T: Scalar>(&self, out: &mut [T]) -> Result<(), BufferError> {
        self.game.write_adjacency(out)
    }
    /// The board rendered with this seat's knowledge.
    pub fn render(&self) -> String {
        crate::render::render_seat(self.game, self.seat)
    }
}
