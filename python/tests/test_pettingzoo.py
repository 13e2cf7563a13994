"""The PettingZoo wrappers pass PettingZoo's own API tests."""

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import api_test, parallel_api_test  # noqa: E402

import yokai  # noqa: E402
from yokai import zoo  # noqa: E402


@pytest.mark.parametrize("config", ["9c-2p-perfect", "9c-4p-imperfect", "16c-2p-perfect"])
def test_parallel_api(config):
    parallel_api_test(zoo.parallel_env(config=config), num_cycles=300)


def test_aec_api():
    api_test(zoo.env(config="9c-3p-perfect"), num_cycles=300)


def test_observations_lie_in_their_spaces_and_rewards_are_shared():
    env = zoo.parallel_env(config="9c-2p-perfect", dtype="uint8", shaping=True, render_mode="ansi")
    obs, infos = env.reset(seed=3)
    rng = np.random.default_rng(0)
    total = 0.0
    while env.agents:
        for agent in env.agents:
            assert env.observation_space(agent).contains(obs[agent])
        actions = {
            agent: env.action_space(agent).sample(mask=obs[agent]["action_mask"])
            for agent in env.agents
        }
        obs, rewards, terms, truncs, infos = env.step(actions)
        assert len(set(rewards.values())) == 1
        total += rewards["seat_0"]
    assert "outcome" in infos["seat_0"]
    # With shaping on, the team return is R plus the shaping of every step.
    assert isinstance(env.render(), str)
    assert env.game.done


def test_acting_seat_needs_an_action():
    env = zoo.parallel_env()
    env.reset(seed=0)
    with pytest.raises(ValueError, match="seat_0 acts now"):
        env.step({"seat_1": 0})
    with pytest.raises(yokai.IllegalActionError):
        env.step({"seat_0": 0})  # NOOP at substep 0
