//! `[ppo]`: the PPO hyper-parameters and the add-ons' weights.

use super::{bad, Checked};
use serde::{Deserialize, Serialize};

/// PPO hyper-parameters (the paper's Table of training details).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PpoConfig {
    /// Parallel games per rollout.
    pub num_envs: usize,
    /// Steps per rollout (and BPTT length: every game's sequence is kept whole).
    pub rollout_steps: usize,
    /// Total environment steps (one step = one action in each of `num_envs` games).
    pub total_steps: u64,
    /// Adam learning rate at the start; annealed linearly to 0 when `anneal_lr`.
    pub lr: f64,
    pub anneal_lr: bool,
    /// Share of the run, in [0, 1), for which the rate holds at `lr` before its linear
    /// anneal to 0 begins (with `anneal_lr`). 0 (the paper's, and left out of saved configs)
    /// anneals over the whole run, so the second half learns at under half the rate; a
    /// hold keeps the full rate while the policy still improves and anneals only at the end.
    #[serde(skip_serializing_if = "is_zero")]
    pub lr_hold: f32,
    pub adam_eps: f64,
    pub gamma: f32,
    pub gae_lambda: f32,
    /// Policy-ratio clip ε.
    pub clip: f32,
    /// Clip of the value change from the rollout's value (the clipped value loss).
    pub value_clip: f32,
    pub value_coef: f32,
    /// Entropy bonus α (at the start of the run, when `entropy_final` is given).
    pub entropy_coef: f32,
    /// The entropy bonus at the end of the run: α falls (or rises) linearly from
    /// `entropy_coef` to it over the run. Absent (the paper's presets): α stays
    /// `entropy_coef`. Early on the bonus keeps END and the moves explored; late, a smaller
    /// one lets the policy settle on the moves its partner reads best.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub entropy_final: Option<f32>,
    /// Divide each row's entropy by the log of its number of legal actions before the
    /// bonus, so a turn with 700 legal moves and one with 10 pull towards uniform with the
    /// same strength (the raw masked entropy of a 700-way choice swamps the policy gradient;
    /// docs/training.md). Off in the paper's presets.
    pub entropy_normalized: bool,
    /// Bonus on the entropy of the binary choice "END or not" wherever END is legal (the
    /// first substep of a turn): keeps ending explored without pulling the hundreds of
    /// MOVE logits towards uniform as `entropy_coef` does. END pays only when the board is
    /// won, so PPO otherwise stops trying it in the first updates (docs/training.md).
    /// 0 (the paper's presets) turns it off.
    pub end_entropy_coef: f32,
    /// Weight of an exact END term: wherever END is legal, the simulator knows what ending
    /// now would pay (R of the true board, `Game::end_reward`), so the loss adds the
    /// expected policy gradient of END, −π(END|s)·(R_END(s) − V(s)), at every such state,
    /// not only where END was drawn. A centralised-training signal (the policy still acts
    /// on its own view); 0 (the paper's presets) turns it off. Under OBL the board is the
    /// fictitious one, recoloured by a draw from the acting seat's belief, so the term
    /// values END as OBL's own target does and never reads the true colours.
    pub end_lookahead: f32,
    /// Which gradient `end_lookahead` adds (see [`EndForm`]); the paper's presets leave
    /// `end_lookahead` at 0, where this does nothing.
    pub end_lookahead_form: EndForm,
    /// Weight of an auxiliary belief loss (pointer head only): from each card's embedding
    /// the network predicts the card's true colour, by cross-entropy, at every state where
    /// a seat chooses. The agent has to represent what it knows and what it can infer about
    /// every card, which END (is every colour clustered?) and clustering moves depend on.
    /// A centralised-training signal; 0 (every preset but `cpu`) turns it off and leaves
    /// the network without the colour layer.
    pub belief_aux: f32,
    /// Global gradient-norm clip.
    pub max_grad_norm: f32,
    pub epochs: usize,
    pub minibatches: usize,
    /// Weight of the shaping reward at the start; annealed linearly to 0 over the first
    /// `shaping_fraction` of the run.
    pub shaping: f32,
    /// Share of the run, in (0, 1], over which the shaping weight falls to 0 (1 = the whole
    /// run, the paper's). The shaping pays for observing and hinting, so while it lasts
    /// every value V(s) counts future shaping that ending forfeits, and END looks worse
    /// than it is; a shorter anneal lets the late run value END by the game's reward alone.
    pub shaping_fraction: f32,
    /// Normalise advantages inside each minibatch (as JaxMARL's IPPO does).
    pub normalize_advantages: bool,
    /// Weight of a clustering shaping reward, annealed with `shaping`: each step that is
    /// not an episode's last adds the change in the number of clustered colours (a
    /// potential-based term, so it does not change which policies are optimal). The game's
    /// own reward counts clustered colours only at the end, 32 steps later; this gives the
    /// moves that cluster a signal of their own. 0 (the paper's presets) turns it off.
    pub cluster_shaping: f32,
    /// Weight of a reward for what the team comes to know of the colours (needs
    /// `belief_aux`, whose colour layer reads it): a game's potential is the sum over its
    /// seats and cards of log p(the card's true colour) under the colour layer at the
    /// seat's state, and every step that is not an episode's last adds the weighted change
    /// of that potential to both seats' reward. It pays a move at once for what it lets
    /// the partner (and the mover) infer, where the game pays only through the ENDs it
    /// makes right, much later. Potential-based, so it does not change which policies are
    /// optimal; `belief_gain_seats = "waiting"` pays another way, which does while it
    /// lasts. Annealed linearly to 0 over the first `belief_gain_fraction` of the run.
    /// 0 (every preset, and left out of saved configs) turns it off.
    #[serde(skip_serializing_if = "is_zero")]
    pub belief_gain: f32,
    /// Share of the run, in (0, 1], over which `belief_gain` falls to 0 (1, left out of
    /// saved configs: the whole run).
    #[serde(skip_serializing_if = "is_one")]
    pub belief_gain_fraction: f32,
    /// What a seat's share of the `belief_gain` potential counts (see [`GainBaseline`]).
    #[serde(skip_serializing_if = "GainBaseline::is_none")]
    pub belief_gain_baseline: GainBaseline,
    /// Whose shares of the `belief_gain` potential are paid, and when (see [`GainSeats`]).
    #[serde(skip_serializing_if = "GainSeats::is_all")]
    pub belief_gain_seats: GainSeats,
}

