//! Tests of OBL's targets in the rollout: ending, partners, the END term, the oracle.

use super::*;
use crate::network::MlpEncoder;
use crate::obl::continuation::continue_all;
use crate::obl::memory::step_along;
use crate::obl::partners::{partner_memories, Learner, PartnerNet, Partners};
use crate::obl::previous::true_observations;
use crate::obl::targets::partners_of;
use crate::TrainConfig;
use burn::module::Module;
use yokai_agents::belief::colouring::all_colourings;
use yokai_engine::{Action, Card, Colour, Game, Part, Seat};
use yokai_vec::Encoding;

fn config() -> TrainConfig {
    let mut c = TrainConfig::from_toml_str(
        "[network]\npreset = \"compact\"\nhidden = 16\n[ppo]\nnum_envs = 8\n\
         rollout_steps = 8\nminibatches = 2\n[obl]\nlevel = 1\n[run]\nthreads = 1\n",
        "test",
    )
    .unwrap();
    c.ppo.total_steps = 64 * 4;
    c
}

/// A trainer after one rollout from `seed` (the rollout's draws from `rng_seed`), games
/// mid-episode, and every row's memory once it has read the current observation.
fn after_a_rollout(c: TrainConfig, seed: u64, rng_seed: u64) -> (Trainer<MlpEncoder>, Vec<f32>) {
    let mut trainer = Trainer::<MlpEncoder>::new(c, seed).unwrap();
    trainer
        .collect(1.0, &mut ChaCha8Rng::seed_from_u64(rng_seed))
        .unwrap();
    let net = trainer.model.valid();
    let (rows, l, na) = (
        trainer.actor.rows(),
        trainer.actor.obs_len(),
        trainer.actor.n_actions(),
    );
    let (mut obs, mut masks) = (vec![0f32; rows * l], vec![0f32; rows * na]);
    trainer.actor.view(&mut obs, &mut masks);
    let dev = trainer.infer_device.clone();
    let real = net
        .act(
            &obs,
            &trainer.actor.memory,
            &trainer.actor.keeps(),
            &[],
            &dev,
            1,
        )
        .states;
    (trainer, real)
}

/// Ending at the first step: the target is R_END in a world drawn from the seat's
/// level-1 belief, which knows nothing yet, so over many draws its mean is the mean
/// R_END over all 1,680 colourings of the game's start square (computed here by
/// listing them), and no value is bootstrapped: the continuation ended.
#[test]
fn the_target_of_ending_at_the_start_is_the_mean_over_all_colourings() {
    let trainer = Trainer::<MlpEncoder>::new(config(), 3).unwrap();
    let net = trainer.model.valid();
    let game = *trainer.actor.env().config();
    let end = game.encode(Action::End) as u32;
    let rows = trainer.actor.rows();
    let joint: Vec<u32> = (0..rows)
        .map(|r| if r % 2 == 0 { end } else { 0 })
        .collect();
    // Per game: the mean and the variance of R_END over all colourings.
    let mut exact = [(0f64, 0f64); 8];
    let all = all_colourings(&game);
    for (i, e) in exact.iter_mut().enumerate() {
        let start = trainer.actor.env().game(i);
        let rewards: Vec<f64> = all
            .iter()
            .map(|x| {
                let colours: Vec<Colour> = (0..9).map(|k| x.colour_of(Card(k))).collect();
                let mut g = start.with_card_colours(&colours).unwrap();
                g.apply(Action::End).unwrap().reward as f64
            })
            .collect();
        let mean = rewards.iter().sum::<f64>() / rewards.len() as f64;
        let var = rewards.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / rewards.len() as f64;
        *e = (mean, var);
    }
    let draws = 3000;
    let mut sums = [0f64; 8];
    for t in 0..draws {
        let targets = trainer.obl_step(&net, t, &joint, 1.0).unwrap().targets;
        assert_eq!(targets.len(), 8, "one target per game");
        for (row, target) in targets {
            assert_eq!(row % 2, 0, "seat 0 acts first");
            sums[row / 2] += target as f64;
        }
    }
    for (i, sum) in sums.iter().enumerate() {
        let mean = sum / draws as f64;
        let (want, var) = exact[i];
        let se = (var / draws as f64).sqrt();
        assert!(
            (mean - want).abs() < 5.0 * se,
            "game {i}: mean target {mean:.3}, exact {want:.3} (SE {se:.3})"
        );
    }
}

