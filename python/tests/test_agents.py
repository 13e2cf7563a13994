"""Built-in agents from Python."""

import numpy as np
import pytest

import yokai


def test_belief_self_play_from_python_matches_its_rust_score_range():
    rewards = [yokai.play("9c-2p-perfect", ["belief", "belief"], seed=s).outcome["reward"] for s in range(60)]
    # 7.24 ± 0.04 over 5,000 games in Rust (docs/bots.md); 60 games land well above 4.
    assert np.mean(rewards) > 4.0


def test_agents_play_legal_actions_and_games_replay():
    env = yokai.play("9c-3p-imperfect", ["greedy", "belief", "random"], seed=4)
    assert env.done
    again = yokai.Env.from_replay(env.to_replay())
    assert again.outcome == env.outcome


def test_agent_is_deterministic():
    a = yokai.play(agents=["belief", "greedy"], seed=9).history
    b = yokai.play(agents=["belief", "greedy"], seed=9).history
    assert a == b


def test_bad_agent_names_and_seat_counts():
    with pytest.raises(yokai.ConfigError, match="unknown policy `chess`"):
        yokai.Agent("chess")
    with pytest.raises(yokai.ConfigError, match="no parameter `depth`"):
        yokai.Agent("greedy:depth=3")
    with pytest.raises(ValueError, match="3 agents for a 2-player game"):
        yokai.play(agents=["random"] * 3)