impl Default for PpoConfig {
    fn default() -> Self {
        PpoConfig {
            num_envs: 1024,
            rollout_steps: 128,
            total_steps: 1_000_000_000,
            lr: 3e-4,
            anneal_lr: true,
            lr_hold: 0.0,
            adam_eps: 1e-5,
            gamma: 0.99,
            gae_lambda: 0.95,
            clip: 0.2,
            value_clip: 0.2,
            value_coef: 0.5,
            entropy_coef: 0.05,
            entropy_final: None,
            entropy_normalized: false,
            end_entropy_coef: 0.0,
            end_lookahead: 0.0,
            end_lookahead_form: EndForm::Expected,
            belief_aux: 0.0,
            max_grad_norm: 0.5,
            epochs: 4,
            minibatches: 4,
            shaping: 1.0,
            shaping_fraction: 1.0,
            normalize_advantages: true,
            cluster_shaping: 0.0,
            belief_gain: 0.0,
            belief_gain_fraction: 1.0,
            belief_gain_baseline: GainBaseline::None,
            belief_gain_seats: GainSeats::All,
        }
    }
}

impl PpoConfig {
    /// The PPO section on its own, for a game of `players` seats.
    pub(super) fn check(&self, players: usize) -> Checked {
        let p = self;
        if p.num_envs == 0 {
            return bad("ppo.num_envs", "must be at least 1");
        }
        if p.rollout_steps == 0 {
            return bad("ppo.rollout_steps", "must be at least 1");
        }
        if p.minibatches == 0 || p.minibatches > p.num_envs * players {
            return bad(
                "ppo.minibatches",
                "must be between 1 and num_envs × players (minibatches split whole sequences)",
            );
        }
        if p.epochs == 0 {
            return bad("ppo.epochs", "must be at least 1");
        }
        if !(p.lr > 0.0 && p.lr.is_finite()) {
            return bad("ppo.lr", "must be a positive number");
        }
        if !(0.0..=1.0).contains(&p.gamma) || !(0.0..=1.0).contains(&p.gae_lambda) {
            return bad("ppo.gamma / ppo.gae_lambda", "must lie in [0, 1]");
        }
        if p.clip <= 0.0 || p.value_clip <= 0.0 || p.max_grad_norm <= 0.0 {
            return bad(
                "ppo.clip / ppo.value_clip / ppo.max_grad_norm",
                "must be positive",
            );
        }
        if !(0.0..1.0).contains(&p.lr_hold) {
            return bad("ppo.lr_hold", "must lie in [0, 1)");
        }
        for (field, fraction) in [
            ("ppo.shaping_fraction", p.shaping_fraction),
            ("ppo.belief_gain_fraction", p.belief_gain_fraction),
        ] {
            if !(fraction > 0.0 && fraction <= 1.0) {
                return bad(field, "must lie in (0, 1]");
            }
        }
        // Weights of optional terms: 0 turns a term off, and none may be negative.
        for (field, weight) in [
            ("ppo.end_lookahead", p.end_lookahead),
            ("ppo.end_entropy_coef", p.end_entropy_coef),
            ("ppo.cluster_shaping", p.cluster_shaping),
            ("ppo.belief_aux", p.belief_aux),
            ("ppo.belief_gain", p.belief_gain),
            ("ppo.entropy_final", p.entropy_final.unwrap_or(0.0)),
        ] {
            if !(weight >= 0.0 && weight.is_finite()) {
                return bad(field, "must be a number ≥ 0");
            }
        }
        Ok(())
    }
}

