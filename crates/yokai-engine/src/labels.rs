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

/// How a seat's colours are named.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColourNaming {
    /// By the order in which the seat first saw each colour, privately or publicly. A name
    /// never changes once given; names are the seat's own (each seat first sees other
    /// cards).
    FirstSeen,
    /// The colours revealed hint tiles have shown first, by the order the tiles showed them
    /// (public: both seats see the same tiles), then the colours the seat has seen only on
    /// cards, by first sight. The public names never change and are the same for both
    /// seats wherever a tile did not show two new colours at once (those ties follow each
    /// seat's own rank); a colour seen only on cards is renamed when a tile first shows it
    /// (it takes the next public name and the private names after it move up).
    PublicFirst,
}

/// One seat's colour labels in one episode: which colours it has seen, and in what order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ColourLabels {
    /// The colours in the order the seat first saw them (the first `seen` entries).
    seen_order: [u8; MAX_COLOURS],
    seen: u8,
    /// The colours in the order revealed hint tiles first showed them (the first `shown`
    /// entries).
    shown_order: [u8; MAX_COLOURS],
    shown: u8,
    /// The colours in their random rank: the order among colours first seen together.
    rank: [u8; MAX_COLOURS],
    colours: u8,
    naming: ColourNaming,
}

impl ColourLabels {
    /// Labels for a new episode of a game of `config`, nothing seen yet; `seed` draws the
    /// rank that orders colours first seen together.
    pub fn new(config: &Config, seed: u64, naming: ColourNaming) -> ColourLabels {
        let c = config.colours();
        let mut rank = [0u8; MAX_COLOURS];
        for (i, r) in rank.iter_mut().enumerate() {
            *r = i as u8;
        }
        // Fisher–Yates over 0..c, one derived draw per position (not `deal::shuffle`'s
        // ChaCha stream: the runs measured in docs/results/first-seen-colours.md drew their
        // ranks this way, and a run is a function of its seed).
        for i in (1..c).rev() {
            let j = (derive_seed(seed, i as u64) % (i as u64 + 1)) as usize;
            rank.swap(i, j);
        }
        ColourLabels::with_rank(c, rank, naming)
    }

    /// Labels whose ties are broken by `rank` (the first `colours` entries a permutation of
    /// `0..colours`).
    fn with_rank(colours: usize, rank: [u8; MAX_COLOURS], naming: ColourNaming) -> ColourLabels {
        ColourLabels {
            seen_order: rank,
            seen: 0,
            shown_order: rank,
            shown: 0,
            rank,
            colours: colours as u8,
            naming,
        }
    }

    /// Note the colours the seat of `view` sees now that it had not seen before (call
    /// after every step of the episode, and once at its start: with imperfect memory a
    /// card's colour shows only in the turn it is observed). Returns whether any was new:
    /// only then can the names change, so a caller that keeps the names' [`Symmetry`]
    /// rebuilds it only then.
    pub fn update(&mut self, view: &SeatView<'_>) -> bool {
        let mut on_cards = 0u8;
        for card in view.known_cards().iter() {
            if let Some(colour) = view.known_colour(card) {
                on_cards |= 1 << colour.0;
            }
        }
        let mut on_tiles = 0u8;
        let public = view.public();
        for slot in 0..view.config().hints() {
            match public.revealed_hint(HintSlot(slot as u8)) {
                Some(ColourSet(set)) => on_tiles |= set,
                None => break,
            }
        }
        let rank = &self.rank[..self.colours as usize];
        let (seen, shown) = (self.seen, self.shown);
        append_new(
            rank,
            on_cards | on_tiles,
            &mut self.seen_order,
            &mut self.seen,
        );
        append_new(rank, on_tiles, &mut self.shown_order, &mut self.shown);
        (seen, shown) != (self.seen, self.shown)
    }

    /// These labels' tie rank and naming with nothing seen: what [`ColourLabels::new`]
    /// gave at the start of the episode.
    pub fn restart(&self) -> ColourLabels {
        ColourLabels::with_rank(self.colours as usize, self.rank, self.naming)
    }

    /// The naming rule these labels follow.
    pub fn naming(&self) -> ColourNaming {
        self.naming
    }

    /// How many colours the seat has seen.
    pub fn seen(&self) -> usize {
        self.seen as usize
    }

    /// How many colours revealed hint tiles have shown.
    pub fn shown(&self) -> usize {
        self.shown as usize
    }

    /// The colours in the order of their names: name k is `names()[k]`. Colours the seat
    /// has not seen come last, in rank order.
    fn names(&self) -> [u8; MAX_COLOURS] {
        let c = self.colours as usize;
        let mut names = [0u8; MAX_COLOURS];
        let (mut at, mut named) = (0, 0u8);
        let mut put = |colour: u8, names: &mut [u8; MAX_COLOURS]| {
            if named & (1 << colour) == 0 {
                named |= 1 << colour;
                names[at] = colour;
                at += 1;
            }
        };
        if self.naming == ColourNaming::PublicFirst {
            for &colour in &self.shown_order[..self.shown as usize] {
                put(colour, &mut names);
            }
        }
        for &colour in &self.seen_order[..self.seen as usize] {
            put(colour, &mut names);
        }
        for &colour in &self.rank[..c] {
            put(colour, &mut names);
        }
        names
    }

    /// The label of a true colour: its place in the order of the names (unseen colours
    /// after the seen ones, in rank order); `None` for a colour the config does not have.
    pub fn label(&self, colour: Colour) -> Option<Colour> {
        self.names()[..self.colours as usize]
            .iter()
            .position(|&c| c == colour.0)
            .map(|at| Colour(at as u8))
    }

