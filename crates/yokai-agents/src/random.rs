//! `random`: uniform over the legal actions.

use crate::Policy;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Action, SeatView};

/// Uniform over the legal actions.
#[derive(Clone, Debug)]
pub struct RandomPolicy {
    rng: ChaCha8Rng,
    legal: Vec<Action>,
}

impl RandomPolicy {
    pub fn new(seed: u64) -> RandomPolicy {
        RandomPolicy {
            rng: ChaCha8Rng::seed_from_u64(seed),
            legal: Vec::with_capacity(256),
        }
    }
}

impl Policy for RandomPolicy {
    fn name(&self) -> String {
        "random".to_string()
    }

    fn reset(&mut self, seed: u64) {
        self.rng = ChaCha8Rng::seed_from_u64(seed);
    }

    fn act(&mut self, view: &SeatView<'_>) -> Action {
        self.legal.clear();
        view.for_each_legal(|a| self.legal.push(a));
        assert!(
            !self.legal.is_empty(),
            "act() called on a seat with no legal action"
        );
        // Unbiased draw in 0..n (Lemire); n is far below 2^32.
        let n = self.legal.len() as u64;
        let threshold = n.wrapping_neg() % n;
        loop {
            let m = (self.rng.next_u64() as u128) * n as u128;
            if (m as u64) >= threshold {
                return self.legal[(m >> 64) as usize];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use yokai_engine::{Config, Game};

    #[test]
    fn random_policy_plays_legal_actions_reproducibly() {
        let config = Config::from_name("9c-3p").unwrap();
        let play = |seed: u64| {
            let mut game = Game::new(config, seed);
            let mut policy = RandomPolicy::new(seed);
            let mut actions = Vec::new();
            while !game.is_over() {
                let a = policy.act(&game.view(game.current_seat()));
                game.apply(a)
                    .expect("random policy chose an illegal action");
                actions.push(a);
            }
            actions
        };
        for seed in 0..50 {
            assert_eq!(play(seed), play(seed));
        }
        assert_ne!(play(1), play(2));
    }

    #[test]
    fn every_legal_action_gets_chosen() {
        // At substep 0 of 9c there are 10 legal actions; 2,000 draws hit all of them.
        let config = Config::from_name("9c-2p").unwrap();
        let game = Game::new(config, 3);
        let mut policy = RandomPolicy::new(0);
        let mut seen = std::collections::HashSet::new();
        for _ in 0..2000 {
            seen.insert(policy.act(&game.view(game.current_seat())));
        }
        assert_eq!(seen.len(), 10);
    }
}
