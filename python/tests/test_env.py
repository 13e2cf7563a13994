"""The single-game Env: introspection, names, observations and replays."""

import numpy as np
import pytest

import yokai


def play_random(env, rng, steps=10_000):
    for _ in range(steps):
        if env.done:
            return
        env.step(int(rng.choice(env.legal_actions())))


def test_action_names_round_trip():
    env = yokai.Env("9c-2p-perfect")
    for a in range(env.num_actions):
        assert env.action_index(env.action_name(a)) == a
    assert env.action_name(0) == "noop"


def test_step_by_name_and_by_index_agree():
    a, b = yokai.Env(seed=4), yokai.Env(seed=4)
    rng = np.random.default_rng(1)
    while not a.done:
        action = int(rng.choice(a.legal_actions()))
        assert a.step(action) == b.step(a.action_name(action))
    assert a.outcome == b.outcome and a.outcome is not None


def test_only_noop_is_legal_for_waiting_seats():
    env = yokai.Env("9c-3p-perfect", seed=2)
    for seat in range(3):
        if seat != env.acting_seat:
            assert env.legal_actions(seat) == [0]
            assert env.legal_mask(seat).sum() == 1


def test_substeps_cycle_observe_observe_move_hint():
    env = yokai.Env(seed=1)
    seen = []
    for _ in range(8):
        seen.append((env.acting_seat, env.substep))
        # Avoid END so that the game goes on.
        env.step(env.legal_actions()[-1])
    assert seen == [(0, 0), (0, 1), (0, 2), (0, 3), (1, 0), (1, 1), (1, 2), (1, 3)]


def test_observation_shapes_per_encoding():
    env = yokai.Env("9c-2p-perfect")
    for encoding in ["image", "image-public", "image-private", "graph", "graph-public", "graph-private"]:
        obs = env.observation(0, encoding)
        assert list(obs.shape) == env.observation_shape(encoding), encoding
        assert obs.dtype == np.float32
    assert env.observation(1, "image", "uint8").dtype == np.uint8
    assert env.adjacency().shape == (9, 9)


def test_ground_truth_counts_each_colour():
    env = yokai.Env("16c-2p-perfect", seed=3)
    truth = env.ground_truth()
    assert truth.shape == (16,)
    assert np.bincount(truth, minlength=4).tolist() == [4, 4, 4, 4]


def test_replay_round_trip_reproduces_the_game():
    rng = np.random.default_rng(7)
    env = yokai.Env("9c-2p-imperfect", seed=13)
    play_random(env, rng)
    text = env.to_replay()
    back = yokai.Env.from_replay(text)
    assert back.done and back.outcome == env.outcome
    assert back.history == env.history
    assert back.render() == env.render()
    assert back.to_replay() == text


def test_replay_of_an_unfinished_game_can_go_on():
    env = yokai.Env(seed=21)
    for _ in range(6):
        env.step(env.legal_actions()[-1])
    back = yokai.Env.from_replay(env.to_replay())
    assert back.steps == 6 and back.acting_seat == env.acting_seat
    for seat in range(2):
        np.testing.assert_array_equal(back.observation(seat), env.observation(seat))
    back.step(back.legal_actions()[-1])
    assert back.steps == 7


def test_copy_is_independent():
    env = yokai.Env(seed=2)
    twin = env.copy()
    env.step(env.legal_actions()[-1])
    assert twin.steps == 0 and env.steps == 1


def test_reset_without_seed_deals_the_next_seed():
    env = yokai.Env(seed=5)
    env.reset()
    assert env.seed == 6
    assert env.render() == yokai.Env(seed=6).render()


def test_custom_config_from_toml(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text('preset = "9c"\nplayers = 3\nmemory = "imperfect"\n')
    env = yokai.Env(str(path))
    assert env.num_players == 3
    assert "9c-3p-imperfect" in yokai.configs()


def test_ground_truth_is_the_colour_a_seat_sees_once_it_looks():
    # Every card, observed in turn across games of several deals, shows in the seat's
    # rendered view in the colour ground_truth() gives it (R, G, B, Y are colours 0-3).
    checked = 0
    for seed in range(6):
        for first in range(0, 16, 2):
            env = yokai.Env("16c-2p-perfect", seed=seed)
            truth = env.ground_truth()
            cards = [first, first + 1]
            for card in cards:
                env.step(f"observe card {card}")
            view = env.render(0)
            for card in cards:
                assert f"{'RGBY'[truth[card]]}{card} " in view.replace("\n", " "), (seed, card, view)
                checked += 1
    assert checked == 6 * 16


def test_step_joint_with_noops_for_the_waiting_seats_is_step():
    # step_joint takes one action per seat: the acting seat's action and NOOP for the
    # others steps exactly as step(action) does, through a whole game.
    rng = np.random.default_rng(5)
    one, joint = yokai.Env("9c-3p-perfect", seed=8), yokai.Env("9c-3p-perfect", seed=8)
    noop = one.action_index("noop")
    while not one.done:
        action = int(rng.choice(one.legal_actions()))
        actions = [noop] * one.num_players
        actions[one.acting_seat] = action
        assert joint.step_joint(actions) == one.step(action)
        assert joint.render() == one.render()
    assert joint.done and joint.outcome == one.outcome and joint.history == one.history


def test_the_distribution_is_named_yokai_learning_environment():
    # `yokai` on PyPI is another project: the package installs as this name and imports as
    # `yokai`, at the version the module reports.
    from importlib import metadata

    assert metadata.version("yokai-learning-environment") == yokai.__version__
    assert metadata.metadata("yokai-learning-environment")["License"] == "MIT OR Apache-2.0"
