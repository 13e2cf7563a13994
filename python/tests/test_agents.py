"""Built-in agents from Python."""

import numpy as np
import pytest

import yokai


def test_belief_self_play_from_python_scores_as_documented():
    outcomes = [yokai.play("9c-2p-perfect", ["belief", "belief"], seed=s).outcome for s in range(300)]
    rewards = np.array([o["reward"] for o in outcomes], dtype=float)
    # docs/bots.md: R 9.78 ± 0.04 and EE 95.5 % over 5,000 games in Rust. Within 4 standard
    # errors of these 300 games (about ±0.65): a bot that lost its convention (R near 2, as
    # with a greedy partner) or never ended (R near 0.5) fails.
    se = rewards.std(ddof=1) / np.sqrt(len(rewards))
    assert abs(rewards.mean() - 9.78) < 4 * se, (rewards.mean(), se)
    early = np.mean([o["early_end"] for o in outcomes])
    assert abs(early - 0.955) < 0.05, early


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