/// [`config`] with Other-Play's symmetries: every seat sees its game through one of the 24
/// colour maps × rotations, drawn per episode.
fn with_other_play(mut c: TrainConfig) -> TrainConfig {
    c.algorithm.symmetries = crate::SymmetrySet::Both;
    c
}

/// Under Other-Play the belief still reads the true game: after a rollout with the 24
/// symmetries, every row's belief input is the graph observation of its seat in the true
/// game, and for some rows that is not the seat's view (which the policy reads).
#[test]
fn the_belief_reads_the_true_game_not_the_seats_view() {
    let (trainer, _) = after_a_rollout(with_other_play(config()), 9, 2);
    let actor = &trainer.actor;
    let (rows, l, na) = (actor.rows(), actor.obs_len(), actor.n_actions());
    let read = true_observations(actor);
    assert_eq!(read.len(), rows * l, "the compact network reads the graph");
    let (mut view, mut masks) = (vec![0f32; rows * l], vec![0f32; rows * na]);
    actor.view(&mut view, &mut masks);
    let graph = Encoding::Graph(Part::Full);
    let mut differ = 0;
    for r in 0..rows {
        let mut truth = vec![0f32; l];
        graph
            .write(actor.game(r / 2), Seat((r % 2) as u8), &mut truth)
            .unwrap();
        assert_eq!(&read[r * l..][..l], &truth[..], "row {r}");
        differ += (view[r * l..][..l] != truth[..]) as usize;
    }
    assert!(differ > 0, "no seat's view differs from its true game");
}

/// The partners' memories rebuilt by replaying each episode are the memories the
/// rollout built, when the colouring replayed is the true one: after a rollout (games
/// mid-episode and some just dealt), every partner seat's replayed memory equals its
/// row of the rollout's state once that has read the current observation. With and
/// without Other-Play: a replay sees each state through the seat's symmetry, as the
/// rollout did.
#[test]
fn partner_memories_replayed_in_the_true_colours_are_the_real_ones() {
    for op in [false, true] {
        let mut c = config();
        c.ppo.rollout_steps = 13;
        if op {
            c = with_other_play(c);
        }
        partner_memories_are_the_real_ones(c, op);
    }
}

fn partner_memories_are_the_real_ones(c: TrainConfig, op: bool) {
    let (trainer, real) = after_a_rollout(c, 9, 2);
    let moved = (0..16)
        .filter(|&r| !trainer.actor.symmetry(r).is_identity())
        .count();
    assert_eq!(moved > 8, op, "seats seeing through a symmetry: {moved}");
    let net = trainer.model.valid();
    let dev = trainer.infer_device.clone();
    let truths: Vec<Vec<Colour>> = (0..8)
        .map(|i| trainer.actor.env().game(i).deal().card_colours)
        .collect();
    let seats: Vec<Vec<Seat>> = (0..8)
        .map(|i| {
            partners_of(
                trainer.actor.env().game(i),
                trainer.actor.env().game(i).current_seat(),
            )
        })
        .collect();
    let h = trainer.model.hidden_size();
    // Recoloured with their own colours, the worlds are the real games.
    let worlds: Vec<Game> = (0..8)
        .map(|i| trainer.actor.env().game(i).clone())
        .collect();
    let learner = Learner {
        net: &net,
        device: &dev,
    };
    let replayed = partner_memories(&trainer.actor, &learner, &truths, &worlds, &seats).unwrap();
    let lengths: Vec<usize> = (0..8).map(|i| trainer.actor.history[i].len()).collect();
    assert!(
        lengths.iter().any(|&n| n > 5),
        "some episode is long: {lengths:?}"
    );
    for i in 0..8 {
        let seat = seats[i][0].index();
        let want = &real[(2 * i + seat) * h..][..h];
        assert_eq!(replayed[i].len(), want.len(), "game {i}: a whole memory");
        for (a, b) in replayed[i].iter().zip(want) {
            assert!(
                (a - b).abs() < 1e-5,
                "game {i} (episode of {}, Other-Play {op}): {a} vs {b}",
                lengths[i]
            );
        }
    }
}

