//! [`PublicView`] and [`SeatView`]: what everyone may know, and what one seat may know.
//!
//! Policies (scripted bots, networks, people) receive a `SeatView`, never a [`Game`]. It
//! wraps the game privately and offers only public facts and the seat's own colour
//! knowledge, so a policy cannot read a hidden colour by construction: there is no method
//! that would return one. A `PublicView` offers the public facts alone; conventions that
//! partners must be able to re-derive (what would seat s do if the cards were coloured so?)
//! take one, so that they cannot depend on anything private by accident.

use crate::action::Action;
use crate::bitboard::{Bitboard, Cell};
use crate::config::Config;
use crate::game::{Game, Phase, Substep};
use crate::observation::{BufferError, ImageLayout, Part, Scalar};
use crate::types::{Card, CardSet, Colour, ColourSet, HintSlot, Seat};

/// The public facts of a game (RULES §5): positions, hints, turns, which cards were
/// observed by whom. No colour of any card.
#[derive(Clone, Copy)]
pub struct PublicView<'a> {
    game: &'a Game,
}

/// What `seat` is allowed to see of a game: the public facts (through `Deref`) plus the
/// colours this seat sees now.
#[derive(Clone, Copy)]
pub struct SeatView<'a> {
    public: PublicView<'a>,
    seat: Seat,
}

impl Game {
    /// The view of one seat, for policies.
    pub fn view(&self, seat: Seat) -> SeatView<'_> {
        SeatView {
            public: self.public_view(),
            seat,
        }
    }

    /// The public facts only.
    pub fn public_view(&self) -> PublicView<'_> {
        PublicView { game: self }
    }
}

impl<'a> PublicView<'a> {
    pub fn config(&self) -> &Config {
        self.game.config()
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
    pub fn is_over(&self) -> bool {
        self.game.is_over()
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
    pub fn occupied(&self) -> Bitboard {
        self.game.occupied()
    }
    /// The cards on the (up to four) cells that share a side with `cell`.
    pub fn cards_around(&self, cell: Cell) -> impl Iterator<Item = Card> + 'a {
        let game = self.game;
        let side = game.config().grid() as i32;
        [(-1, 0), (1, 0), (0, -1), (0, 1)]
            .into_iter()
            .filter_map(move |(dr, dc): (i32, i32)| {
                let (r, c) = (cell.row as i32 + dr, cell.col as i32 + dc);
                if r < 0 || c < 0 || r >= side || c >= side {
                    return None;
                }
                game.card_at(Cell::new(r as usize, c as usize))
            })
    }
    pub fn hint_on(&self, card: Card) -> Option<HintSlot> {
        self.game.hint_on(card)
    }
    pub fn is_hinted(&self, card: Card) -> bool {
        self.game.is_hinted(card)
    }
    /// Mask of the cards that carry a hint.
    pub fn hinted_cards(&self) -> CardSet {
        self.game.hinted_cards()
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
    pub fn revealed_unplaced(&self) -> usize {
        self.game.revealed_unplaced()
    }
    /// Cards the acting seat observed this turn (public: everyone sees which).
    pub fn turn_observed(&self) -> CardSet {
        self.game.turn_observed()
    }
    pub fn last_action(&self) -> Option<(Seat, Action)> {
        self.game.last_action()
    }
    /// Which cards `seat` sees the colour of now (public: observations are seen by all,
    /// and the memory mode is part of the config). Not their colours.
    pub fn known_cards_of(&self, seat: Seat) -> CardSet {
        self.game.known_cards(seat)
    }
    /// Cards `seat` has observed at least once this episode.
    pub fn ever_observed(&self, seat: Seat) -> CardSet {
        self.game.ever_observed(seat)
    }
    /// Legal actions of `seat`, in index order (legality depends on public facts only).
    pub fn for_each_legal_of(&self, seat: Seat, f: impl FnMut(Action)) {
        self.game.for_each_legal(seat, f)
    }
    pub fn is_legal_for(&self, seat: Seat, action: Action) -> bool {
        self.game.check(seat, action).is_ok()
    }
}

impl<'a> std::ops::Deref for SeatView<'a> {
    type Target = PublicView<'a>;
    fn deref(&self) -> &PublicView<'a> {
        &self.public
    }
}

impl<'a> SeatView<'a> {
    pub fn seat(&self) -> Seat {
        self.seat
    }
    /// The public part of this view.
    pub fn public(&self) -> PublicView<'a> {
        self.public
    }
    pub fn is_my_turn(&self) -> bool {
        !self.game().is_over() && self.game().current_seat() == self.seat
    }
    fn game(&self) -> &'a Game {
        self.public.game
    }
    /// The cards whose colour this seat sees now.
    pub fn known_cards(&self) -> CardSet {
        self.game().known_cards(self.seat)
    }
    /// The colour of a card, if this seat sees it now.
    pub fn known_colour(&self, card: Card) -> Option<Colour> {
        self.known_cards()
            .contains(card)
            .then(|| self.game().colour_of(card))
    }
    pub fn legal_actions(&self) -> Vec<Action> {
        self.game().legal_actions(self.seat)
    }
    pub fn for_each_legal(&self, f: impl FnMut(Action)) {
        self.game().for_each_legal(self.seat, f)
    }
    pub fn write_legal_mask<T: Scalar>(&self, out: &mut [T]) {
        self.game().write_legal_mask(self.seat, out)
    }
    pub fn write_image<T: Scalar>(&self, part: Part, out: &mut [T]) -> Result<(), BufferError> {
        self.game().write_image(self.seat, part, out)
    }
    pub fn write_image_in<T: Scalar>(
        &self,
        part: Part,
        layout: ImageLayout,
        out: &mut [T],
    ) -> Result<(), BufferError> {
        self.game().write_image_in(self.seat, part, layout, out)
    }
    pub fn write_nodes<T: Scalar>(&self, part: Part, out: &mut [T]) -> Result<(), BufferError> {
        self.game().write_nodes(self.seat, part, out)
    }
    pub fn write_adjacency<T: Scalar>(&self, out: &mut [T]) -> Result<(), BufferError> {
        self.game().write_adjacency(out)
    }
    /// The board rendered with this seat's knowledge.
    pub fn render(&self) -> String {
        crate::render::render_seat(self.game(), self.seat)
    }
}
