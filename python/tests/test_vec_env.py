"""The batched environment from Python: shapes, dtypes, views, and agreement with Env."""

import numpy as np
import pytest

import yokai


def single_games(config, num_envs, seed):
    """One Env per game of a VecEnv, dealt from the same seed stream."""
    return [yokai.Env(config, yokai.episode_seed(seed, i, 0)) for i in range(num_envs)]


@pytest.mark.parametrize(
    "config,obs,dtype",
    [
        ("9c-2p-perfect", "image", "float32"),
        ("9c-3p-imperfect", "image", "uint8"),
        ("9c-2p-perfect", "graph", "float32"),
        ("16c-2p-perfect", "image-public", "uint8"),
        ("9c-2p-imperfect", "image-chw", "float32"),
        ("9c-3p-perfect", "image-private-chw", "uint8"),
    ],
)
def test_random_play_agrees_with_single_games(config, obs, dtype):
    n, seed = 6, 11
    venv = yokai.VecEnv(config, num_envs=n, seed=seed, obs=obs, dtype=dtype, threads=2)
    games = single_games(config, n, seed)
    episodes = [0] * n
    rng = np.random.default_rng(0)
    out = venv.reset()
    finished = 0
    for step in range(400):
        p = venv.num_players
        for i, game in enumerate(games):
            assert out["acting_seat"][i] == game.acting_seat
            for s in range(p):
                np.testing.assert_array_equal(out["obs"][i, s], game.observation(s, obs, dtype))
                np.testing.assert_array_equal(out["legal_mask"][i, s], game.legal_mask(s))
            if obs.startswith("graph"):
                np.testing.assert_array_equal(out["adjacency"][i], game.adjacency())
        # Random legal actions for the acting seat, sometimes as a joint [N, P] array.
        actions = np.array(
            [rng.choice(out["legal_mask"][i, out["acting_seat"][i]].nonzero()[0]) for i in range(n)]
        )
        if step % 2:
            joint = np.zeros((n, p), dtype=np.int64)
            joint[np.arange(n), out["acting_seat"]] = actions
            out = venv.step(joint)
        else:
            out = venv.step(actions)
        for i, game in enumerate(games):
            reward, shaping, done = game.step(int(actions[i]))
            assert out["reward"][i] == reward
            assert out["shaping"][i] == shaping
            assert out["done"][i] == done
            if done:
                finished += 1
                outcome = game.outcome
                for key in ["reward", "won", "early_end", "length", "correct_hints", "wrong_hints", "score"]:
                    assert out["final"][key][i] == outcome[key], key
                episodes[i] += 1
                game.reset(yokai.episode_seed(seed, i, episodes[i]))
            else:
                assert out["final"]["length"][i] == 0
    assert finished > 10, "the test should cross several auto-resets"


def test_channels_first_images_are_the_spec_images_transposed():
    hwc = yokai.VecEnv("9c-2p-perfect", num_envs=4, seed=5, obs="image")
    chw = yokai.VecEnv("9c-2p-perfect", num_envs=4, seed=5, obs="image-chw")
    a, b = hwc.reset(), chw.reset()
    assert b["obs"].shape == (4, 2, 14, 9, 10)
    for step in range(60):
        np.testing.assert_array_equal(b["obs"], a["obs"].transpose(0, 1, 4, 2, 3))
        actions = hwc.sample_actions(seed=step)
        a, b = hwc.step(actions), chw.step(actions)


def test_arrays_have_documented_shapes_and_dtypes():
    n = 5
    for dtype, np_dtype in [("float32", np.float32), ("uint8", np.uint8), (np.uint8, np.uint8)]:
        venv = yokai.VecEnv("9c-3p-perfect", num_envs=n, obs="image", dtype=dtype)
        out = venv.reset()
        p, n_a = 3, venv.num_actions
        assert out["obs"].shape == (n, p, *venv.observation_shape)
        assert out["obs"].dtype == np_dtype
        assert out["legal_mask"].shape == (n, p, n_a) and out["legal_mask"].dtype == np.uint8
        for key, kind in [("reward", np.float32), ("shaping", np.float32), ("done", np.bool_), ("acting_seat", np.uint8)]:
            assert out[key].shape == (n,) and out[key].dtype == kind, key
        assert out["final"]["won"].dtype == np.bool_
        assert out["final"]["reward"].shape == (n,)
    graph = yokai.VecEnv("9c-2p-perfect", num_envs=n, obs="graph").reset()
    assert graph["adjacency"].shape == (n, 9, 9)
    assert "obs" not in yokai.VecEnv("9c-2p-perfect", num_envs=n, obs="none").reset()


def test_float_observations_are_scaled_to_unit_range():
    venv = yokai.VecEnv("16c-2p-perfect", num_envs=8, dtype="float32")
    out = venv.reset()
    for t in range(50):
        assert out["obs"].min() >= 0.0 and out["obs"].max() <= 1.0
        out = venv.step(venv.sample_actions(t))


def test_arrays_are_read_only_views_updated_in_place():
    venv = yokai.VecEnv(num_envs=4, seed=3)
    first = venv.reset()
    obs = first["obs"]
    before = obs.copy()
    with pytest.raises(ValueError):
        obs[0, 0, 0, 0, 0] = 1.0
    second = venv.step(venv.sample_actions(0))
    assert np.shares_memory(obs, second["obs"])
    assert not np.array_equal(before, obs), "a view shows the newest step"


def test_sample_actions_are_legal_and_deterministic():
    venv = yokai.VecEnv(num_envs=64, seed=0)
    out = venv.reset()
    for t in range(100):
        a = venv.sample_actions(t)
        assert a.dtype == np.uint32
        np.testing.assert_array_equal(a, venv.sample_actions(t))
        masks = out["legal_mask"][np.arange(64), out["acting_seat"]]
        assert masks[np.arange(64), a].all()
        out = venv.step(a)


def test_same_seed_same_trajectory_any_thread_count():
    def trajectory(threads):
        venv = yokai.VecEnv("9c-2p-perfect", num_envs=40, seed=5, threads=threads)
        venv.reset()
        rewards = []
        for t in range(150):
            out = venv.step(venv.sample_actions(t))
            rewards.append(out["reward"].copy())
        return np.array(rewards), out["obs"].copy()

    r1, o1 = trajectory(1)
    r2, o2 = trajectory(2)
    np.testing.assert_array_equal(r1, r2)
    np.testing.assert_array_equal(o1, o2)


def test_reset_with_a_new_seed_changes_the_deals():
    venv = yokai.VecEnv(num_envs=3, seed=0, obs="none")
    venv.reset(seed=9)
    assert venv.seed == 9
    for i in range(3):
        assert venv.render(i) == yokai.Env("9c-2p-perfect", yokai.episode_seed(9, i, 0)).render()


def test_run_random_plays_whole_games():
    venv = yokai.VecEnv(num_envs=16, obs="none")
    venv.reset()
    ended = venv.run_random(400, 0)
    # The same steps from Python, on a twin: sample_actions(t) is run_random's sampler at
    # step t, so the twin ends exactly as many games.
    twin = yokai.VecEnv(num_envs=16, obs="none")
    twin.reset()
    twin_ended = sum(int(twin.step(twin.sample_actions(t))["done"].sum()) for t in range(400))
    assert ended == twin_ended
    # Random games last about 20 steps (docs/bots.md), so 16 × 400 steps end hundreds.
    assert 16 * 400 / 40 < ended < 16 * 400 / 10, ended
