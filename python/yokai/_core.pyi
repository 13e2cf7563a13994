"""Type stubs of the Rust extension module ``yokai._core``."""

from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

class YokaiError(ValueError):
    """Base class of every error raised by the Yōkai engine."""

class ConfigError(YokaiError):
    """A configuration name, TOML file or option that does not describe a playable game."""

class IllegalActionError(YokaiError):
    """An illegal action or an index outside the action space; the game is unchanged."""

class ReplayError(YokaiError):
    """A replay record that is not valid JSON or does not replay to the recorded game."""

Action = Union[int, str]
DType = Union[str, type, np.dtype]

def episode_seed(seed: int, env: int, episode: int) -> int:
    """The deal seed of episode ``episode`` of game ``env`` in a VecEnv seeded ``seed``."""

def derive_seed(seed: int, index: int) -> int:
    """The seed derived from ``seed`` for ``index`` (game i's stream of ``VecEnv(seed)``)."""
    ...

def configs() -> list[str]:
    """Names of the built-in configurations (e.g. ``"9c-2p-perfect"``)."""

def policy_parameters(path: str) -> np.ndarray:
    """Every parameter of the trained network at ``path``, flattened (float32)."""

def pretrained_agents() -> list[dict]:
    """The pretrained agents built in, one dict per preset: ``preset``, ``about``,
    ``command``, ``steps``, ``seeds``, and self-play ``sp_r`` / ``sp_se`` per seed over
    ``games`` games. Seat one with ``Agent.pretrained(preset, seed)`` or the name
    ``"pretrained:PRESET/SEED"``."""

def probe_records(
    policies: list[str], probed: list[bool] | None = None, games: int = 500, seed: int = 0
) -> dict[str, np.ndarray]:
    """Play ``games`` games with one trained policy per seat and record the probed seats'
    memory after every step: ``states`` [N, H] float32, ``colours`` [N, Y] uint8, ``seen``
    [N, Y] bool, ``steps`` [N] and ``episodes`` [N] int64, and ``head`` [N, Y] uint8 (the
    belief head's guess of every colour) where the probed network has a colour layer."""

def probe_accuracy(
    config: str,
    records: dict[str, np.ndarray],
    test: dict[str, np.ndarray] | None = None,
    min_rows: int = 20,
) -> dict[str, np.ndarray | float]:
    """Fit a linear probe per card on 80 % of ``records``' episodes and report accuracy per
    game step (``step``, ``all``, ``oracle_all``, ``unseen``, ``oracle_unseen``, ``rows``,
    ``chance``; ``head`` and ``head_unseen`` where the records hold ``head``) on the other
    20 %, or on all of ``test``. ``records`` may hold any agent's
    states (same keys as ``probe_records`` returns)."""

def policy_step(
    path: str, env: "Env", seat: int, state: Optional[npt.ArrayLike] = None
) -> tuple[Optional[npt.NDArray[np.float32]], npt.NDArray[np.float32]]:
    """One step of the trained network at ``path`` for ``seat`` of ``env``'s game, from its
    memory ``state`` (None: fresh): (logits [N_a] or None where the seat waits, new state)."""

class TrainEnv:
    """The batched games of a training run as ``yokai train`` plays them: a row per seat,
    each row's Other-Play view, the true colours and what END would pay."""

    def __init__(self, config: str, seed: int = 0, set: Sequence[str] = ...) -> None: ...
    def observe(self) -> dict[str, Any]:
        """``obs`` [rows, ...] and ``legal_mask`` [rows, N_a] float32 in each row's view,
        ``keep`` [rows], ``acting_seat`` [N], ``truth`` [rows, Y] uint8, ``end_reward`` [N]."""
    def step(self, actions: npt.ArrayLike) -> dict[str, Any]:
        """One action per row in its own view: ``reward``, ``shaping``, ``done``, ``final``."""
    @property
    def train_config(self) -> str: ...
    @property
    def name(self) -> str: ...
    @property
    def game_config(self) -> str: ...
    @property
    def num_envs(self) -> int: ...
    @property
    def num_players(self) -> int: ...
    @property
    def num_rows(self) -> int: ...
    @property
    def num_actions(self) -> int: ...
    @property
    def num_cards(self) -> int: ...
    @property
    def num_colours(self) -> int: ...
    @property
    def num_hints(self) -> int: ...
    @property
    def grid(self) -> int: ...
    @property
    def observation_shape(self) -> list[int]: ...
    @property
    def end_action(self) -> int: ...
    @property
    def channels(self) -> dict[str, int]: ...

class VecEnv:
    """N games of one configuration stepped together on all cores.

    ``reset()`` and ``step()`` return a dict of read-only NumPy arrays that view the
    environment's buffers; the next call overwrites them in place (copy what you keep).

    Keys: ``obs`` [N, P, ...], ``legal_mask`` [N, P, N_a] uint8, ``reward`` [N] float32,
    ``shaping`` [N] float32, ``done`` [N] bool, ``acting_seat`` [N] uint8, ``adjacency``
    [N, Y, Y] (graph encodings), ``final``: dict of [N] arrays (``reward``, ``won``,
    ``early_end``, ``length``, ``correct_hints``, ``wrong_hints``, ``score``) for games
    that ended on this step. A finished game is reset in the same step: ``obs``,
    ``legal_mask`` and ``acting_seat`` then show the next game's first state.
    """

    def __init__(
        self,
        config: str = "9c-2p-perfect",
        num_envs: int = 1024,
        seed: int = 0,
        obs: str = "image",
        dtype: Optional[DType] = None,
        threads: Optional[int] = None,
    ) -> None: ...
    def reset(self, seed: Optional[int] = None) -> dict[str, Any]:
        """Restart every game at episode 0 of its seed stream."""
    def step(self, actions: npt.ArrayLike) -> dict[str, Any]:
        """Step all games with int actions of shape [N] (acting seat) or [N, P] (all seats).

        Raises IllegalActionError (nothing changes) for an illegal action, ValueError for
        a wrong shape, TypeError for non-integer actions.
        """
    def sample_actions(self, seed: int) -> npt.NDArray[np.uint32]:
        """A uniformly random legal action of each game's acting seat, [N] uint32."""
    def action_name(self, action: int) -> str: ...
    def render(self, env: int, seat: Optional[int] = None) -> str:
        """Text picture of game ``env``: the true board or what ``seat`` knows."""
    @property
    def num_envs(self) -> int: ...
    @property
    def num_players(self) -> int: ...
    @property
    def num_actions(self) -> int: ...
    @property
    def observation_shape(self) -> list[int]: ...
    @property
    def config(self) -> str: ...
    @property
    def obs(self) -> str: ...
    @property
    def dtype(self) -> str: ...
    @property
    def seed(self) -> int: ...
    def __len__(self) -> int: ...

