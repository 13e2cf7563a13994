"""Gymnasium interfaces: the game as one agent sees it when it plays every seat (self-play).

Yōkai is cooperative with one shared reward, so a single policy that acts for whichever
seat is to play is self-play, as in the Hanabi Learning Environment's single-agent view.
Each step's observation is the acting seat's; the action is the acting seat's; the reward is
the team's. The legal moves come in ``info["action_mask"]`` (bool), as Gymnasium's masked
environments give them.

- :class:`YokaiEnv` is one game, a ``gymnasium.Env`` that passes
  ``gymnasium.utils.env_checker.check_env``.
- :class:`YokaiVectorEnv` is ``num_envs`` games stepped together in Rust on all cores
  (:class:`yokai.VecEnv`), a ``gymnasium.vector.VectorEnv`` for CleanRL-style training
  loops.

Needs ``gymnasium`` >= 1.1 (``pip install "yokai-learning-environment[gymnasium]"``).
"""

from __future__ import annotations

from typing import Any, Optional

import gymnasium
import numpy as np
from gymnasium import spaces

try:
    from gymnasium.vector import AutoresetMode
except ImportError as e:  # pragma: no cover - older Gymnasium
    raise ImportError(
        f"yokai.gymnasium needs gymnasium >= 1.1 (found {gymnasium.__version__}): "
        'pip install "yokai-learning-environment[gymnasium]"'
    ) from e

from . import Env, IllegalActionError, VecEnv

__all__ = ["YokaiEnv", "YokaiVectorEnv"]

_ENCODINGS = ("image", "image-chw", "image-public", "image-private", "image-public-chw", "image-private-chw")


def _check_encoding(obs: str) -> None:
    if obs not in _ENCODINGS:
        raise ValueError(f"obs={obs!r}: the Gymnasium interfaces take an image encoding, one of {', '.join(_ENCODINGS)}")


def _observation_space(shape) -> spaces.Box:
    # Every channel of the image encodings lies in [0, 1] (docs/spec/rules.md, section 5).
    return spaces.Box(low=0.0, high=1.0, shape=tuple(shape), dtype=np.float32)


class YokaiEnv(gymnasium.Env):
    """One game of ``config`` from the acting seat's point of view.

    ``reset(seed=s)`` deals game ``s`` (the same deal as ``yokai.Env(config, s)``);
    ``reset()`` deals the next game of the stream. ``step(action)`` plays the acting seat's
    action and returns the next acting seat's observation. The reward is the game's
    (terminal) reward plus ``shaping`` times its shaping term (0 by default: the paper's R).

    An illegal action raises :class:`yokai.IllegalActionError` and changes nothing
    (``illegal="raise"``, the default). With ``illegal="end"`` it ends the episode instead,
    with reward ``illegal_reward`` and ``info["illegal"] = True``, as PettingZoo's classic
    games do: for learners that sample from the whole action space (and for Gymnasium's
    ``check_env``, which steps random actions).
    """

    metadata = {"render_modes": ["ansi"]}

    def __init__(self, config: str = "9c-2p-perfect", obs: str = "image", shaping: float = 0.0,
                 render_mode: Optional[str] = None, illegal: str = "raise", illegal_reward: float = -1.0):
        _check_encoding(obs)
        if illegal not in ("raise", "end"):
            raise ValueError(f"illegal={illegal!r}: 'raise' (an error, nothing changes) or 'end' (the episode ends)")
        self._illegal, self._illegal_reward = illegal, float(illegal_reward)
        self._ended = False
        if render_mode not in (None, "ansi"):
            raise ValueError(f"render_mode={render_mode!r}: YokaiEnv renders as text, render_mode='ansi'")
        self._obs, self._shaping = obs, float(shaping)
        self.render_mode = render_mode
        self._game = Env(config, 0)
        self.observation_space = _observation_space(self._game.observation_shape(obs))
        self.action_space = spaces.Discrete(self._game.num_actions)
        self._dealt = False

    def _observe(self) -> tuple[np.ndarray, dict[str, Any]]:
        seat = self._game.acting_seat
        obs = np.asarray(self._game.observation(seat, self._obs, "float32"), dtype=np.float32)
        info = {"action_mask": self._game.legal_mask(seat).astype(bool), "acting_seat": seat}
        return obs, info

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        if seed is None and not self._dealt:  # a first deal drawn from Gymnasium's generator
            seed = int(self.np_random.integers(0, 2**63 - 1))
        self._game.reset(None if seed is None else int(seed))  # None: the previous deal + 1
        self._dealt, self._ended = True, False
        return self._observe()

    def _terminal(self, **extra) -> tuple[np.ndarray, dict[str, Any]]:
        self._ended = True
        info = {"action_mask": np.zeros(self.action_space.n, bool), "acting_seat": -1, **extra}
        return np.zeros(self.observation_space.shape, np.float32), info

    def step(self, action):
        if self._ended or self._game.done:
            raise RuntimeError("the episode has ended: call reset()")
        try:
            reward, shaping, done = self._game.step(int(action))
        except IllegalActionError:  # the engine changed nothing
            if self._illegal == "raise":
                raise
            obs, info = self._terminal(illegal=True)
            return obs, self._illegal_reward, True, False, info
        if done:
            obs, info = self._terminal(outcome=self._game.outcome)
        else:
            obs, info = self._observe()
        return obs, float(reward + self._shaping * shaping), bool(done), False, info

    def render(self):
        return self._game.render()

    def action_masks(self) -> np.ndarray:
        """The acting seat's legal moves (the method sb3-contrib's MaskablePPO calls)."""
        return self._game.legal_mask(self._game.acting_seat).astype(bool)


class YokaiVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` games of ``config`` stepped together in Rust (:class:`yokai.VecEnv`),
    each from its acting seat's point of view.

    Autoreset is ``SAME_STEP``: a game that ends is dealt anew within the same ``step``, so
    the returned observation is the next game's first. ``infos["final_info"]`` then holds
    the finished games' metrics (``reward``, ``won``, ``early_end``, ``length``, …, arrays
    over all envs, valid where ``infos["_final_info"]`` is True). The terminal observation
    itself is not kept: a finished game has no value to bootstrap from, so ``final_obs`` is
    absent. ``infos["action_mask"]`` is the acting seats' legal moves, [N, N_a] bool.
    Illegal actions raise :class:`yokai.IllegalActionError` and change nothing.
    """

    metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}

    def __init__(self, config: str = "9c-2p-perfect", num_envs: int = 64, seed: int = 0, obs: str = "image",
                 shaping: float = 0.0, threads: Optional[int] = None):
        _check_encoding(obs)
        self._env = VecEnv(config, num_envs=num_envs, seed=seed, obs=obs, dtype="float32", threads=threads)
        self._shaping = float(shaping)
        self.num_envs = self._env.num_envs
        self.single_observation_space = _observation_space(self._env.observation_shape)
        self.single_action_space = spaces.Discrete(self._env.num_actions)
        self.observation_space = gymnasium.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = gymnasium.vector.utils.batch_space(self.single_action_space, self.num_envs)
        self._rows = np.arange(self.num_envs)
        self.closed = False

    def _view(self, out: dict) -> tuple[np.ndarray, dict[str, Any]]:
        seats = out["acting_seat"].astype(np.intp)
        obs = np.ascontiguousarray(out["obs"][self._rows, seats], dtype=np.float32)
        info = {"action_mask": out["legal_mask"][self._rows, seats].astype(bool), "acting_seat": seats.copy()}
        return obs, info

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Restart every game; ``seed`` starts a new deal stream (game i's first deal is
        ``yokai.episode_seed(seed, i, 0)``)."""
        if self.closed:
            raise RuntimeError("this YokaiVectorEnv is closed")
        return self._view(self._env.reset(seed))

    def step(self, actions):
        if self.closed:
            raise RuntimeError("this YokaiVectorEnv is closed")
        actions = np.asarray(actions)
        if actions.shape != (self.num_envs,):
            raise ValueError(f"actions of shape {actions.shape}: one action per game, shape ({self.num_envs},)")
        out = self._env.step(actions)
        obs, info = self._view(out)
        done = out["done"].copy()
        reward = out["reward"].astype(np.float32) + np.float32(self._shaping) * out["shaping"]
        if done.any() and out["final"] is not None:
            info["final_info"] = {k: np.asarray(v).copy() for k, v in out["final"].items()}
            info["_final_info"] = done.copy()
        return obs, reward, done, np.zeros(self.num_envs, bool), info

    def close_extras(self, **kwargs):
        self._env = None
