"""The Yōkai Learning Environment: the cooperative card game Yōkai for zero-shot
coordination research, with a Rust engine.

- :class:`VecEnv` steps many games at once on all cores and returns NumPy views of its
  buffers (observations of every seat, legal-action masks, rewards, done flags, final
  metrics): hand them to PyTorch or JAX without copying.
- :class:`Env` is one game with full introspection (legal actions by name, text rendering,
  observations in every encoding, ground truth, replays).
- :func:`yokai.pettingzoo.parallel_env` wraps :class:`Env` as a PettingZoo ``ParallelEnv``.

Errors raised by the engine derive from :class:`YokaiError` (a ``ValueError``).
"""

from ._core import (
    ConfigError,
    Env,
    IllegalActionError,
    ReplayError,
    VecEnv,
    YokaiError,
    __version__,
    configs,
    episode_seed,
)

__all__ = [
    "ConfigError",
    "Env",
    "IllegalActionError",
    "ReplayError",
    "VecEnv",
    "YokaiError",
    "__version__",
    "configs",
    "episode_seed",
]
