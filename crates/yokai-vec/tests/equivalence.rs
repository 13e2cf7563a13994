//! The batched environment equals N independent single games with the same seeds: every
//! buffer, every step, across auto-resets, for 1 and 2 threads.

use yokai_engine::{Action, Config, Game, ImageLayout, Part, Scalar, Seat};
use yokai_vec::{episode_seed, Encoding, VecEnv, VecEnvOptions, VecError};

/// Deterministic "random" choice among the legal actions of the acting seat.
fn choose(game: &Game, step: usize, env: usize) -> Action {
    let legal = game.legal_actions(game.current_seat());
    legal[(step * 7919 + env * 104_729) % legal.len()]
}

fn run<T: Scalar + Default>(config: Config, encoding: Encoding, threads: usize, steps: usize) {
    let n = 13; // not a multiple of the chunk size
    let options = VecEnvOptions {
        encoding,
        threads: Some(threads),
        chunk: 4,
        ..VecEnvOptions::new(n, 99)
    };
    let mut env = VecEnv::<T>::new(config, options).unwrap();
    let p = config.players();
    let n_a = config.num_actions();
    let obs_len: usize = encoding.shape(&config).iter().product();
    let mut games: Vec<Game> = (0..n)
        .map(|i| Game::new(config, episode_seed(99, i, 0)))
        .collect();
    let mut episodes = vec![0u64; n];
    let mut resets = 0;
    for step in 0..steps {
        // Compare every buffer with the single games.
        for (i, game) in games.iter().enumerate() {
            assert_eq!(env.acting_seats()[i], game.current_seat().0);
            for s in 0..p {
                let seat = Seat(s as u8);
                let mut mask = vec![0u8; n_a];
                game.write_legal_mask(seat, &mut mask);
                assert_eq!(
                    &env.legal_masks()[(i * p + s) * n_a..][..n_a],
                    &mask[..],
                    "mask env {i} seat {s} step {step}"
                );
                let mut o = vec![T::ZERO; obs_len];
                encoding.write(game, seat, &mut o).unwrap();
                assert!(
                    env.observations()[(i * p + s) * obs_len..][..obs_len] == o[..],
                    "obs env {i} seat {s} step {step}"
                );
            }
            if let Encoding::Graph(_) = encoding {
                let y = config.cards();
                let mut a = vec![T::ZERO; y * y];
                game.write_adjacency(&mut a).unwrap();
                assert!(env.adjacency()[i * y * y..][..y * y] == a[..]);
            }
        }
        let actions: Vec<u32> = games
            .iter()
            .enumerate()
            .map(|(i, g)| config.encode(choose(g, step, i)) as u32)
            .collect();
        env.step(&actions).unwrap();
        for (i, game) in games.iter_mut().enumerate() {
            let result = game.apply_index(actions[i] as usize).unwrap();
            assert_eq!(env.rewards()[i], result.reward as f32);
            assert_eq!(env.shaping()[i], result.shaping as f32);
            assert_eq!(env.dones()[i], result.done as u8);
            if result.done {
                assert_eq!(env.outcomes()[i], game.outcome());
                episodes[i] += 1;
                resets += 1;
                *game = Game::new(config, episode_seed(99, i, episodes[i]));
            } else {
                assert_eq!(env.outcomes()[i], None);
            }
            assert_eq!(env.episodes(i), episodes[i]);
            assert!(env.game(i) == game);
        }
    }
    assert!(resets >= n, "the run should cross auto-resets ({resets})");
}

#[test]
fn batched_equals_single_games_image_f32_on_one_and_two_threads() {
    for threads in [1, 2] {
        run::<f32>(
            Config::from_name("9c-2p").unwrap(),
            Encoding::Image(Part::Full, ImageLayout::Hwc),
            threads,
            120,
        );
    }
}

#[test]
fn batched_equals_single_games_image_u8_more_players_and_16c() {
    for threads in [1, 2] {
        run::<u8>(
            Config::from_name("9c-3p-imperfect").unwrap(),
            Encoding::Image(Part::Full, ImageLayout::Hwc),
            threads,
            100,
        );
        run::<u8>(
            Config::from_name("16c-2p").unwrap(),
            Encoding::Image(Part::Public, ImageLayout::Hwc),
            threads,
            100,
        );
    }
}

