"""Yōkai as a JaxMARL environment that works under ``jax.jit``, ``jax.vmap`` and
``jax.lax.scan``.

:class:`YokaiEnv` is a ``jaxmarl`` ``MultiAgentEnv``: ``reset(key)``, ``step(key, state,
actions)`` with dicts keyed by agent and auto-reset, ``get_avail_actions(state)``,
``observation_space(agent)``, ``action_space(agent)``. Training code written for JaxMARL's
environments (its Hanabi, with ``LogWrapper``) runs with only the environment swapped.

How it works: the state is a pytree of three arrays — the game packed into
``PACKED_LEN`` bytes, the game's seed stream and its episode number — and every
transition runs in the Rust engine through ``jax.pure_callback`` with
``vmap_method="broadcast_all"``: under ``vmap`` one call steps every game of the batch,
in parallel on all cores. Each call is a pure function of its arrays, so ``jit`` may
cache, reorder or repeat it freely.

Deals: ``reset(key)`` draws a 64-bit stream seed from ``key``; episode ``e`` of stream
``s`` is dealt from ``yokai.derive_seed(s, e)``, and an auto-reset deals the next
episode of the same stream. The stream ``derive_seed(seed, i)`` plays exactly the games of
env ``i`` of ``yokai.VecEnv(seed=seed)`` (``reset_from_stream``).

Bad input: an action dict without an agent is a ``KeyError``, a float action a
``TypeError``, a batched action outside ``vmap`` a ``ValueError`` (all at trace time). An
illegal action leaves its game unchanged, gives reward 0 and sets ``infos["illegal"]``.
A state whose bytes are not a packed game raises inside the callback, which JAX reports as
a runtime error carrying the engine's message.

Install with ``pip install "yokai-learning-environment[jax]"``.
"""

from __future__ import annotations

from typing import Dict, Optional, Tuple

import jax
import jax.numpy as jnp
import numpy as np
from flax import struct
from jaxmarl.environments import spaces
from jaxmarl.environments.multi_agent_env import MultiAgentEnv

from . import _core

PACKED_LEN = _core.PackedGames.packed_len

__all__ = ["PACKED_LEN", "State", "YokaiEnv", "stream_of_key", "streams_of_seed"]


@struct.dataclass
class State:
    """One game as JAX arrays (add leading axes with ``vmap``)."""

    #: ``uint8[PACKED_LEN]``: the game, packed by the engine (``Game::pack``).
    packed: jax.Array
    #: ``uint32[2]``: the 64-bit seed stream of this game's deals (low word first).
    stream: jax.Array
    #: ``uint32[]``: the episode of the stream being played.
    episode: jax.Array
    #: ``bool[P, N_a]``: each seat's legal actions, kept so that ``get_avail_actions``
    #: needs no call into the engine.
    legal: jax.Array


def stream_of_key(key: jax.Array) -> jax.Array:
    """The ``uint32[2]`` stream seed that ``reset(key)`` deals from."""
    return jax.random.bits(key, (2,), jnp.uint32)


def streams_of_seed(seed: int, num_envs: int) -> np.ndarray:
    """``uint32[num_envs, 2]``: the streams of envs ``0..num_envs`` of ``VecEnv(seed=seed)``,
    for ``vmap(env.reset_from_stream)``."""
    s = np.array([_core.derive_seed(seed, i) for i in range(num_envs)], dtype=np.uint64)
    return np.stack([s & 0xFFFFFFFF, s >> 32], axis=-1).astype(np.uint32)


def _rows(packed) -> Tuple[np.ndarray, tuple]:
    """A callback's packed games ``[..., PACKED_LEN]`` (the batch axes ``vmap`` added) as
    ``[n, PACKED_LEN]`` rows for the engine, and the batch axes to give its results back."""
    packed = np.asarray(packed)
    return packed.reshape(-1, PACKED_LEN), packed.shape[:-1]


def _to_u64(stream: np.ndarray) -> np.ndarray:
    stream = np.asarray(stream, dtype=np.uint64)
    return stream[..., 0] | (stream[..., 1] << np.uint64(32))


