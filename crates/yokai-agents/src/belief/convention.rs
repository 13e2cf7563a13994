//! The shared convention of the belief bot: the action a seat takes given the public facts
//! and its posterior over colourings. It reads nothing else — a [`PublicView`] has no
//! colours — so a partner can re-derive it for every colouring it thinks possible, which is
//! how moves and hints carry information (docs/bots.md states the rules for people).

use super::colouring::Colouring;
use yokai_engine::{Action, Card, Cell, HintSlot, PublicView, Seat, Substep};

/// The tunable parts of the convention.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeliefParams {
    /// Win probability assumed for playing on when deciding whether to END: END when the
    /// expected reward of ending now is at least that of playing one more turn, whose
    /// value is `continue_win · (score after its hint step) − (1 − continue_win) · 3`.
    pub continue_win: f64,
    /// Extra margin (in reward points) that ending must win by.
    pub end_margin: f64,
    /// Read nothing into partners' actions: the posterior is first-hand knowledge and the
    /// colour counts only, as Off-Belief Learning's level-1 belief. The bot still plays
    /// its convention; it just does not trust its partner to. A reference for what a
    /// grounded seat, one without conventions, can score (docs/bots.md).
    pub grounded: bool,
}

impl Default for BeliefParams {
    fn default() -> Self {
        BeliefParams {
            continue_win: 0.85,
            end_margin: 0.0,
            grounded: false,
        }
    }
}

/// The convention's action for `seat` (the acting seat of `view`), whose posterior is
/// `posterior` (non-empty), when everyone's common knowledge is `public`.
pub fn decide(
    view: &PublicView<'_>,
    seat: Seat,
    posterior: &[Colouring],
    public: &[Colouring],
    params: &BeliefParams,
) -> Action {
    match view.substep() {
        Substep::FirstObserve => {
            if should_end(view, posterior, params) {
                Action::End
            } else {
                choose_observe(view, posterior)
            }
        }
        Substep::SecondObserve => choose_observe(view, posterior),
        Substep::Move => choose_move(view, seat, posterior),
        Substep::Hint => choose_hint(view, posterior, public),
    }
}

/// Expected reward of END now against the estimate of playing on.
pub fn should_end(view: &PublicView<'_>, posterior: &[Colouring], params: &BeliefParams) -> bool {
    let n = posterior.len() as f64;
    let end_now: f64 = posterior
        .iter()
        .map(|x| x.reward_if_over(view, true) as f64)
        .sum::<f64>()
        / n;
    let (correct, wrong): (f64, f64) = posterior.iter().fold((0.0, 0.0), |acc, x| {
        let (c, w) = x.hint_tally(view);
        (acc.0 + c as f64 / n, acc.1 + w as f64 / n)
    });
    let score =
        5.0 * view.face_down() as f64 + 2.0 * view.revealed_unplaced() as f64 + correct - wrong;
    // One more turn costs at least one hint step: a place (2 → 1) or a reveal (5 → 2).
    let cost = if view.revealed_unplaced() > 0 {
        1.0
    } else {
        3.0
    };
    let q = params.continue_win;
    let play_on = q * (score - cost) - (1.0 - q) * 3.0;
    end_now >= play_on + params.end_margin
}

/// Per card, how many colourings of `set` give it each colour.
fn colour_counts(set: &[Colouring], cards: usize) -> Vec<[u32; 4]> {
    let mut counts = vec![[0u32; 4]; cards];
    for x in set {
        for (c, &mask) in x.masks.iter().enumerate() {
            for card in mask.iter() {
                counts[card.index()][c] += 1;
            }
        }
    }
    counts
}

/// OBSERVE the unhinted card whose colour is least certain, never the card already observed
/// this turn. Among the cards tied for least certain (in id order), take number
/// `k mod (number tied)` with `k` as in [`choose_move`]: the first observation of a turn
/// takes the lowest id, the second spells the colour of the first.
fn choose_observe(view: &PublicView<'_>, posterior: &[Colouring]) -> Action {
    let cards = view.config().cards();
    let counts = colour_counts(posterior, cards);
    let excluded = view.hinted_cards() | view.turn_observed();
    // Score = uncertainty: the fewest colourings agreeing on the card's likeliest colour.
    let options: Vec<(f64, Card)> = counts
        .iter()
        .enumerate()
        .filter(|&(card, _)| !excluded.contains(Card(card as u8)))
        .map(|(card, count)| {
            (
                -f64::from(*count.iter().max().unwrap_or(&0)),
                Card(card as u8),
            )
        })
        .collect();
    // `None` is unreachable in a valid config (Y − H ≥ 2); END is always legal at substep 0.
    pick_tied(&options, seen_this_turn(view, posterior)).map_or(Action::End, Action::Observe)
}

