"""``yokai.gymnasium``: the single game passes Gymnasium's checker, the vector env is the
same games stepped in Rust, and a CleanRL-style PPO learns on it."""

import importlib.util
import pathlib
import sys

import numpy as np
import pytest

import yokai
from gymnasium.utils.env_checker import check_env
from gymnasium.vector import AutoresetMode
from yokai.gymnasium import YokaiEnv, YokaiVectorEnv


def test_the_single_game_passes_gymnasiums_checker():
    check_env(YokaiEnv(illegal="end"), skip_render_check=True)


def test_an_illegal_action_raises_and_changes_nothing_or_ends_the_episode():
    env = YokaiEnv()
    obs, info = env.reset(seed=4)
    illegal = int(np.flatnonzero(~info["action_mask"])[0])
    with pytest.raises(yokai.IllegalActionError):
        env.step(illegal)
    again = YokaiEnv()
    obs2, info2 = again.reset(seed=4)
    assert np.array_equal(env._observe()[0], obs2) and np.array_equal(env.action_masks(), info2["action_mask"])
    ending = YokaiEnv(illegal="end", illegal_reward=-3.0)
    ending.reset(seed=4)
    _, reward, terminated, truncated, info = ending.step(illegal)
    assert (reward, terminated, truncated, info["illegal"]) == (-3.0, True, False, True)
    with pytest.raises(RuntimeError, match="reset"):
        ending.step(0)
    # An index outside the action space is illegal too (the engine refuses it).
    ending.reset(seed=4)
    assert ending.step(10**6)[2:4] == (True, False)


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="image encoding"):
        YokaiEnv(obs="graph")
    with pytest.raises(ValueError, match="illegal="):
        YokaiEnv(illegal="ignore")
    venv = YokaiVectorEnv(num_envs=4)
    venv.reset()
    with pytest.raises(ValueError, match=r"shape \(4,\)"):
        venv.step(np.zeros(3, dtype=np.int64))
    venv.close()
    with pytest.raises(RuntimeError, match="closed"):
        venv.reset()


def test_the_vector_env_is_the_single_games_stepped_together():
    """Every game of a YokaiVectorEnv is the YokaiEnv dealt from its seed stream, step for
    step: observations, masks, rewards, terminations, and the next deal after each end."""
    n, seed = 12, 5
    venv = YokaiVectorEnv(num_envs=n, seed=seed, shaping=0.5)
    assert venv.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    assert venv.observation_space.shape == (n, *venv.single_observation_space.shape)
    singles = [YokaiEnv(shaping=0.5) for _ in range(n)]
    episodes = [0] * n
    obs, info = venv.reset(seed=seed)
    for i, env in enumerate(singles):
        o, inf = env.reset(seed=yokai.episode_seed(seed, i, 0))
        assert np.array_equal(obs[i], o) and np.array_equal(info["action_mask"][i], inf["action_mask"])
    rng = np.random.default_rng(0)
    finished = 0
    for _ in range(150):
        assert venv.observation_space.contains(obs)
        actions = np.array([rng.choice(np.flatnonzero(m)) for m in info["action_mask"]])
        obs, reward, term, trunc, info = venv.step(actions)
        assert not trunc.any()
        for i, env in enumerate(singles):
            o, r, t, _, inf = env.step(actions[i])
            assert r == pytest.approx(reward[i]) and t == term[i]
            if t:
                finished += 1
                assert info["_final_info"][i]
                assert info["final_info"]["reward"][i] == inf["outcome"]["reward"]
                episodes[i] += 1
                o, inf = env.reset(seed=yokai.episode_seed(seed, i, episodes[i]))
            assert np.array_equal(obs[i], o), i
            assert np.array_equal(info["action_mask"][i], inf["action_mask"]), i
            assert info["acting_seat"][i] == inf["acting_seat"]
    assert finished >= n  # 150 steps hold several games of every slot


def load_example():
    path = pathlib.Path(__file__).resolve().parents[1] / "examples" / "ppo_gymnasium.py"
    spec = importlib.util.spec_from_file_location("ppo_gymnasium", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["ppo_gymnasium"] = module
    spec.loader.exec_module(module)
    return module


def test_a_cleanrl_style_ppo_learns_on_the_vector_env():
    pytest.importorskip("torch")
    log = load_example().main(["--updates", "40", "--seed", "0"])
    assert [line["env_steps"] for line in log][-1] == 40 * 64 * 32
    assert all(line["games"] >= 64 for line in log)
    # The shaped return it optimises rises by more than 0.8: learning happened (8.75 over
    # the first five updates, 10.34 over the last five when written; its game reward R
    # stays near random play's -4.0 at this length, as the example's docstring says).
    first = np.mean([line["shaped_return"] for line in log[:5]])
    last = np.mean([line["shaped_return"] for line in log[-5:]])
    assert last > first + 0.8, (first, last)
