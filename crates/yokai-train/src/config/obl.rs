//! `[obl]`: Off-Belief Learning.

use super::{bad, Checked};
use serde::{Deserialize, Serialize};

/// Off-Belief Learning (docs/training.md): the value target of each of a seat's actions
/// comes from a fictitious continuation in a world drawn from the seat's belief (of the
/// previous level's play), the partners played by `partner`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OblConfig {
    /// 0: off (IPPO, HE, OP). 1: level 1, whose previous level is uniform random play and
    /// whose belief is exact (uniform over the colourings consistent with the seat's
    /// first-hand colours). 2 and up: the previous level is `previous`, and the belief a
    /// model trained on its self-play when the run starts (`yokai train --levels` also
    /// starts the level from the previous level's weights).
    pub level: u32,
    /// Levels ≥ 2: the previous level's policy (policy file, checkpoint or run directory;
    /// for a directory of `seed-N` runs, seed N uses `seed-N`). A relative path is read
    /// from the directory `yokai train` runs in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub previous: Option<std::path::PathBuf>,
    /// Levels ≥ 2: updates of the belief model on the previous level's self-play (16 games
    /// × 16 steps each) before PPO starts; kept in checkpoints, so a resume reads it.
    pub belief_updates: u64,
    /// Levels ≥ 2: width of the belief model's memory.
    pub belief_hidden: usize,
    /// Levels ≥ 2: whose self-play the belief model learns from. `own-seed` (the rule of
    /// OBL): seed N's level below. `all-seeds`: every `seed-N` run of `previous` (a
    /// directory of seeds), game g of each belief rollout played by the g-th of them in
    /// turn, so every seed of a level reads its partner's actions by the same belief, of
    /// the level below as a population rather than of its own lineage.
    #[serde(skip_serializing_if = "BeliefOf::is_own_seed")]
    pub belief_of: BeliefOf,
    /// A diagnostic, not OBL (level 1 only): every continuation runs in the true colours
    /// instead of a draw from the belief. The continuation is then the real transition, so
    /// this is self-play with OBL's one-step targets: what the learning machinery reaches
    /// when the belief grounds nothing away.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub oracle: bool,
    /// Who plays the partners' turns inside the fictitious continuations.
    pub partner: OblPartner,
    /// How many of the acting seat's own decisions a fictitious continuation covers before
    /// it bootstraps from the learner's value. 1 (the reference implementation's one-step
    /// target): the partners play until the seat is to act again. n > 1: the seat plays
    /// its next n − 1 decisions in the fictitious world too (as the learner, with its memory
    /// of that world), so the target is an n-decision return of the world drawn once from
    /// the belief, as OBL's operator defines the value ("past by π_{ℓ−1}, future by π_ℓ");
    /// the longer return carries credit further per update, as a GAE λ above 0 does for
    /// IPPO. Needs `partner = "learner"`: in the operator, every future move is π_ℓ's.
    pub decisions: u32,
    /// Levels ≥ 2 that start from trained weights (`run.init_from`: under `yokai train
    /// --levels`, the level below's; by hand, whatever `--init-from` names): the learning
    /// rate they start at in place of `ppo.lr` ([`super::TrainConfig::for_its_level`]). A
    /// new level restarts the rate (with a fresh Adam) and the shaping reward, and a policy
    /// that already plays well is jolted by both in its first updates: its critic learnt
    /// returns without shaping, so the value loss jumps seven- to eightfold and the level's
    /// games fall below the level it started from (docs/results/obl-levels-5M.md). Absent
    /// (the reference's rule): as `ppo.lr`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warm_lr: Option<f64>,
    /// Levels ≥ 2 that start from trained weights (`run.init_from`): the shaping weight in
    /// place of `ppo.shaping` (0 turns it off: the policy already observes and hints).
    /// Absent: as `ppo.shaping`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warm_shaping: Option<f32>,
    /// The first level that trains with `algorithm.symmetries` (Other-Play's symmetries);
    /// the levels below it train without them ([`super::TrainConfig::for_its_level`]).
    /// Why: with the symmetries from level 1 a chain learns late and barely climbs (levels
    /// 1-2 at SP 2.43 / 2.51 against 2.69 / 3.16 without), while switched on at level 5 of
    /// a chain trained without them they bring cross-play to self-play at once, and the
    /// levels above climb again (docs/results/obl-other-play.md). A field rather than a
    /// `--set` because a `--set` reaches every level of a `--levels` range. Absent: every
    /// level as `algorithm.symmetries` says.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetries_from_level: Option<u32>,
    /// At level `symmetries_from_level` only: the first fraction of the level's steps over
    /// which the share of games whose seats see them through a drawn symmetry grows
    /// linearly from 0 to 1 (each game decides when it is dealt; the others are played as
    /// plain self-play). Why: switched on at once, the symmetries make the level fall below
    /// the one it starts from (docs/results/obl-op-from-4-all.md); brought in gradually,
    /// the policy can leave its conventions while it still scores with them. Absent: every
    /// game with the symmetries from the level's first step.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetries_ramp: Option<f32>,
}

impl Default for OblConfig {
    fn default() -> Self {
        OblConfig {
            level: 0,
            previous: None,
            belief_updates: 300,
            belief_hidden: 64,
            belief_of: BeliefOf::OwnSeed,
            oracle: false,
            partner: OblPartner::Previous,
            decisions: 1,
            warm_lr: None,
            warm_shaping: None,
            symmetries_from_level: None,
            symmetries_ramp: None,
        }
    }
}