#[test]
fn batched_equals_single_games_channels_first_images() {
    for threads in [1, 2] {
        run::<f32>(
            Config::from_name("9c-2p-imperfect").unwrap(),
            Encoding::Image(Part::Full, ImageLayout::Chw),
            threads,
            120,
        );
        run::<u8>(
            Config::from_name("16c-3p").unwrap(),
            Encoding::Image(Part::Public, ImageLayout::Chw),
            threads,
            100,
        );
        run::<u8>(
            Config::from_name("9c-2p").unwrap(),
            Encoding::Image(Part::Private, ImageLayout::Chw),
            threads,
            80,
        );
    }
}

#[test]
fn batched_equals_single_games_graph_and_none() {
    for threads in [1, 2] {
        run::<f32>(
            Config::from_name("9c-4p").unwrap(),
            Encoding::Graph(Part::Full),
            threads,
            80,
        );
        run::<u8>(
            Config::from_name("9c-2p").unwrap(),
            Encoding::None,
            threads,
            80,
        );
    }
}

#[test]
fn stepping_on_the_workers_gives_the_same_buffers() {
    let config = Config::from_name("9c-2p").unwrap();
    let options = VecEnvOptions {
        threads: Some(2),
        chunk: 3,
        ..VecEnvOptions::new(10, 4)
    };
    let mut outside = VecEnv::<u8>::new(config, options).unwrap();
    let mut inside = VecEnv::<u8>::new(config, options).unwrap();
    let mut actions = vec![0u32; 10];
    for round in 0..100 {
        outside.sample_legal(round, &mut actions);
        outside.step(&actions).unwrap();
    }
    let bad = inside.on_workers(|env| {
        let mut actions = vec![0u32; 10];
        for round in 0..100 {
            env.sample_legal(round, &mut actions);
            env.step(&actions).unwrap();
        }
        actions[0] = u32::MAX; // out of range: an error, and nothing changes
        env.step(&actions)
    });
    assert!(
        matches!(bad, Err(VecError::Action { env: 0, .. })),
        "{bad:?}"
    );
    assert_eq!(inside.observations(), outside.observations());
    assert_eq!(inside.legal_masks(), outside.legal_masks());
    assert_eq!(inside.acting_seats(), outside.acting_seats());
    assert_eq!(inside.rewards(), outside.rewards());
}

#[test]
fn the_error_names_the_first_illegal_game_whichever_chunk_or_thread_finds_one() {
    let config = Config::from_name("9c-2p").unwrap();
    let mv = config.encode(Action::Move(
        yokai_engine::Card(0),
        yokai_engine::Cell::new(0, 0),
    )) as u32;
    for threads in [1, 2] {
        let options = VecEnvOptions {
            threads: Some(threads),
            chunk: 4,
            ..VecEnvOptions::new(64, 3)
        };
        let mut env = VecEnv::<u8>::new(config, options).unwrap();
        let mut actions = vec![1u32; 64]; // END: legal at substep 0
        for bad in [60, 37, 9, 10] {
            actions[bad] = mv;
        }
        let err = env.step(&actions).unwrap_err();
        assert!(matches!(err, VecError::Action { env: 9, .. }), "{err}");
        assert!((0..64).all(|i| env.game(i).steps() == 0));
    }
}

#[test]
fn illegal_actions_are_errors_that_change_nothing() {
    let config = Config::from_name("9c-2p").unwrap();
    let mut env = VecEnv::<f32>::new(config, VecEnvOptions::new(4, 1)).unwrap();
    let before_obs = env.observations().to_vec();
    // env 2 tries to MOVE at substep 0.
    let mv = config.encode(Action::Move(
        yokai_engine::Card(0),
        yokai_engine::Cell::new(0, 0),
    )) as u32;
    let err = env.step(&[1, 1, mv, 1]).unwrap_err();
    assert!(matches!(err, VecError::Action { env: 2, .. }));
    assert!(
        err.to_string().starts_with(
            "env 2: seat 0 cannot play `move card 0 to r0c0`: substep 0 allows only OBSERVE or END"
        ),
        "{err}"
    );
    assert_eq!(env.observations(), &before_obs[..]);
    assert_eq!(env.game(0).steps(), 0);
    let err = env.step(&[1, 1, 5000, 1]).unwrap_err();
    assert!(
        err.to_string()
            .contains("action index 5000 is out of range"),
        "{err}"
    );
    assert!(matches!(
        env.step(&[1, 1]).unwrap_err(),
        VecError::ActionCount {
            expected: 4,
            got: 2,
            ..
        }
    ));
    // Joint actions: seat 1 must submit NOOP.
    let err = env.step_joint(&[2, 0, 2, 0, 2, 3, 2, 0]).unwrap_err();
    assert!(
        err.to_string()
            .contains("env 2: seat 1 cannot play `observe card 1`: it is seat 0's turn"),
        "{err}"
    );
    // ...and the acting seat's action is checked as in `step`, changing nothing on error.
    let err = env.step_joint(&[2, 0, 0, 0, 2, 0, 1, 0]).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("env 1: seat 0 cannot play `noop`"),
        "{err}"
    );
    assert_eq!(env.observations(), &before_obs[..]);
    assert_eq!(env.game(0).steps(), 0);
    env.step_joint(&[2, 0, 2, 0, 2, 0, 1, 0]).unwrap();
    assert_eq!(env.dones(), &[0, 0, 0, 1]);
    assert!(env.outcomes()[3].unwrap().early_end);
    assert_eq!(env.episodes(3), 1);
}

