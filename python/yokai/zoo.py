"""PettingZoo environments over :class:`yokai.Env`.

``parallel_env()`` is a ``pettingzoo.ParallelEnv``: every seat submits an action each step,
NOOP (index 0) for every seat but the acting one, exactly as in the engine. ``env()`` is the
AEC form through PettingZoo's ``parallel_to_aec`` converter.

Agents are ``"seat_0"`` … ``"seat_{P-1}"``. Each observation is a dict with
``"observation"`` (the seat's image or graph-node observation) and ``"action_mask"``
(int8, 1 = legal; only NOOP for seats that are not acting), as PettingZoo's classic games
do. All seats share the team reward: the game reward R on the final step, plus the shaping
reward of each step when ``shaping=True``. Games always end by themselves, so there are no
truncations. Needs the ``pettingzoo`` extra: ``pip install "./python[pettingzoo]"`` from the
repository (the distribution is ``yokai-learning-environment``; ``yokai`` on PyPI is
another project).
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv
from pettingzoo.utils.conversions import parallel_to_aec

from ._core import Env, IllegalActionError

__all__ = ["YokaiParallelEnv", "parallel_env", "env"]

#: Largest value of any channel of the uint8 image encoding, per dtype, for Box bounds.
_UINT8_HIGH = 255


class YokaiParallelEnv(ParallelEnv):
    """Yōkai as a PettingZoo ParallelEnv (see the module docs)."""

    metadata = {"name": "yokai_v0", "render_modes": ["ansi", "human"], "is_parallelizable": True}

    def __init__(
        self,
        config: str = "9c-2p-perfect",
        obs: str = "image",
        dtype: str = "float32",
        shaping: bool = False,
        render_mode: Optional[str] = None,
        seed: int = 0,
        illegal: str = "raise",
        illegal_reward: float = -1.0,
    ) -> None:
        if illegal not in ("raise", "end"):
            raise ValueError(f"illegal={illegal!r}: 'raise' (an error, nothing changes) or 'end' (the game ends)")
        self._illegal, self._illegal_reward = illegal, float(illegal_reward)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be one of {self.metadata['render_modes']} or None, "
                f"not {render_mode!r}"
            )
        self._game = Env(config, seed)
        self._obs = obs
        self._dtype = np.dtype(dtype)
        if self._dtype not in (np.dtype(np.float32), np.dtype(np.uint8)):
            raise ValueError(f"dtype must be float32 or uint8, not {self._dtype}")
        self._shaping = shaping
        self.render_mode = render_mode
        self.possible_agents = [f"seat_{s}" for s in range(self._game.num_players)]
        self.agents: list[str] = []
        shape = tuple(self._game.observation_shape(obs))
        high = 1.0 if self._dtype == np.float32 else _UINT8_HIGH
        self._observation_spaces = {
            agent: spaces.Dict(
                {
                    "observation": spaces.Box(0, high, shape, self._dtype),
                    "action_mask": spaces.Box(0, 1, (self._game.num_actions,), np.int8),
                }
            )
            for agent in self.possible_agents
        }
        self._action_spaces = {
            agent: spaces.Discrete(self._game.num_actions) for agent in self.possible_agents
        }

    # The same space object each call, as PettingZoo requires.
    def observation_space(self, agent: str) -> spaces.Space:
        return self._observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space:
        return self._action_spaces[agent]

    @property
    def game(self) -> Env:
        """The underlying :class:`yokai.Env` (for rendering, replays, introspection)."""
        return self._game

    def _observe(self, seat: int) -> dict[str, np.ndarray]:
        return {
            "observation": self._game.observation(seat, self._obs, self._dtype),
            "action_mask": self._game.legal_mask(seat).view(np.int8),
        }

    def _infos(self) -> dict[str, dict[str, Any]]:
        acting = self._game.acting_seat
        return {
            agent: {"acting": s == acting, "substep": self._game.substep}
            for s, agent in enumerate(self.possible_agents)
        }

    def reset(
        self, seed: Optional[int] = None, options: Optional[dict] = None
    ) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, dict[str, Any]]]:
        """Deal a new game (from ``seed`` when given, else the next seed)."""
        self._game.reset(seed)
        self.agents = list(self.possible_agents)
        observations = {agent: self._observe(s) for s, agent in enumerate(self.agents)}
        return observations, self._infos()

    def step(self, actions: dict[str, int]):
        """Play one step. The acting seat's action is required; the other seats may be
        left out or must be NOOP (0). An illegal action raises ``yokai.IllegalActionError``
        (the game is unchanged), or with ``illegal="end"`` ends the game with every seat
        rewarded ``illegal_reward`` and ``infos[agent]["illegal"] = True``, as PettingZoo's
        classic games do (for PettingZoo's ``parallel_seed_test``, which samples actions
        without their masks)."""
        if not self.agents:
            raise RuntimeError("the game is over: call reset() first")
        unknown = set(actions) - set(self.agents)
        if unknown:
            raise ValueError(f"actions for unknown agents {sorted(unknown)}")
        acting = self.possible_agents[self._game.acting_seat]
        if acting not in actions:
            raise ValueError(f"{acting} acts now and must be given an action")
        joint = [int(actions.get(agent, 0)) for agent in self.possible_agents]
        try:
            reward, shaping, done = self._game.step_joint(joint)
        except IllegalActionError:  # the engine changed nothing
            if self._illegal == "raise":
                raise
            return self._end_on_illegal()
        team = float(reward + (shaping if self._shaping else 0))
        agents = self.agents
        observations = {agent: self._observe(s) for s, agent in enumerate(agents)}
        rewards = {agent: team for agent in agents}
        terminations = {agent: done for agent in agents}
        truncations = {agent: False for agent in agents}
        infos = self._infos()
        if done:
            outcome = self._game.outcome
            for agent in agents:
                infos[agent]["outcome"] = outcome
            self.agents = []
        if self.render_mode == "human":
            print(self.render())
        return observations, rewards, terminations, truncations, infos

    def _end_on_illegal(self):
        agents, self.agents = self.agents, []
        observations = {agent: self._observe(s) for s, agent in enumerate(agents)}
        infos = self._infos()
        for agent in agents:
            infos[agent]["illegal"] = True
        return (
            observations,
            {agent: self._illegal_reward for agent in agents},
            {agent: True for agent in agents},
            {agent: False for agent in agents},
            infos,
        )

    def render(self) -> Optional[str]:
        """The true board as text (``ansi``), or printed (``human``)."""
        if self.render_mode is None:
            return None
        return self._game.render()

    def state(self) -> np.ndarray:
        """The true colour of every card (hidden information, for centralised critics)."""
        return self._game.ground_truth()

    def close(self) -> None:
        pass


def parallel_env(**kwargs: Any) -> YokaiParallelEnv:
    """A :class:`YokaiParallelEnv`; keyword arguments as its constructor."""
    return YokaiParallelEnv(**kwargs)


def env(**kwargs: Any):
    """The AEC form of :func:`parallel_env`, through PettingZoo's converter."""
    return parallel_to_aec(parallel_env(**kwargs))