/// Who plays the partners inside OBL's fictitious continuations (`obl.partner`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OblPartner {
    /// The level below (uniformly random play at level 1, `obl.previous` above): the
    /// project's training spec (docs/spec/training.md, row OBL).
    #[default]
    Previous,
    /// The policy being learnt, as the reference implementation plays it (all actors of a
    /// game share the learning network's runner, `pyhanabi/act_group.py`) and as OBL's
    /// operator reads ("future actions will follow π_ℓ", the paper's §4).
    Learner,
}

/// Whose self-play a level ≥ 2 trains its belief on (`obl.belief_of`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BeliefOf {
    /// The same seed's run of the level below.
    #[default]
    OwnSeed,
    /// Every seed's run of the level below, one game in turn each.
    AllSeeds,
}

impl BeliefOf {
    fn is_own_seed(&self) -> bool {
        *self == BeliefOf::OwnSeed
    }
}

impl super::TrainConfig {
    /// The config an OBL level trains with, by two rules that depend on the level. An OBL
    /// level ≥ 2 that starts from trained weights (`run.init_from`) takes `obl.warm_lr`
    /// and `obl.warm_shaping`, when given, in place of `ppo.lr` and `ppo.shaping`; a level
    /// below `obl.symmetries_from_level` trains without symmetries. Any other config is
    /// returned as it is. One function for every way a level is started — `--levels`
    /// (`obl::levels::plan`), a level run by hand with `--init-from`, Python — because the
    /// trainer applies it when a run starts (`Trainer::new_on`). Applying it twice changes
    /// nothing, so a resumed run, whose saved config already holds the level's values,
    /// trains on as it started.
    pub fn for_its_level(mut self) -> Self {
        if self.obl.level >= 2 && self.run.init_from.is_some() {
            if let Some(lr) = self.obl.warm_lr {
                self.ppo.lr = lr;
            }
            if let Some(shaping) = self.obl.warm_shaping {
                self.ppo.shaping = shaping;
            }
        }
        if self
            .obl
            .symmetries_from_level
            .is_some_and(|from| self.obl.level < from)
        {
            self.algorithm.symmetries = super::SymmetrySet::None;
        }
        self
    }

    /// With `obl.symmetries_ramp` at the level the symmetries come in: the steps per game
    /// over which the share of games drawing a symmetry grows from 0 to 1. `None` at any
    /// other level, and without the ramp.
    pub fn symmetry_ramp_steps(&self) -> Option<u64> {
        let o = &self.obl;
        let ramp = o.symmetries_ramp?;
        (o.symmetries_from_level == Some(o.level)).then(|| {
            let per_game = self.updates() * self.ppo.rollout_steps as u64;
            ((ramp as f64 * per_game as f64).ceil() as u64).max(1)
        })
    }
}

impl OblConfig {
    /// The OBL section on its own.
    pub(super) fn check(&self) -> Checked {
        let o = self;
        if o.level >= 2 && o.previous.is_none() {
            return bad(
                "obl.previous",
                "is needed from level 2 on: the previous level's policy (its run directory)",
            );
        }
        if o.oracle && o.level != 1 {
            return bad(
                "obl.oracle",
                "is a level-1 diagnostic (the true colours in place of the exact belief)",
            );
        }
        if o.level < 2 && o.previous.is_some() {
            return bad(
                "obl.previous",
                "is read from level 2 on only (level 1's previous level is random play)",
            );
        }
        if o.level >= 2 && (o.belief_updates == 0 || o.belief_hidden == 0) {
            return bad(
                "obl.belief_updates / obl.belief_hidden",
                "must be at least 1",
            );
        }
        if o.level == 0 && o.belief_of != BeliefOf::OwnSeed {
            return bad(
                "obl.belief_of",
                "is read by OBL levels ≥ 2 (level 1's belief is exact, of random play); this \
                 config trains no OBL level (obl.level = 0)",
            );
        }
        if o.decisions == 0 {
            return bad(
                "obl.decisions",
                "must be at least 1 (1: bootstrap where the seat acts again)",
            );
        }
        if o.decisions > 1 && o.partner != OblPartner::Learner {
            return bad(
                "obl.decisions",
                "above 1 has the learner play on after the seat's next decision, so the \
                 partners must be the learner too: set obl.partner = \"learner\"",
            );
        }
        if o.level == 0 && (o.warm_lr.is_some() || o.warm_shaping.is_some()) {
            return bad(
                "obl.warm_lr / obl.warm_shaping",
                "are read for OBL levels ≥ 2 that start from trained weights (run.init_from, \
                 which `--levels` sets to the level below); this config trains no OBL level \
                 (obl.level = 0)",
            );
        }
        if o.warm_lr.is_some_and(|lr| !(lr > 0.0 && lr.is_finite())) {
            return bad("obl.warm_lr", "must be a positive number");
        }
        if o.warm_shaping.is_some_and(|w| !(w >= 0.0 && w.is_finite())) {
            return bad("obl.warm_shaping", "must be a number ≥ 0");
        }
        if o.level == 0 && o.symmetries_from_level.is_some() {
            return bad(
                "obl.symmetries_from_level",
                "is read by OBL levels; this config trains no OBL level (obl.level = 0)",
            );
        }
        if let Some(ramp) = o.symmetries_ramp {
            if !(ramp > 0.0 && ramp <= 1.0) {
                return bad(
                    "obl.symmetries_ramp",
                    "must be a fraction of the level's steps in (0, 1]",
                );
            }
            if o.symmetries_from_level.is_none() {
                return bad(
                    "obl.symmetries_ramp",
                    "is read at the level the symmetries come in: set \
                     obl.symmetries_from_level too",
                );
            }
        }
        if o.symmetries_from_level == Some(0) {
            return bad(
                "obl.symmetries_from_level",
                "must be at least 1 (levels count from 1; 1: every level, as if absent)",
            );
        }
        Ok(())
    }
}
