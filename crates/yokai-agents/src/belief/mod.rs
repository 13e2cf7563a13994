//! `belief`: a bot that keeps the posterior over colourings and plays a shared convention.
//!
//! Two sets of colourings drive it:
//! - the **public set**: colourings consistent with everything every seat has seen — the
//!   colour counts and every action, read under the convention: for each action, a
//!   colouring stays only if the actor, knowing what it would know under that colouring,
//!   would have chosen exactly that action ([`convention::decide`]). All seats compute the
//!   same public set, because it depends on public facts only.
//! - the **posterior** of a seat: the public set restricted to its own first-hand colours.
//!
//! For 9c the sets are exact (1,680 colourings). Where the colourings are too many to list
//! (16c: 63 million) the bot samples colourings consistent with its first-hand colours
//! instead and reads nothing into partners' actions (documented in docs/bots.md).
//! If partners stop following the convention (cross-play), the public set can run empty;
//! the bot then falls back to first-hand knowledge for the rest of the episode.

pub mod colouring;
pub mod convention;

use crate::Policy;
use colouring::{all_colourings, count_colourings, sample_colouring, Colouring};
pub use convention::BeliefParams;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use yokai_engine::{derive_seed, Action, CardSet, Config, PublicView, Seat, SeatView, MAX_COLOURS};

/// Largest number of colourings the bot lists exactly.
pub const EXACT_LIMIT: u128 = 100_000;
/// Colourings sampled per decision where listing them all is too costly.
pub const SAMPLES: usize = 256;

/// The belief bot (see the module docs).
pub struct BeliefPolicy {
    params: BeliefParams,
    seed: u64,
    config: Option<Config>,
    /// All colourings of the config, when few enough to list.
    all: Option<Arc<Vec<Colouring>>>,
    public: Vec<Colouring>,
    /// False once partners' actions contradicted the convention this episode.
    trusting: bool,
    scratch: Vec<([CardSet; MAX_COLOURS], Colouring)>,
}

impl BeliefPolicy {
    pub fn new(params: BeliefParams, seed: u64) -> BeliefPolicy {
        BeliefPolicy {
            params,
            seed,
            config: None,
            all: None,
            public: Vec::new(),
            trusting: true,
            scratch: Vec::new(),
        }
    }

    pub fn params(&self) -> &BeliefParams {
        &self.params
    }

    /// Set up for `config` at the start of an episode (or when the config changes).
    fn prepare(&mut self, config: &Config) {
        if self.config != Some(*config) {
            self.config = Some(*config);
            self.all =
                (count_colourings(config) <= EXACT_LIMIT).then(|| Arc::new(all_colourings(config)));
            self.restart();
        }
    }

    fn restart(&mut self) {
        // A grounded bot never trusts its partners: it starts where a betrayed one ends up.
        self.trusting = !self.params.grounded;
        self.public = self.all.as_ref().map_or_else(Vec::new, |all| all.to_vec());
    }

    /// The common-knowledge set (exact mode only).
    pub fn public_set(&self) -> &[Colouring] {
        &self.public
    }

    /// Whether the bot still reads partners' actions under the convention.
    pub fn is_trusting(&self) -> bool {
        self.trusting
    }

    /// The posterior of the seat of `view`: the public set restricted to its first-hand
    /// colours. Falls back to first-hand knowledge alone if that leaves nothing.
    pub fn posterior(&mut self, view: &SeatView<'_>) -> Vec<Colouring> {
        let config = *view.config();
        self.prepare(&config);
        let known = view.known_cards();
        let mut key = [CardSet::EMPTY; MAX_COLOURS];
        for card in known.iter() {
            if let Some(colour) = view.known_colour(card) {
                key[colour.index()].insert(card);
            }
        }
        if self.all.is_none() {
            let first_hand: Vec<_> = known
                .iter()
                .filter_map(|c| view.known_colour(c).map(|col| (c, col)))
                .collect();
            let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(self.seed, view.steps() as u64));
            return (0..SAMPLES)
                .map(|_| sample_colouring(&config, &first_hand, &mut rng))
                .collect();
        }
        let mut posterior: Vec<Colouring> = self
            .public
            .iter()
            .filter(|x| x.restricted(known) == key)
            .copied()
            .collect();
        if posterior.is_empty() {
            self.trusting = false;
            self.public = self.all.as_ref().map_or_else(Vec::new, |all| all.to_vec());
            posterior = self
                .public
                .iter()
                .filter(|x| x.restricted(known) == key)
                .copied()
                .collect();
        }
        posterior
    }

    /// Keep the public colourings under which `actor` would have played `action`.
    fn filter_public(&mut self, view: &PublicView<'_>, actor: Seat, action: Action) {
        let known = view.known_cards_of(actor);
        self.scratch.clear();
        self.scratch
            .extend(self.public.iter().map(|x| (x.restricted(known), *x)));
        self.scratch.sort_unstable_by_key(|(key, _)| *key);
        let mut kept = Vec::with_capacity(self.public.len());
        let mut group: Vec<Colouring> = Vec::new();
        let mut start = 0;
        while start < self.scratch.len() {
            let key = self.scratch[start].0;
            let end = start
                + self.scratch[start..]
                    .iter()
                    .take_while(|(k, _)| *k == key)
                    .count();
            group.clear();
            group.extend(self.scratch[start..end].iter().map(|(_, x)| *x));
            if convention::decide(view, actor, &group, &self.public, &self.params) == action {
                kept.extend_from_slice(&group);
            }
            start = end;
        }
        if kept.is_empty() {
            // Nobody following the convention would have played that.
            self.trusting = false;
            self.public = self.all.as_ref().map_or_else(Vec::new, |all| all.to_vec());
        } else {
            self.public = kept;
        }
    }
}

impl Policy for BeliefPolicy {
    fn name(&self) -> String {
        "belief".to_string()
    }

    fn reset(&mut self, seed: u64) {
        self.seed = seed;
        self.restart();
    }

    fn observe(&mut self, before: &SeatView<'_>, actor: Seat, action: Action) {
        self.prepare(before.config());
        if self.all.is_some() && self.trusting {
            self.filter_public(&before.public(), actor, action);
        }
    }

    fn act(&mut self, view: &SeatView<'_>) -> Action {
        let posterior = self.posterior(view);
        let public = if self.all.is_some() {
            std::mem::take(&mut self.public)
        } else {
            let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(!self.seed, view.steps() as u64));
            (0..SAMPLES)
                .map(|_| sample_colouring(view.config(), &[], &mut rng))
                .collect()
        };
        let action = convention::decide(
            &view.public(),
            view.seat(),
            &posterior,
            &public,
            &self.params,
        );
        if self.all.is_some() {
            self.public = public;
        }
        action
    }
}