/// `obl.partner` decides who plays the partners: where the seat's action ends its turn
/// (substep 3) the partners move inside the continuation and the targets differ between
/// random play (the level below level 1) and the learner; where the seat acts again at
/// once (MOVE) they are the same.
#[test]
fn obl_partner_chooses_who_plays_the_partners() {
    use crate::config::OblPartner;
    use yokai_engine::Substep;
    // After `steps` rollout steps from the deals, one legal action of every game.
    let targets = |partner: OblPartner, steps: usize| {
        let mut c = config();
        c.ppo.rollout_steps = steps;
        c.obl.partner = partner;
        let mut trainer = Trainer::<MlpEncoder>::new(c, 6).unwrap();
        trainer
            .collect(1.0, &mut ChaCha8Rng::seed_from_u64(3))
            .unwrap();
        let mut joint = vec![0u32; trainer.actor.rows()];
        let mut ends_turn = Vec::new();
        for i in 0..8 {
            let g = trainer.actor.env().game(i);
            let seat = g.current_seat();
            joint[2 * i + seat.index()] = g.config().encode(g.legal_actions(seat)[0]) as u32;
            ends_turn.push(g.substep() == Substep::Hint);
        }
        let net = trainer.model.valid();
        let step = trainer.obl_step(&net, 0, &joint, 1.0).unwrap();
        (step.targets, ends_turn)
    };
    // Three steps in: every game is at its first REVEAL/PLACE.
    let (below, ends_turn) = targets(OblPartner::Previous, 3);
    let (learner, _) = targets(OblPartner::Learner, 3);
    assert!(ends_turn.iter().all(|&e| e), "{ends_turn:?}");
    for i in 0..8 {
        assert_ne!(
            below[i].1, learner[i].1,
            "game {i}: the partners' play made no difference"
        );
    }
    // Two steps in, at MOVE: the seat acts again at once, no partner moves.
    let (below, ends_turn) = targets(OblPartner::Previous, 2);
    let (learner, _) = targets(OblPartner::Learner, 2);
    assert!(ends_turn.iter().all(|&e| !e), "{ends_turn:?}");
    assert_eq!(below, learner);
}

/// `obl.oracle` runs every continuation in the true colours, where the exact belief
/// draws other colourings.
#[test]
fn the_oracle_draws_the_true_colours() {
    let worlds = |oracle: bool| {
        let mut c = config();
        c.obl.oracle = oracle;
        let trainer = Trainer::<MlpEncoder>::new(c, 4).unwrap();
        let end = trainer.actor.env().config().encode(Action::End) as u32;
        let net = trainer.model.valid();
        let step = trainer
            .obl_step(&net, 0, &vec![end; trainer.actor.rows()], 1.0)
            .unwrap();
        let truths: Vec<Vec<Colour>> = (0..8)
            .map(|i| trainer.actor.env().game(i).deal().card_colours)
            .collect();
        let drawn: Vec<Vec<Colour>> = step.worlds.iter().map(|w| w.deal().card_colours).collect();
        (drawn, truths)
    };
    let (drawn, truths) = worlds(true);
    assert_eq!(drawn, truths);
    let (drawn, truths) = worlds(false);
    assert!(
        drawn != truths,
        "the exact belief drew the true colouring in all 8 games"
    );
}

/// With the END term on, what END would pay at a rollout step is read in the world the
/// step's OBL continuation was drawn in, not on the true board: at the first step every
/// game's END reward is that world's R_END, and some differ from the true board's.
#[test]
fn the_end_term_values_ending_in_the_world_drawn_from_the_belief() {
    let mut c = config();
    c.ppo.end_lookahead = 0.5;
    let drawn = Trainer::<MlpEncoder>::new(c.clone(), 5).unwrap();
    let net = drawn.model.valid();
    // The worlds depend on the games and the step's stream only, not on the actions.
    let end = drawn.actor.env().config().encode(Action::End) as u32;
    let worlds = drawn
        .obl_step(&net, 0, &vec![end; drawn.actor.rows()], 1.0)
        .unwrap()
        .worlds;
    let mut trainer = Trainer::<MlpEncoder>::new(c, 5).unwrap();
    let truths: Vec<i32> = (0..8)
        .map(|i| trainer.actor.env().game(i).end_reward())
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let rollout = trainer.collect(1.0, &mut rng).unwrap();
    let mut differ = 0;
    for (i, world) in worlds.iter().enumerate() {
        let want = world.end_reward();
        let row = 2 * i + world.current_seat().index();
        assert_eq!(
            rollout.columns.end.as_ref().unwrap().paid()[row],
            want as f32,
            "game {i}"
        );
        differ += (want != truths[i]) as usize;
    }
    assert!(
        differ > 0,
        "every world paid what the true board pays: {truths:?}"
    );
}