    /// `view` with its colour permutation replaced by these labels (its rotation and
    /// reflection kept): the symmetry that shows the seat its game with these names.
    pub fn symmetry(&self, config: &Config, view: Symmetry) -> Symmetry {
        let c = self.colours as usize;
        let mut map = [0u8; MAX_COLOURS];
        for (label, &colour) in self.names()[..c].iter().enumerate() {
            map[colour as usize] = label as u8;
        }
        Symmetry::new(config, &map[..c], view.rotation(), view.reflects())
            .expect("labels are a permutation of the config's colours")
    }
}

/// Append to `order[..*len]` the colours of the bit set `now` not yet in it, in `rank`
/// order (the order among colours that appear at the same step).
fn append_new(rank: &[u8], now: u8, order: &mut [u8; MAX_COLOURS], len: &mut u8) {
    let mut known = 0u8;
    for &colour in &order[..*len as usize] {
        known |= 1 << colour;
    }
    for &colour in rank {
        if (now & !known) & (1 << colour) != 0 {
            order[*len as usize] = colour;
            *len += 1;
        }
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

    /// A game's deal with every colour renamed by `perm` (`perm[c]` is the new name of c),
    /// through the symmetry that renames them so.
    fn renamed(game: &Game, perm: &[u8]) -> Game {
        let config = *game.config();
        let rename = Symmetry::new(&config, perm, 0, false).unwrap();
        let deal = game.deal();
        let renamed = Deal {
            card_colours: deal
                .card_colours
                .iter()
                .map(|&c| rename.map_colour(c))
                .collect(),
            hint_colours: deal
                .hint_colours
                .iter()
                .map(|&s| rename.map_colour_set(s))
                .collect(),
        };
        Game::from_deal(config, &renamed).unwrap()
    }

    /// A random permutation of the `c` colours, drawn from `seed`.
    fn permutation(c: usize, seed: u64) -> Vec<u8> {
        use rand_chacha::rand_core::SeedableRng;
        let mut perm: Vec<u8> = (0..c as u8).collect();
        crate::deal::shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(seed), &mut perm);
        perm
    }

    /// Labels with a given tie rank, for tests that set it instead of drawing it.
    fn labels_with(naming: ColourNaming, c: usize, rank: [u8; MAX_COLOURS]) -> ColourLabels {
        ColourLabels::with_rank(c, rank, naming)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Renaming the deal's colours (and the tie rank with them) changes nothing a seat
        /// sees through its names, at any step of a random game, in both encodings and
        /// under both namings; a first-seen name never changes once given, nor does a
        /// public-first name once a tile has shown the colour.
        #[test]
        fn named_views_do_not_depend_on_the_dealt_colour_names(deal in 0u64..1_000_000, play in any::<u64>(), rename in any::<u64>()) {
            let config = config();
            let (c, players) = (config.colours(), config.players());
            let perm = permutation(c, rename);
            for naming in [ColourNaming::FirstSeen, ColourNaming::PublicFirst] {
                let mut a = Game::new(config, deal);
                let mut b = renamed(&a, &perm);
                let mut labels_a: Vec<ColourLabels> = (0..players)
                    .map(|s| ColourLabels::new(&config, deal + s as u64, naming))
                    .collect();
                let mut labels_b: Vec<ColourLabels> = labels_a
                    .iter()
                    .map(|l| {
                        let mut rank = l.rank;
                        for r in rank[..c].iter_mut() {
                            *r = perm[*r as usize];
                        }
                        labels_with(naming, c, rank)
                    })
                    .collect();
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
                        // Names that are fixed once given keep their labels.
                        let fixed = match naming {
                            ColourNaming::FirstSeen => &before.seen_order[..before.seen()],
                            ColourNaming::PublicFirst => &before.shown_order[..before.shown()],
                        };
                        for &colour in fixed {
                            prop_assert_eq!(labels_a[s].label(Colour(colour)), before.label(Colour(colour)));
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

        /// Public-first names are shared: two seats with one rank name every colour a tile
        /// has shown alike at every step of a random game, whatever each saw on cards, and
        /// those names come before every other.
        #[test]
        fn public_first_names_of_shown_colours_are_the_same_for_both_seats(deal in 0u64..1_000_000, play in any::<u64>()) {
            let config = config();
            let c = config.colours();
            let rank = ColourLabels::new(&config, deal, ColourNaming::PublicFirst).rank;
            let mut game = Game::new(config, deal);
            let mut seats = [labels_with(ColourNaming::PublicFirst, c, rank); 2];
            let mut step = 0u64;
            loop {
                for (s, l) in seats.iter_mut().enumerate() {
                    l.update(&game.view(Seat(s as u8)));
                }
                prop_assert_eq!(seats[0].shown(), seats[1].shown());
                for &colour in &seats[0].shown_order[..seats[0].shown()] {
                    prop_assert_eq!(seats[0].label(Colour(colour)), seats[1].label(Colour(colour)));
                    prop_assert!(seats[0].label(Colour(colour)).unwrap().0 < seats[0].shown() as u8);
                }
                if game.is_over() {
                    break;
                }
                let legal = game.legal_actions(game.current_seat());
                game.apply(legal[(derive_seed(play, step) % legal.len() as u64) as usize]).unwrap();
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
        let mut labels = ColourLabels::new(&config, 3, ColourNaming::FirstSeen);
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