#[test]
fn sampled_actions_are_legal_and_deterministic() {
    let config = Config::from_name("16c-2p").unwrap();
    let mut env = VecEnv::<u8>::new(config, VecEnvOptions::new(50, 5)).unwrap();
    let mut a = vec![0u32; 50];
    let mut b = vec![0u32; 50];
    for step in 0..200 {
        env.sample_legal(step, &mut a);
        env.sample_legal(step, &mut b);
        assert_eq!(a, b);
        env.step(&a).unwrap();
    }
}

#[test]
fn encodings_parse() {
    assert_eq!(
        Encoding::parse("image").unwrap(),
        Encoding::Image(Part::Full, ImageLayout::Hwc)
    );
    assert_eq!(
        Encoding::parse("graph-private").unwrap(),
        Encoding::Graph(Part::Private)
    );
    assert_eq!(
        Encoding::parse("image-public-chw").unwrap(),
        Encoding::Image(Part::Public, ImageLayout::Chw)
    );
    assert!(Encoding::parse("graph-chw").is_err());
    assert!(Encoding::parse("image-secret").is_err());
    assert!(Encoding::parse("pixels").is_err());
}

#[test]
fn restore_rebuilds_a_game_mid_episode_exactly() {
    let config = Config::from_name("9c-2p-perfect").unwrap();
    let n = 5;
    let mut env = VecEnv::<f32>::new(config, VecEnvOptions::new(n, 7)).unwrap();
    let mut history: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut actions = vec![0u32; n];
    for step in 0..60 {
        env.sample_legal(step, &mut actions);
        env.step(&actions).unwrap();
        for (i, h) in history.iter_mut().enumerate() {
            if env.dones()[i] == 1 {
                h.clear();
            } else {
                h.push(actions[i]);
            }
        }
    }
    // A second batch, put into the same state game by game, writes the same buffers.
    let mut copy = VecEnv::<f32>::new(config, VecEnvOptions::new(n, 7)).unwrap();
    for (i, h) in history.iter().enumerate() {
        copy.restore(i, env.episodes(i), h).unwrap();
        assert_eq!(copy.game(i).steps(), env.game(i).steps());
    }
    assert_eq!(copy.observations(), env.observations());
    assert_eq!(copy.legal_masks(), env.legal_masks());
    assert_eq!(copy.acting_seats(), env.acting_seats());
    // And both go on identically.
    for step in 60..90 {
        env.sample_legal(step, &mut actions);
        env.step(&actions).unwrap();
        copy.step(&actions).unwrap();
        assert_eq!(copy.observations(), env.observations());
        assert_eq!(copy.rewards(), env.rewards());
    }
    // Bad input is an error naming the game.
    let e = copy.restore(9, 0, &[]).unwrap_err();
    assert!(matches!(e, VecError::EnvIndex { env: 9, .. }));
    let e = copy.restore(1, 0, &[5000]).unwrap_err();
    assert!(e.to_string().starts_with("env 1:"), "{e}");
}

/// A `num_envs` no machine can hold is an error naming the buffer and its size, not an
/// abort: 2^40 games need more than the 128 TB a process can address.
#[test]
fn a_num_envs_too_large_for_memory_is_an_error_not_an_abort() {
    let config = Config::resolve("9c-2p-perfect").unwrap();
    for n in [1usize << 40, usize::MAX / 2] {
        let err = VecEnv::<f32>::new(config, VecEnvOptions::new(n, 0))
            .err()
            .expect("refused");
        assert!(
            matches!(err, VecError::Memory { num_envs, .. } if num_envs == n),
            "{err}"
        );
        let text = err.to_string();
        assert!(
            text.starts_with(&format!("num_envs = {n} needs ")),
            "{text}"
        );
        assert!(text.contains("TB") && text.contains("buffer"), "{text}");
    }
}