/// With the learner as partner the seat's memory steps in the network beside its partners'
/// (with `obl.decisions` > 1 the seat also plays on), and the bootstrap reads that memory
/// after one more step on the last state: the same memory as stepping the seat's state at t
/// along every state of the continuation (the path where random play or the previous level
/// plays the partners). Games mid-episode, true colours (so that the real memories are
/// every seat's memory of the world), two decisions.
#[test]
fn a_seat_that_plays_on_carries_the_memory_of_its_whole_continuation() {
    for op in [false, true] {
        let mut c = config();
        c.ppo.rollout_steps = 11;
        if op {
            c = with_other_play(c);
        }
        carries_the_memory_of_its_whole_continuation(c);
    }
}

fn carries_the_memory_of_its_whole_continuation(c: TrainConfig) {
    let (trainer, real) = after_a_rollout(c, 8, 4);
    let symmetries = trainer.actor.symmetries();
    let net = trainer.model.valid();
    let dev = trainer.infer_device.clone();
    let h = trainer.model.hidden_size();
    let learner = Learner {
        net: &net,
        device: &dev,
    };
    let games: Vec<Game> = (0..8)
        .map(|i| trainer.actor.env().game(i).clone())
        .collect();
    use rand_chacha::rand_core::Rng;
    let mut pick = ChaCha8Rng::seed_from_u64(1);
    let starts: Vec<(&Game, usize)> = games
        .iter()
        .map(|g| {
            let mut legal = g.legal_actions(g.current_seat());
            legal.retain(|&a| a != Action::End);
            let k = (pick.next_u64() % legal.len() as u64) as usize;
            (g, g.config().encode(legal[k]))
        })
        .collect();
    let seats: Vec<Vec<Seat>> = games
        .iter()
        .map(|g| {
            std::iter::once(g.current_seat())
                .chain(partners_of(g, g.current_seat()))
                .collect()
        })
        .collect();
    let states = seats
        .iter()
        .enumerate()
        .map(|(i, s)| {
            s.iter()
                .flat_map(|seat| real[(2 * i + seat.index()) * h..][..h].to_vec())
                .collect()
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut partners = Partners::Network {
        net: &learner,
        seats: seats.clone(),
        symmetries: symmetries.clone(),
        states,
        rng: &mut rng,
    };
    let runs = continue_all(&starts, &mut |w, g| partners.act(w, g), 1.0, 0.99, 2, 16).unwrap();
    let carried: Vec<Vec<f32>> = partners
        .into_states()
        .unwrap()
        .into_iter()
        .map(|mut m| {
            m.truncate(h);
            m
        })
        .collect();
    let own: Vec<Vec<Seat>> = seats.iter().map(|s| vec![s[0]]).collect();
    let (mut fast, mut slow) = (carried, Vec::new());
    for (i, s) in own.iter().enumerate() {
        slow.push(real[(2 * i + s[0].index()) * h..][..h].to_vec());
    }
    let last: Vec<&[Game]> = runs.iter().map(|c| &c.states[c.steps() - 1..]).collect();
    let all: Vec<&[Game]> = runs.iter().map(|c| &c.states[..]).collect();
    let mut recur = |o, s, k| learner.recur(o, s, k);
    step_along(
        &last,
        &own,
        &symmetries,
        &mut fast,
        MlpEncoder::encoding(),
        false,
        &mut recur,
    );
    step_along(
        &all,
        &own,
        &symmetries,
        &mut slow,
        MlpEncoder::encoding(),
        false,
        &mut recur,
    );
    let longest = runs.iter().map(|c| c.steps()).max().unwrap();
    assert!(
        longest >= 6,
        "some continuation went through a partner's turn: {longest}"
    );
    for i in 0..8 {
        assert!(
            !fast[i].is_empty() && fast[i].len() == slow[i].len(),
            "game {i}"
        );
        for (a, b) in fast[i].iter().zip(&slow[i]) {
            assert!(
                (a - b).abs() < 1e-5,
                "game {i} ({} steps): {a} vs {b}",
                runs[i].steps()
            );
        }
    }
}