/// P(same colour) of every pair of cards under `set`, as a flat `cards × cards` table.
fn same_colour(set: &[Colouring], cards: usize) -> Vec<f64> {
    let mut same = vec![0u32; cards * cards];
    for x in set {
        for &mask in &x.masks {
            for (n, a) in mask.iter().enumerate() {
                for b in mask.iter().skip(n + 1) {
                    let (i, j) = (a.index(), b.index());
                    same[i * cards + j] += 1;
                    same[j * cards + i] += 1;
                }
            }
        }
    }
    let n = set.len().max(1) as f64;
    same.into_iter().map(|s| s as f64 / n).collect()
}

/// Expected number of same-colour neighbours of `card` if it stood on `cell`.
fn neighbour_value(view: &PublicView<'_>, same: &[f64], card: Card, cell: Cell) -> f64 {
    let cards = view.config().cards();
    view.cards_around(cell)
        .filter(|&other| other != card)
        .map(|other| same[card.index() * cards + other.index()])
        .sum()
}

/// MOVE the card whose move most raises the expected number of same-colour contacts. Many
/// moves often tie for the best gain; among them (in action-index order) take number
/// `k mod (number tied)`, where `k` spells the colours of the cards observed this turn as
/// a base-C number (cards in id order, colours numbered from 0). The move still builds
/// clusters as well as any other, and also tells partners what this seat just saw.
/// NOOP when no card can move.
fn choose_move(view: &PublicView<'_>, seat: Seat, posterior: &[Colouring]) -> Action {
    let same = same_colour(posterior, view.config().cards());
    let mut moves: Vec<(f64, Action)> = Vec::new();
    view.for_each_legal_of(seat, |action| {
        if let Action::Move(card, cell) = action {
            let gain = neighbour_value(view, &same, card, cell)
                - neighbour_value(view, &same, card, view.cell_of(card));
            moves.push((gain, action));
        }
    });
    pick_tied(&moves, seen_this_turn(view, posterior)).unwrap_or(Action::Noop)
}

/// Among `options` tied for the highest score, in their given order, the one numbered
/// `k mod (number tied)`: how rules 2 and 3 make a choice between equally good options say
/// what the actor saw. `None` if there are no options.
fn pick_tied<A: Copy>(options: &[(f64, A)], k: usize) -> Option<A> {
    let best = options.iter().map(|&(score, _)| score).reduce(f64::max)?;
    let tied = || {
        options
            .iter()
            .filter(move |&&(score, _)| score >= best - 1e-9)
    };
    tied().nth(k % tied().count()).map(|&(_, option)| option)
}

/// The colours of the cards observed this turn as a base-C number (cards in id order): what
/// the acting seat knows for certain and its partners do not (yet).
fn seen_this_turn(view: &PublicView<'_>, posterior: &[Colouring]) -> usize {
    let Some(colouring) = posterior.first() else {
        return 0;
    };
    let c = view.config().colours();
    view.turn_observed()
        .iter()
        .fold(0, |k, card| k * c + colouring.colour_of(card).index())
}

/// PLACE a revealed hint where it is certainly true (preferring the card whose colour the
/// hint tells partners most about, then a card that already has same-colour contacts);
/// otherwise REVEAL; with nothing left to reveal, PLACE where it is most likely true.
fn choose_hint(view: &PublicView<'_>, posterior: &[Colouring], public: &[Colouring]) -> Action {
    let config = view.config();
    let cards = config.cards();
    let same = same_colour(posterior, cards);
    let mut safe: Option<((f64, f64), Action)> = None;
    let mut likely: Option<(f64, Action)> = None;
    for slot in 0..config.hints() {
        let slot = HintSlot(slot as u8);
        let Some(colours) = view.revealed_hint(slot) else {
            continue;
        };
        if view.hint_card(slot).is_some() {
            continue;
        }
        for card in 0..cards {
            let card = Card(card as u8);
            if view.is_hinted(card) {
                continue;
            }
            let fits = |set: &[Colouring]| {
                set.iter().filter(|x| x.in_hint(card, colours)).count() as f64
                    / set.len().max(1) as f64
            };
            let p = fits(posterior);
            let action = Action::Place(slot, card);
            if p >= 1.0 {
                let news = 1.0 - fits(public);
                let settled = neighbour_value(view, &same, card, view.cell_of(card));
                let key = (news, settled);
                if safe.is_none_or(|(b, _)| key > b) {
                    safe = Some((key, action));
                }
            }
            if likely.is_none_or(|(b, _)| p > b) {
                likely = Some((p, action));
            }
        }
    }
    if let Some((_, action)) = safe {
        return action;
    }
    if view.face_down() > 0 {
        return Action::Reveal;
    }
    likely.map_or(Action::Reveal, |(_, a)| a)
}
