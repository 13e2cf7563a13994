"""The Yōkai Learning Environment: the cooperative card game Yōkai for zero-shot
coordination research, with a Rust engine.

- :class:`VecEnv` steps many games at once on all cores and returns NumPy views of its
  buffers (observations of every seat, legal-action masks, rewards, done flags, final
  metrics): hand them to PyTorch or JAX without copying.
- :class:`Env` is one game with full introspection (legal actions by name, text rendering,
  observations in every encoding, ground truth, replays).
- :func:`yokai.zoo.parallel_env` wraps :class:`Env` as a PettingZoo ``ParallelEnv``;
  :mod:`yokai.gymnasium` gives Gymnasium's ``Env`` and ``VectorEnv``; :mod:`yokai.jax` a
  JaxMARL ``MultiAgentEnv`` that works under ``jit``, ``vmap`` and ``scan``.
- :class:`TrainEnv` is the batched games of a training run as ``yokai train`` plays them
  (a row per seat, Other-Play symmetries, true colours, what END would pay);
  ``python -m yokai.torch_train`` trains the Rust presets on it in PyTorch.

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
    derive_seed,
    episode_seed,
)

try:  # absent from a wheel built with --no-default-features (no trainer, no burn)
    from ._core import TrainEnv, policy_parameters, policy_step, pretrained_agents, probe_accuracy, probe_records
except ImportError:  # pragma: no cover - exercised by the no-default-features build only

    def _needs_trainer(*_args, **_kwargs):
        raise YokaiError(
            "this build of yokai has no trainer (built with --no-default-features): "
            "install it with the default features for trained policies and probes"
        )

    policy_parameters = pretrained_agents = probe_accuracy = probe_records = policy_step = TrainEnv = _needs_trainer

__all__ = [
    "ConfigError",
    "Env",
    "IllegalActionError",
    "ReplayError",
    "TrainEnv",
    "VecEnv",
    "YokaiError",
    "__version__",
    "configs",
    "derive_seed",
    "episode_seed",
    "policy_parameters",
    "policy_step",
    "pretrained_agents",
    "probe_accuracy",
    "probe_records",
]

from ._core import Agent  # noqa: E402


def play(config: str = "9c-2p-perfect", agents=("belief", "belief"), seed: int = 0, agent_seed: int = 0) -> Env:
    """Play one game with a built-in agent per seat (names or ``Agent`` objects); every
    agent is shown every action. Returns the finished ``Env`` (``outcome``,
    ``to_replay()``, ``render()``)."""
    env = Env(config, seed)
    seats = [a if isinstance(a, Agent) else Agent(a, agent_seed + s) for s, a in enumerate(agents)]
    if len(seats) != env.num_players:
        raise ValueError(f"{len(seats)} agents for a {env.num_players}-player game")
    for s, agent in enumerate(seats):
        agent.reset(agent_seed + s)
    while not env.done:
        action = seats[env.acting_seat].act(env)
        for s, agent in enumerate(seats):
            agent.observe(env, s, action)
        env.step(action)
    return env


__all__ += ["Agent", "play"]
