"""The PettingZoo wrappers pass PettingZoo's own API tests."""

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from pettingzoo.test import api_test, parallel_api_test, parallel_seed_test, seed_test  # noqa: E402

import yokai  # noqa: E402
from yokai import zoo  # noqa: E402


@pytest.mark.parametrize("config", ["9c-2p-perfect", "9c-4p-imperfect", "16c-2p-perfect"])
def test_parallel_api(config):
    parallel_api_test(zoo.parallel_env(config=config), num_cycles=300)


def test_aec_api():
    api_test(zoo.env(config="9c-3p-perfect"), num_cycles=300)


def test_seed_tests():
    # The AEC test samples with the action masks, so it plays whole games; the parallel
    # one samples without them, so it needs illegal actions to end the game, not raise.
    seed_test(lambda: zoo.env(config="9c-2p-perfect"), num_cycles=200)
    parallel_seed_test(lambda: zoo.parallel_env(config="9c-2p-perfect", illegal="end"), num_cycles=200)


def test_an_illegal_action_ends_the_game_when_asked():
    env = zoo.parallel_env(illegal="end", illegal_reward=-2.0)
    obs, _ = env.reset(seed=3)
    illegal = int(np.flatnonzero(obs["seat_0"]["action_mask"] == 0)[0])
    _, rewards, terms, truncs, infos = env.step({"seat_0": illegal, "seat_1": 0})
    assert rewards == {"seat_0": -2.0, "seat_1": -2.0}
    assert all(terms.values()) and not any(truncs.values())
    assert all(info["illegal"] for info in infos.values()) and env.agents == []
    with pytest.raises(ValueError, match="illegal="):
        zoo.parallel_env(illegal="skip")
    # The default still refuses it and changes nothing.
    strict = zoo.parallel_env()
    strict.reset(seed=3)
    with pytest.raises(yokai.IllegalActionError):
        strict.step({"seat_0": illegal, "seat_1": 0})
    assert strict.game.steps == 0


def test_observations_lie_in_their_spaces_and_rewards_are_shared():
    # Twin games, the same seed and actions, with and without shaping.
    shaped = zoo.parallel_env(config="9c-2p-perfect", dtype="uint8", shaping=True, render_mode="ansi")
    plain = zoo.parallel_env(config="9c-2p-perfect", dtype="uint8")
    obs, infos = shaped.reset(seed=3)
    plain_obs, _ = plain.reset(seed=3)
    rng = np.random.default_rng(0)
    shaped_steps, plain_steps = [], []
    while shaped.agents:
        for agent in shaped.agents:
            assert shaped.observation_space(agent).contains(obs[agent])
            np.testing.assert_array_equal(obs[agent]["observation"], plain_obs[agent]["observation"])
        # Drawn from the test's own generator: the spaces' sample() is unseeded, and a
        # game it ended with END at once paid no shaping, failing the test at random.
        actions = {
            agent: int(rng.choice(np.flatnonzero(obs[agent]["action_mask"])))
            for agent in shaped.agents
        }
        obs, rewards, terms, truncs, infos = shaped.step(actions)
        plain_obs, plain_rewards, _, _, plain_infos = plain.step(actions)
        # Every seat gets the team's reward.
        assert len(set(rewards.values())) == 1 and len(set(plain_rewards.values())) == 1
        shaped_steps.append(rewards["seat_0"])
        plain_steps.append(plain_rewards["seat_0"])
    outcome = infos["seat_0"]["outcome"]
    assert plain_infos["seat_0"]["outcome"] == outcome
    # Without shaping the team return is R, paid on the final step alone.
    assert plain_steps[:-1] == [0.0] * (len(plain_steps) - 1)
    assert plain_steps[-1] == outcome["reward"]
    # With shaping it is R plus the shaping of every step, which pays for observing and
    # hinting: never negative, and something over a whole game.
    extra = np.array(shaped_steps) - np.array(plain_steps)
    assert (extra >= 0).all() and extra.sum() > 0, extra
    assert isinstance(shaped.render(), str)
    assert shaped.game.done


def test_acting_seat_needs_an_action():
    env = zoo.parallel_env()
    env.reset(seed=0)
    with pytest.raises(ValueError, match="seat_0 acts now"):
        env.step({"seat_1": 0})
    with pytest.raises(yokai.IllegalActionError):
        env.step({"seat_0": 0})  # NOOP at substep 0