/// Whether a field is at its left-out value (0), for `skip_serializing_if`.
fn is_zero(x: &f32) -> bool {
    *x == 0.0
}

/// Whether a share of the run is at its left-out value (1, the whole run).
fn is_one(x: &f32) -> bool {
    *x == 1.0
}

/// What a seat's share of the `ppo.belief_gain` potential counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GainBaseline {
    /// log p(true colour) of every card. A card the seat opens becomes certain, so most of
    /// the gain pays for opening cards, which the shaping reward already pays.
    #[default]
    None,
    /// log p(true colour) − log p_counting(true colour) of the cards the seat has not opened,
    /// p_counting the share of the colour among the cards the seat has not opened (what
    /// counting alone knows). Opening a card moves it out of the sum; what is left grows
    /// only with what the seat infers beyond counting: from its partner's moves. "Opened"
    /// is what the seat sees by the game's memory rule: with imperfect memory, the cards it
    /// has opened this turn, none while it waits.
    Counting,
}

impl GainBaseline {
    fn is_none(&self) -> bool {
        *self == GainBaseline::None
    }
}

/// Whose shares of the `ppo.belief_gain` potential are paid, and when.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GainSeats {
    /// Every seat's: the change of the game's potential, which telescopes over a game to
    /// Φ(last state) − Φ(first). Under a critic that keeps up, what lasts of it is that end
    /// term (docs/results/cpu-belief-gain.md).
    #[default]
    All,
    /// What a seat came to know while its partner played: at the step that hands it the
    /// turn, its share at the turn's first state less its share at the last state it
    /// acted at (both states the belief loss trains the colour layer on). What a seat
    /// learns on its own turn (opening cards) is not paid, so the payments no longer
    /// telescope: while the weight lasts they change which policies are best. What a turn
    /// tells is never negative in expectation, so they also pay for more turns: at weight
    /// 1.0 on `cpu` the seats stopped ENDing while paid
    /// (docs/results/cpu-belief-gain-waiting.md). Under perfect memory a seat's unopened
    /// cards do not change while it waits, so the baseline cancels out of the payment;
    /// under imperfect memory the cards it opened on its turn count again at its next one.
    Waiting,
    /// The `Waiting` payments less their mean over the rollout's handovers at the same
    /// step of a game: a turn added to a game is not paid in itself on average. But in a
    /// given state the turns to come are expected to tell more or less than the mean, so
    /// going on is still paid or charged there, and END is the way out of a charge: at
    /// weight 1.0 on `cpu` the seats ENDed early and wrongly while it was paid (as with one
    /// mean over all of a rollout's handovers, a first form;
    /// docs/results/cpu-belief-gain-centred.md). `Turn` credits the same payments to the
    /// turns that earned them instead.
    Centred,
    /// The `Centred` payments as credit for the turn that earned them: each handover's is
    /// added to the advantages of the choices of the seat whose turn it ends (but the
    /// turn's first, where END is chosen), not to the reward. No value learns it and no
    /// earlier step's advantage carries it, so it cannot pay or charge for the turns a
    /// game goes on: what it reinforces is a turn that told more than turns at that point
    /// of a game usually do.
    Turn,
}

impl GainSeats {
    fn is_all(&self) -> bool {
        *self == GainSeats::All
    }
}

/// How `ppo.end_lookahead` turns "what END would pay" into a gradient on the END logit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EndForm {
    /// The expected policy gradient of END, −π(END|s)·(R_END(s) − V(s)). Its gradient on the
    /// END logit carries a factor π(END)(1 − π(END)), so it fades once P(END) is tiny.
    #[default]
    Expected,
    /// A cross-entropy pulling P(END) towards σ((R_END(s) − V(s)) / ¼ point): about 1 where
    /// ending pays a point or more beyond playing on, about 0 where it costs as much. Its
    /// gradient on the END log-odds, σ(…) − P(END), does not fade with P(END), and it is at
    /// most 1 per state whatever the size of the advantage, so it never outweighs the rest
    /// of the loss. Under partial observability P(END | history) settles at the mean target
    /// over the boards the history allows: the agent ends when it is likely to pay.
    Target,
}
