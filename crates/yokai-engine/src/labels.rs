//! Colours named by the order in which a seat first saw them ("first-seen" labels).
//!
//! Why: Yōkai's colours are interchangeable, so a convention tied to a colour's dealt name
//! ("a red hint on a card means …") is one that a policy trained apart has no reason to
//! share. Other-Play trains against such conventions by showing each seat its game under a
//! random colour permutation, at the price of learning every colour's role under every
//! name. A policy that reads colours by the order it first saw them cannot tie anything to
//! a dealt name at all: permuting the deal's colours changes nothing it sees (the property
//! test below), so every such policy is invariant under colour permutations by
//! construction.
//!
//! The labels depend on the seat's history, not only on what it sees now, so the caller
//! keeps one [`ColourLabels`] per seat and calls [`ColourLabels::update`] after every step
//! of the game, before it writes that step's observation. A seat first sees a colour when
//! it observes a card of that colour or when a hint showing it is revealed. Colours first
//! seen at the same step (a hint tile of two or three colours) are ordered by a random
//! rank drawn per episode: any fixed rule would order them by their dealt names again.
//! Colours not yet seen take the labels after the seen ones, in the same random rank: the
//! seat's observation shows nothing of them, so only a target that names every card's
//! true colour (a belief model's) reads those labels.

use crate::config::Config;
use crate::deal::derive_seed;
use crate::symmetry::Symmetry;
use crate::types::{Colour, ColourSet, HintSlot, MAX_COLOURS};
use crate::view::SeatView;

/// One seat's colour labels in one episode: which colours it has seen, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ColourLabels {
    /// The colours in the order the seat first saw them (the first `seen` entries), then
    /// the unseen ones in rank order (recomputed by [`ColourLabels::update`]).
    order: [u8; MAX_COLOURS],
    seen: u8,
    /// The colours in their random rank: the order among colours first seen together.
    rank: [u8; MAX_COLOURS],
    colours: u8,
}

impl ColourLabels {
    /// Labels for a new episode of a game of `config`, nothing seen yet; `seed` draws the
    /// rank that orders colours first seen together.
    pub fn new(config: &Config, seed: u64) -> ColourLabels {
        let c = config.colours();
        let mut rank = [0u8; MAX_COLOURS];
        for (i, r) in rank.iter_mut().enumerate() {
            *r = i as u8;
        }
        // Fisher–Yates over 0..c, one derived draw per position.
        for i in (1..c).rev() {
            let j = (derive_seed(seed, i as u64) % (i as u64 + 1)) as usize;
            rank.swap(i, j);
        }
        ColourLabels::with_rank(c, rank)
    }

    /// Labels whose ties are broken by `rank` (the first `colours` entries a permutation of
    /// `0..colours`).
    fn with_rank(colours: usize, rank: [u8; MAX_COLOURS]) -> ColourLabels {
        ColourLabels {
            order: rank,
            seen: 0,
            rank,
            colours: colours as u8,
        }
    }

    /// Note the colours the seat of `view` sees now that it had not seen before (call
    /// after every step of the episode, and once at its start: with imperfect memory a
    /// card's colour shows only in the turn it is observed).
    pub fn update(&mut self, view: &SeatView<'_>) {
        let mut now = 0u8;
        for card in view.known_cards().iter() {
            if let Some(colour) = view.known_colour(card) {
                now |= 1 << colour.0;
            }
        }
        let public = view.public();
        for slot in 0..view.config().hints() {
            match public.revealed_hint(HintSlot(slot as u8)) {
                Some(ColourSet(set)) => now |= set,
                None => break,
            }
        }
        let c = self.colours as usize;
        let mut known = 0u8;
        for &colour in &self.order[..self.seen as usize] {
            known |= 1 << colour;
        }
        let new = now & !known;
        if new == 0 {
            return;
        }
        let mut at = self.seen as usize;
        for &colour in &self.rank[..c] {
            if new & (1 << colour) != 0 {
                self.order[at] = colour;
                at += 1;
            }
        }
        self.seen = at as u8;
        let known = known | new;
        for &colour in &self.rank[..c] {
            if known & (1 << colour) == 0 {
                self.order[at] = colour;
                at += 1;
            }
        }
    }