class Env:
    """One game of Yōkai that records its actions. ``seat=None`` means the acting seat."""

    def __init__(self, config: str = "9c-2p-perfect", seed: int = 0) -> None: ...
    def reset(self, seed: Optional[int] = None) -> None:
        """Deal from ``seed``, or from the previous seed + 1."""
    def step(self, action: Action) -> tuple[int, int, bool]:
        """Play the acting seat's action; returns (reward, shaping, done)."""
    def step_joint(self, actions: Sequence[Action]) -> tuple[int, int, bool]:
        """One action per seat (NOOP for all but the acting seat)."""
    def legal_actions(self, seat: Optional[int] = None) -> list[int]: ...
    def legal_mask(self, seat: Optional[int] = None) -> npt.NDArray[np.uint8]: ...
    def action_name(self, action: int) -> str: ...
    def action_index(self, name: str) -> int: ...
    def render(self, seat: Optional[int] = None) -> str: ...
    def observation(
        self, seat: Optional[int] = None, encoding: str = "image", dtype: Optional[DType] = None
    ) -> npt.NDArray[Any]: ...
    def observation_shape(self, encoding: str = "image") -> list[int]: ...
    def adjacency(self) -> npt.NDArray[np.float32]: ...
    def ground_truth(self) -> npt.NDArray[np.uint8]:
        """True colour of every card (hidden information)."""
    def to_replay(self) -> str: ...
    @staticmethod
    def from_replay(text: str) -> "Env": ...
    def copy(self) -> "Env": ...
    @property
    def acting_seat(self) -> int: ...
    @property
    def substep(self) -> int: ...
    @property
    def done(self) -> bool: ...
    @property
    def steps(self) -> int: ...
    @property
    def outcome(self) -> Optional[dict[str, Any]]: ...
    @property
    def history(self) -> list[int]: ...
    @property
    def seed(self) -> Optional[int]: ...
    @property
    def num_players(self) -> int: ...
    @property
    def num_actions(self) -> int: ...
    @property
    def num_cards(self) -> int: ...
    @property
    def num_colours(self) -> int: ...
    @property
    def config(self) -> str: ...

class Agent:
    """A built-in policy ("random", "greedy", "belief", "belief:continue_win=0.9"), a
    pretrained agent ("pretrained:quick/0") or a trained policy (the path of a policy file,
    checkpoint or run directory) for one seat;
    sees only what its seat may know. Show it every action with ``observe`` before
    ``env.step``. ``end`` (trained policies only): ``None`` plays END as the training
    config says, ``"draw"`` draws it like any action, a probability ``p`` in (0, 1) ends
    wherever the network gives END more than ``p``. ``temperature`` (trained policies
    only): ``None`` as the training config says (``act.temperature``, else 1), ``T`` draws
    the other moves from softmax(logits / T), 0 plays the most likely legal move."""

    def __init__(self, name: str, seed: int = 0, end: float | str | None = None,
                 temperature: float | None = None) -> None: ...
    @staticmethod
    def pretrained(preset: str, seed: int = 0, agent_seed: int = 0, end: float | str | None = None,
                   temperature: float | None = None) -> Agent:
        """Seed ``seed`` of the pretrained agents of ``preset`` (``pretrained_agents()``);
        ``agent_seed`` seeds its draws."""
    def reset(self, seed: int) -> None: ...
    def act(self, env: Env) -> int:
        """The action index it plays as the acting seat of ``env``."""
    def observe(self, env: Env, seat: int, action: int) -> None:
        """Tell the agent at ``seat`` that the acting seat is about to play ``action``."""
    @property
    def name(self) -> str: ...


class PackedGames:
    """Batches of games held outside Rust as packed bytes (``yokai.jax`` calls these)."""

    packed_len: int
    def __init__(self, config: str, encoding: str = "image") -> None: ...
    @property
    def observation_shape(self) -> list[int]: ...
    @property
    def num_actions(self) -> int: ...
    @property
    def num_players(self) -> int: ...
    def reset(self, streams: npt.NDArray[np.uint64]) -> dict[str, Any]: ...
    def step(
        self,
        states: npt.NDArray[np.uint8],
        streams: npt.NDArray[np.uint64],
        episodes: npt.NDArray[np.uint32],
        actions: npt.NDArray[np.uint32],
        autoreset: bool,
    ) -> dict[str, Any]: ...
    def observe(self, states: npt.NDArray[np.uint8], episodes: npt.NDArray[np.uint32]) -> dict[str, Any]: ...
    def render(self, state: npt.NDArray[np.uint8]) -> str: ...