class YokaiEnv(MultiAgentEnv):
    """Yōkai for JaxMARL training loops.

    ``config``: a configuration name (``"9c-2p-perfect"``) or TOML path. ``obs``:
    ``"flat"`` (the image as one vector per seat, as JaxMARL's Hanabi gives), ``"image"``
    ``[g, g+1, F]``, ``"image-chw"`` ``[F, g, g+1]``, or either with ``-public`` /
    ``-private`` for that part of the image. ``shaping``: weight of the shaping reward
    added to each step's reward (0: the game reward R alone, on the last step).
    """

    def __init__(self, config: str = "9c-2p-perfect", obs: str = "flat", shaping: float = 0.0):
        encoding, self._flat = _encoding(obs)
        self._games = _core.PackedGames(config, encoding)
        super().__init__(num_agents=self._games.num_players)
        self.config = config
        self.obs_name = obs
        self.shaping = float(shaping)
        self.num_actions = self._games.num_actions
        shape = tuple(self._games.observation_shape)
        self._image_shape = shape
        self._obs_shape = (int(np.prod(shape)),) if self._flat else shape
        for agent in self.agents:
            self.observation_spaces[agent] = spaces.Box(0.0, 1.0, self._obs_shape, jnp.float32)
            self.action_spaces[agent] = spaces.Discrete(self.num_actions)

    # --- the MultiAgentEnv interface --------------------------------------------------

    def reset(self, key: jax.Array) -> Tuple[Dict[str, jax.Array], State]:
        """A new game dealt from ``key``."""
        return self.reset_from_stream(stream_of_key(key))

    def reset_from_stream(self, stream: jax.Array) -> Tuple[Dict[str, jax.Array], State]:
        """Episode 0 of the stream ``uint32[2]`` (see :func:`streams_of_seed`)."""
        stream = jnp.asarray(stream, jnp.uint32)
        if stream.shape != (2,):
            raise ValueError(f"a stream is uint32[2] per game, got shape {stream.shape}: vmap over games")
        out = jax.pure_callback(self._reset_host, self._result_shapes(), stream, vmap_method="broadcast_all")
        state = State(packed=out[0], stream=stream, episode=out[1], legal=out[3])
        return self._obs_dict(out[2]), state

    def step(
        self,
        key: jax.Array,
        state: State,
        actions: Dict[str, jax.Array],
        reset_state: Optional[State] = None,
    ):
        """Play the acting seat's action (waiting seats submit NOOP, action 0). A game
        that ends is replaced by the next episode of its stream, or by ``reset_state``
        when given; on that step the observations are the new game's, and ``rewards``
        and ``dones`` describe the finished one."""
        del key  # deals come from the state's stream
        if reset_state is None:
            return self._step(state, actions, autoreset=True)
        obs, new, rewards, dones, infos = self._step(state, actions, autoreset=False)
        done = dones["__all__"]
        obs_re = self.get_obs(reset_state)
        new = jax.tree.map(lambda r, s: jax.lax.select(done, r, s), reset_state, new)
        obs = jax.tree.map(lambda r, s: jax.lax.select(done, r, s), obs_re, obs)
        return obs, new, rewards, dones, infos

    def step_env(self, key: jax.Array, state: State, actions: Dict[str, jax.Array]):
        """One transition without auto-reset: a finished game stays finished."""
        del key
        return self._step(state, actions, autoreset=False)

    def get_obs(self, state: State) -> Dict[str, jax.Array]:
        return self._obs_dict(self._observe(state)[2])

    def get_avail_actions(self, state: State) -> Dict[str, jax.Array]:
        """Boolean masks ``[N_a]`` per agent: the waiting seat's only legal action is NOOP."""
        return {agent: state.legal[i] for i, agent in enumerate(self.agents)}

    def get_legal_moves(self, state: State) -> Dict[str, jax.Array]:
        """The same masks under the name JaxMARL's Hanabi gives them, so its scripts run."""
        return self.get_avail_actions(state)

    @property
    def name(self) -> str:
        return f"Yokai-{self.config}"

    @property
    def agent_classes(self) -> dict:
        return {"agents": list(self.agents)}

    # --- conveniences -------------------------------------------------------------------

    def acting_seat(self, state: State) -> jax.Array:
        """The seat to act (``uint8``)."""
        return self._observe(state)[4]

    def render(self, state: State) -> str:
        """The true board of one (unbatched) game as text. Not jittable: for looking at a
        state, not for training loops."""
        return self._games.render(np.asarray(state.packed))

    # --- the callbacks --------------------------------------------------------------------

    def _result_shapes(self):
        p, a = self.num_agents, self.num_actions
        sds = jax.ShapeDtypeStruct
        return (
            sds((PACKED_LEN,), jnp.uint8),  # packed
            sds((), jnp.uint32),  # episode
            sds((p,) + self._image_shape, jnp.float32),  # obs
            sds((p, a), jnp.bool_),  # legal masks
            sds((), jnp.uint8),  # acting seat
            sds((), jnp.float32),  # reward
            sds((), jnp.float32),  # shaping
            sds((), jnp.bool_),  # done
            sds((), jnp.bool_),  # illegal
        )

    @staticmethod
    def _unbatch(out: dict, lead: tuple):
        keys = ("state", "episode", "obs", "legal_mask", "acting_seat", "reward", "shaping", "done", "illegal")
        return tuple(out[k].reshape(lead + out[k].shape[1:]) for k in keys)

    def _reset_host(self, stream):
        stream = np.asarray(stream)
        lead = stream.shape[:-1]
        out = self._games.reset(_to_u64(stream.reshape(-1, 2)))
        return self._unbatch(out, lead)

    def _step_host(self, packed, stream, episode, actions, autoreset):
        packed, lead = _rows(packed)
        n = len(packed)
        out = self._games.step(
            packed,
            _to_u64(np.asarray(stream).reshape(n, 2)),
            np.asarray(episode, dtype=np.uint32).reshape(n),
            np.asarray(actions, dtype=np.uint32).reshape(n, self.num_agents),
            bool(autoreset),
        )
        return self._unbatch(out, lead)

    def _observe_host(self, packed, episode):
        packed, lead = _rows(packed)
        out = self._games.observe(packed, np.asarray(episode, dtype=np.uint32).reshape(len(packed)))
        return self._unbatch(out, lead)

    def _observe(self, state: State):
        return jax.pure_callback(
            self._observe_host, self._result_shapes(), state.packed, state.episode, vmap_method="broadcast_all"
        )

    def _step(self, state: State, actions: Dict[str, jax.Array], autoreset: bool):
        joint = self._joint_actions(actions)
        out = jax.pure_callback(
            lambda *a: self._step_host(*a, autoreset),
            self._result_shapes(),
            state.packed,
            state.stream,
            state.episode,
            joint,
            vmap_method="broadcast_all",
        )
        packed, episode, obs, legal, _, reward, shaping, done, illegal = out
        new = State(packed=packed, stream=state.stream, episode=episode, legal=legal)
        r = reward + self.shaping * shaping
        rewards = {agent: r for agent in self.agents}
        rewards["__all__"] = r
        dones = {agent: done for agent in self.agents}
        dones["__all__"] = done
        p = self.num_agents
        infos = {
            "illegal": jnp.full((p,), illegal),
            "game_reward": jnp.full((p,), reward),
            "shaping": jnp.full((p,), shaping),
        }
        return self._obs_dict(obs), new, rewards, dones, infos

    def _joint_actions(self, actions: Dict[str, jax.Array]) -> jax.Array:
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise KeyError(f"actions has no entry for {missing} (expected one per agent of {self.agents})")
        values = []
        for agent in self.agents:
            a = jnp.asarray(actions[agent])
            if not jnp.issubdtype(a.dtype, jnp.integer):
                raise TypeError(f"actions[{agent!r}] must be an integer action index, got dtype {a.dtype}")
            if a.shape != ():
                raise ValueError(
                    f"actions[{agent!r}] has shape {a.shape}; step takes one action per agent "
                    "per game: jax.vmap(env.step) over a batch of games"
                )
            # Indices outside uint32 (negative ones) become one the engine flags illegal.
            bad = a < 0
            if a.dtype.itemsize > 4:
                bad = bad | (a > 0xFFFFFFFF)
            values.append(jnp.where(bad, jnp.uint32(0xFFFFFFFF), a.astype(jnp.uint32)))
        return jnp.stack(values)

    def _obs_dict(self, obs: jax.Array) -> Dict[str, jax.Array]:
        """``[P, ...]`` observations of one game as a dict per agent."""
        obs = obs.reshape((self.num_agents,) + self._obs_shape)
        return {agent: obs[i] for i, agent in enumerate(self.agents)}


def _encoding(obs: str) -> Tuple[str, bool]:
    """The engine encoding and whether to flatten it, for an ``obs`` name."""
    if obs == "flat":
        return "image", True
    if obs.startswith("flat-"):
        return "image-" + obs[len("flat-") :], True
    if obs.startswith("image"):
        return obs, False
    raise ValueError(
        f"obs {obs!r} is not offered here: use 'flat', 'image', 'image-chw', or either with "
        "'-public' or '-private' (graph encodings need a second buffer per game; use yokai.VecEnv)"
    )