    /// These labels' tie rank with nothing seen: what [`ColourLabels::new`] gave at the
    /// start of the episode.
    pub fn restart(&self) -> ColourLabels {
        ColourLabels::with_rank(self.colours as usize, self.rank)
    }

    /// How many colours the seat has seen.
    pub fn seen(&self) -> usize {
        self.seen as usize
    }

    /// The label of a true colour: its place in the order the seat first saw the colours
    /// (unseen colours after the seen ones, in rank order); `None` for a colour the
    /// config does not have.
    pub fn label(&self, colour: Colour) -> Option<Colour> {
        self.order[..self.colours as usize]
            .iter()
            .position(|&c| c == colour.0)
            .map(|at| Colour(at as u8))
    }

    /// `view` with its colour permutation replaced by these labels (its rotation and
    /// reflection kept): the symmetry that shows the seat its game with first-seen colours.
    pub fn symmetry(&self, config: &Config, view: Symmetry) -> Symmetry {
        let c = self.colours as usize;
        let mut map = [0u8; MAX_COLOURS];
        for (label, &colour) in self.order[..c].iter().enumerate() {
            map[colour as usize] = label as u8;
        }
        Symmetry::new(config, &map[..c], view.rotation(), view.reflects())
            .expect("labels are a permutation of the config's colours")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deal::Deal;
    use crate::game::Game;
    use crate::observation::{ImageLayout, Part};
    use crate::types::Seat;
    use crate::Action;
    use proptest::prelude::*;

    fn config() -> Config {
        Config::from_name("9c-2p-perfect").unwrap()
    }

    /// A game's deal with every colour renamed by `perm` (`perm[c]` is the new name of c).
    fn renamed(game: &Game, perm: &[u8]) -> Game {
        let deal = game.deal();
        let renamed = Deal {
            card_colours: deal
                .card_colours
                .iter()
                .map(|c| Colour(perm[c.index()]))
                .collect(),
            hint_colours: deal
                .hint_colours
                .iter()
                .map(|s| {
                    let mut out = 0u8;
                    for (c, &p) in perm.iter().enumerate() {
                        if s.0 & (1 << c) != 0 {
                            out |= 1 << p;
                        }
                    }
                    ColourSet(out)
                })
                .collect(),
        };
        Game::from_deal(*game.config(), &renamed).unwrap()
    }

    fn permutation(c: usize, seed: u64) -> Vec<u8> {
        let mut perm: Vec<u8> = (0..c as u8).collect();
        for i in (1..c).rev() {
            perm.swap(
                i,
                (derive_seed(seed, 100 + i as u64) % (i as u64 + 1)) as usize,
            );
        }
        perm
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Renaming the deal's colours (and the tie rank with them) changes nothing a seat
        /// sees through its first-seen labels, at any step of a random game, in both
        /// encodings; and a colour's label never changes once the seat has seen it.
        #[test]
        fn first_seen_views_do_not_depend_on_the_dealt_colour_names(deal in 0u64..1_000_000, play in any::<u64>(), rename in any::<u64>()) {
            let config = config();
            let (c, players) = (config.colours(), config.players());
            let perm = permutation(c, rename);
            let mut a = Game::new(config, deal);
            let mut b = renamed(&a, &perm);
            let labels_a: Vec<ColourLabels> = (0..players).map(|s| ColourLabels::new(&config, deal + s as u64)).collect();
            let mut labels_b = labels_a.clone();
            for l in labels_b.iter_mut() {
                for r in l.rank[..c].iter_mut() {
                    *r = perm[*r as usize];
                }
                l.order = l.rank;
            }
            let mut labels_a = labels_a;
            let identity = Symmetry::identity(&config);
            let [nodes, f] = config.node_shape(Part::Full);
            let image_len: usize = config.image_shape(Part::Full).iter().product();
            let mut step = 0u64;
            loop {
                for s in 0..players {
                    let seat = Seat(s as u8);
                    let before = labels_a[s];
                    labels_a[s].update(&a.view(seat));
                    labels_b[s].update(&b.view(seat));
                    // Seen colours keep their labels.
                    for k in 0..before.seen() {
                        let colour = Colour(before.order[k]);
                        prop_assert_eq!(labels_a[s].label(colour), before.label(colour));
                    }
                    for colour in 0..c as u8 {
                        prop_assert_eq!(
                            labels_a[s].label(Colour(colour)),
                            labels_b[s].label(Colour(perm[colour as usize]))
                        );
                    }
                    let (sym_a, sym_b) = (labels_a[s].symmetry(&config, identity), labels_b[s].symmetry(&config, identity));
                    let (mut raw_a, mut raw_b) = (vec![0f32; nodes * f], vec![0f32; nodes * f]);
                    a.write_nodes(seat, Part::Full, &mut raw_a).unwrap();
                    b.write_nodes(seat, Part::Full, &mut raw_b).unwrap();
                    let (mut view_a, mut view_b) = (raw_a.clone(), raw_b.clone());
                    sym_a.apply_nodes(&config, Part::Full, &raw_a, &mut view_a).unwrap();
                    sym_b.apply_nodes(&config, Part::Full, &raw_b, &mut view_b).unwrap();
                    prop_assert_eq!(&view_a, &view_b);
                    let (mut raw_a, mut raw_b) = (vec![0f32; image_len], vec![0f32; image_len]);
                    a.write_image_in(seat, Part::Full, ImageLayout::Chw, &mut raw_a).unwrap();
                    b.write_image_in(seat, Part::Full, ImageLayout::Chw, &mut raw_b).unwrap();
                    let (mut view_a, mut view_b) = (raw_a.clone(), raw_b.clone());
                    sym_a.apply_image_in(&config, Part::Full, ImageLayout::Chw, &raw_a, &mut view_a).unwrap();
                    sym_b.apply_image_in(&config, Part::Full, ImageLayout::Chw, &raw_b, &mut view_b).unwrap();
                    prop_assert_eq!(&view_a, &view_b);
                }
                if a.is_over() {
                    break;
                }
                let legal = a.legal_actions(a.current_seat());
                prop_assert_eq!(&legal, &b.legal_actions(b.current_seat()));
                let pick = legal[(derive_seed(play, step) % legal.len() as u64) as usize];
                a.apply(pick).unwrap();
                b.apply(pick).unwrap();
                step += 1;
            }
        }
    }

    /// The first colour a seat observes is label 0, the next new one label 1; a colour it
    /// has not seen is not labelled before the seen ones.
    #[test]
    fn labels_follow_the_order_of_first_sight() {
        let config = config();
        let mut game = Game::new(config, 7);
        let mut labels = ColourLabels::new(&config, 3);
        labels.update(&game.view(Seat(0)));
        assert_eq!(labels.seen(), 0);
        let mut order: Vec<Colour> = Vec::new();
        for card in 0..config.cards() as u8 {
            if game.is_over() || game.current_seat() != Seat(0) {
                break;
            }
            let observe = Action::Observe(crate::types::Card(card));
            if !game.is_legal(observe) {
                break;
            }
            game.apply(observe).unwrap();
            labels.update(&game.view(Seat(0)));
            let colour = game.colour_of(crate::types::Card(card));
            if !order.contains(&colour) {
                order.push(colour);
            }
            assert_eq!(labels.seen(), order.len());
            for (k, &colour) in order.iter().enumerate() {
                assert_eq!(labels.label(colour), Some(Colour(k as u8)));
            }
        }
        assert!(!order.is_empty(), "seat 0 observed no card");
        assert_eq!(labels.label(Colour(config.colours() as u8)), None);
    }
}
