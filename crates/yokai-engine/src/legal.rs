//! Legal MOVE targets, and the legal-action mask.
//!
//! A MOVE is legal when afterwards all cards form one 4-connected group. Checking that by a
//! flood fill per (card, cell) candidate costs Y·g² fills per substep. Instead we work per
//! card: take the card off the board and split the rest into its connected groups. The card
//! must land on an empty cell adjacent to *every* group (it becomes the bridge), so the legal
//! targets are the intersection of the groups' neighbourhoods, minus occupied cells and the
//! card's own cell. When the rest stays connected (the usual case) that is simply the rest's
//! neighbourhood. A card whose side neighbours are linked through the 8 cells around it (a
//! leaf, or a card inside a block) can never split the rest, so it skips the fill
//! ([`crate::bitboard::BLOCK_KEEPS_CONNECTED`], looked up by the card's 3×3 block).
//! Otherwise each group costs one bitboard flood fill (a few shift/mask rounds).

use crate::action::Action;
use crate::bitboard::{Bitboard, BLOCK_KEEPS_CONNECTED};
use crate::game::{Game, Substep};
use crate::observation::Scalar;
use crate::types::{Card, Seat};

impl Game {
    /// Empty cells `card` may move to so that all cards stay one group. Pure geometry: the
    /// caller checks that the card is unhinted.
    #[inline]
    pub fn move_targets(&self, card: Card) -> Bitboard {
        move_targets(self, self.cell_of[card.index()] as usize)
    }

    /// Whether any unhinted card has a legal move (if not, NOOP is the MOVE substep's action).
    pub fn any_move(&self) -> bool {
        self.unhinted()
            .iter()
            .any(|c| !self.move_targets(c).is_empty())
    }

    /// Write the legal-action mask of `seat` (length N_a): `ONE` for legal, `ZERO` otherwise.
    /// Allocation-free; this is what batched environments call every step.
    pub fn write_legal_mask<T: Scalar>(&self, seat: Seat, out: &mut [T]) {
        assert_eq!(
            out.len(),
            self.config.num_actions(),
            "legal mask buffer has the wrong length"
        );
        out.fill(T::ZERO);
        self.mark_legal_mask(seat, out);
    }

    /// Set the legal entries of `seat`'s mask to `ONE`, leaving the others as they are: for
    /// a buffer already zero there (see [`Game::clear_legal_mask`]).
    #[inline]
    pub fn mark_legal_mask<T: Scalar>(&self, seat: Seat, out: &mut [T]) {
        self.for_each_legal_index(seat, |i| out[i] = T::ONE);
    }

    /// The range of action indices where `seat`'s legal actions lie in this state: the
    /// action groups of the current substep for the acting seat, NOOP for the others, empty
    /// once the game is over. Outside it the mask is zero, so callers can clear or scan this
    /// range instead of all N_a entries.
    #[inline]
    pub fn legal_span(&self, seat: Seat) -> std::ops::Range<usize> {
        if self.is_over() {
            return 0..0;
        }
        if seat.0 != self.current {
            return 0..1;
        }
        let layout = self.config.action_layout();
        let y = self.config.cards();
        match self.substep() {
            Substep::FirstObserve => 1..layout.observe + y,
            Substep::SecondObserve => layout.observe..layout.observe + y,
            Substep::Move => 0..layout.reveal,
            Substep::Hint => layout.reveal..layout.len,
        }
    }

    /// Zero every entry that [`Game::write_legal_mask`] can have set to `ONE` in this state
    /// (the [`Game::legal_span`]). A batched environment calls this before an action and
    /// [`Game::mark_legal_mask`] after it, so that a mask costs the few groups that change
    /// rather than a clear of all N_a entries per seat and step.
    #[inline]
    pub fn clear_legal_mask<T: Scalar>(&self, seat: Seat, out: &mut [T]) {
        let span = self.legal_span(seat);
        if span.len() == 1 {
            // A waiting seat's NOOP, every step for every seat but one: one store instead
            // of a call to `memset`.
            out[span.start] = T::ZERO;
        } else {
            out[span].fill(T::ZERO);
        }
    }

    /// Call `f` on every legal action of `seat`, in index order.
    pub fn for_each_legal(&self, seat: Seat, mut f: impl FnMut(Action)) {
        let config = self.config;
        self.for_each_legal_index(seat, |i| f(config.decode(i).expect("legal indices decode")));
    }

    /// The one enumeration of legal actions (RULES §2), as action indices in increasing
    /// order: NOOP alone for a non-acting seat, nothing once the game is over.
    #[inline]
    pub fn for_each_legal_index(&self, seat: Seat, mut f: impl FnMut(usize)) {
        if self.is_over() {
            return;
        }
        if seat.0 != self.current {
            f(0);
            return;
        }
        let layout = self.config.action_layout();
        let free = self.unhinted();
        match self.substep() {
            Substep::FirstObserve => {
                f(1);
                free.iter().for_each(|c| f(layout.observe + c.index()));
            }
            Substep::SecondObserve => (free & !self.turn_observed)
                .iter()
                .for_each(|c| f(layout.observe + c.index())),
            Substep::Move => {
                let cells = self.config.geometry().cells();
                let mut any = false;
                for c in free.iter() {
                    let base = layout.movement + c.index() * cells;
                    for to in self.move_targets(c).iter() {
                        f(base + to);
                        any = true;
                    }
                }
                if !any {
                    f(0);
                }
            }
            Substep::Hint => {
                if self.face_down() > 0 {
                    f(layout.reveal);
                }
                let y = self.config.cards();
                let mut slots = self.placeable_slots();
                while slots != 0 {
                    let slot = slots.trailing_zeros() as usize;
                    slots &= slots - 1;
                    let base = layout.place + slot * y;
                    free.iter().for_each(|c| f(base + c.index()));
                }
            }
        }
    }
}

/// Legal targets of the card on bit `from` (see the module docs).
#[inline]
fn move_targets(game: &Game, from: usize) -> Bitboard {
    let geo = game.config.geometry();
    let own = Bitboard::from_index(from);
    let rest = game.occupied ^ own;
    let empty = geo.board() & !game.occupied;
    // A card whose side neighbours are linked around it (a leaf, or a card inside a
    // block) cannot disconnect the rest: no flood fill needed.
    if BLOCK_KEEPS_CONNECTED[geo.block(from, rest) as usize] {
        return geo.neighbours(rest) & empty;
    }
    let first = geo.flood(rest.lowest(), rest);
    let mut targets = geo.neighbours(first) & empty;
    let mut remaining = rest ^ first;
    while !remaining.is_empty() && !targets.is_empty() {
        let group = geo.flood(remaining.lowest(), remaining);
        targets &= geo.neighbours(group);
        remaining ^= group;
    }
    targets
}
