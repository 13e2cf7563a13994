"""Pretrained agents built into the package: listed with their scores, seated by name or
with ``Agent.pretrained``, refused clearly when unknown."""

import pytest

import yokai


def test_the_list_names_each_preset_with_its_seeds_and_scores():
    agents = yokai.pretrained_agents()
    presets = [a["preset"] for a in agents]
    assert "quick" in presets and "cpu-fast" in presets
    for a in agents:
        assert len(a["seeds"]) == len(a["sp_r"]) == len(a["sp_se"]) >= 1
        assert a["games"] >= 1000 and a["steps"] > 0
        assert a["command"].startswith("yokai train ")
        # Every shipped agent plays far above random play (R -4.0).
        assert all(r > 0 for r in a["sp_r"]), a


def test_agent_pretrained_is_the_agent_of_that_name():
    by_method = yokai.Agent.pretrained("quick", seed=1, agent_seed=5)
    assert by_method.name == "pretrained:quick/1"
    by_name = yokai.Agent("pretrained:quick/1", 5)
    a = yokai.play("9c-2p-perfect", [by_method, yokai.Agent("pretrained:quick/1", 6)], seed=3)
    b = yokai.play("9c-2p-perfect", [by_name, yokai.Agent("pretrained:quick/1", 6)], seed=3)
    assert a.to_replay() == b.to_replay()
    assert a.done


def test_pretrained_self_play_beats_greedy_over_some_games():
    # quick/0 documents R 5.27 in self-play; greedy with itself scores 0.51.
    rewards = []
    for seed in range(40):
        env = yokai.play("9c-2p-perfect", [yokai.Agent.pretrained("quick", 0, agent_seed=seed),
                                           yokai.Agent.pretrained("quick", 0, agent_seed=seed + 1000)],
                         seed=seed)
        rewards.append(env.outcome["reward"])
    assert sum(rewards) / len(rewards) > 2.0, rewards


def test_an_unknown_pretrained_agent_lists_the_ones_built_in():
    with pytest.raises(yokai.ConfigError, match=r"no pretrained agent `pretrained:nope/0`.*pretrained:quick/0"):
        yokai.Agent.pretrained("nope")
    with pytest.raises(yokai.ConfigError, match="pretrained:quick/0"):
        yokai.Agent("pretrained:quick/9")
