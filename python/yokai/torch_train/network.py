"""The compact recurrent actor-critic of ``yokai train`` in PyTorch, layer for layer.

Same layers, same names and the same equations as the Rust network
(``crates/yokai-train/src/network``): a node MLP shared by every card and hint slot, a
mixing layer, an embedding, a GRU cell with PyTorch's equations, then the actor (a dense
layer, or the pointer head that scores each action from card and hint embeddings) and
the critic (the memory's state, with ``network.critic = "central"`` also every card's true
colour). The parameter names are the Rust network's, so weights move between the two
through one SafeTensors file (``weights.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import torch
import torch.nn as nn
import torch.nn.functional as F

#: Width of a node embedding (encoder) and of the pointer head's embeddings.
NODE_WIDTH = 32
HEAD_WIDTH = 32


@dataclass(frozen=True)
class Shapes:
    """What the network needs to know of the game."""

    cards: int
    hints: int
    features: int
    grid: int
    colours: int
    actions: int
    #: Node feature channels the board is read from (``TrainEnv.channels``).
    row: int
    col: int

    @staticmethod
    def of(env) -> "Shapes":
        nodes, features = env.observation_shape
        ch = env.channels
        return Shapes(env.num_cards, env.num_hints, features, env.grid, env.num_colours, env.num_actions, ch["row"], ch["col"])


def linear(d_in: int, d_out: int, gain: float) -> nn.Linear:
    """A linear layer with orthogonal weights times ``gain`` and zero bias (as ``Init``)."""
    layer = nn.Linear(d_in, d_out)
    nn.init.orthogonal_(layer.weight, gain)
    nn.init.zeros_(layer.bias)
    return layer


class MlpEncoder(nn.Module):
    """One layer shared by every node, then one over all nodes in order."""

    def __init__(self, s: Shapes, out: int):
        super().__init__()
        self.nodes, self.features = s.cards + s.hints, s.features
        self.node = linear(s.features, NODE_WIDTH, math.sqrt(2))
        self.mix = linear(self.nodes * NODE_WIDTH, out, math.sqrt(2))

    def forward(self, obs: torch.Tensor) -> torch.Tensor:
        b = obs.shape[0]
        per_node = F.relu(self.node(obs.reshape(b * self.nodes, self.features)))
        return F.relu(self.mix(per_node.reshape(b, self.nodes * NODE_WIDTH)))


class GruCell(nn.Module):
    """A GRU cell from two linear maps, PyTorch's equations; ``project`` is the input map,
    computed for a whole sequence at once."""

    def __init__(self, d_in: int, size: int):
        super().__init__()
        self.size = size
        self.input = linear(d_in, 3 * size, 1.0)
        self.hidden = linear(size, 3 * size, 1.0)

    def step(self, gx: torch.Tensor, h: torch.Tensor) -> torch.Tensor:
        gh = self.hidden(h)
        n = self.size
        r = torch.sigmoid(gx[:, :n] + gh[:, :n])
        z = torch.sigmoid(gx[:, n : 2 * n] + gh[:, n : 2 * n])
        cand = torch.tanh(gx[:, 2 * n :] + r * gh[:, 2 * n :])
        return cand + z * (h - cand)


def is_one(d: torch.Tensor) -> torch.Tensor:
    """1 where a whole-numbered distance is 1, else 0."""
    return (1.0 - (d - 1.0).abs()).clamp_min(0.0)


class PointerHead(nn.Module):
    """Action logits from per-card and per-hint embeddings (``network/pointer.rs``): MOVE
    y→x scores card y against the cell's embedding and the cards that would become its
    neighbours, PLACE h on y a hint slot against a card, OBSERVE y one card; NOOP, END and
    REVEAL read the memory (and with ``pool`` the mean and maximum card embedding)."""

    def __init__(self, s: Shapes, hidden: int, pool: bool, colour_head: bool, gain: float):
        super().__init__()
        self.s, self.pool = s, pool
        w, sqrt2 = HEAD_WIDTH, math.sqrt(2)
        self.node = linear(s.features, w, sqrt2)
        self.context = linear(hidden, w, sqrt2)
        self.message = linear(w, w, 1.0)
        self.move_query = linear(w, w, gain)
        self.move_key = linear(w, w, 1.0)
        self.cell = nn.Parameter(nn.init.orthogonal_(torch.empty(s.grid * s.grid, w)))
        self.observe = linear(w, 1, gain)
        self.hint_query = linear(w, w, gain)
        self.hint_key = linear(w, w, 1.0)
        self.other = linear(hidden + (2 * w if pool else 0), 3, gain)
        self.colour = linear(w, s.colours, 1.0) if colour_head else None
        g = s.grid
        cells = torch.arange(g * g)
        self.register_buffer("cell_rows", (cells // g).float().view(1, 1, -1), persistent=False)
        self.register_buffer("cell_cols", (cells % g).float().view(1, 1, -1), persistent=False)

    def forward(self, nodes: torch.Tensor, h: torch.Tensor):
        """Logits ``[B, N_a]`` in the game's action order, and the cards' colour logits
        ``[B, Y, C]`` (``None`` without the colour layer)."""
        s = self.s
        b, y = nodes.shape[0], s.cards
        x = nodes.reshape(b, y + s.hints, s.features)
        z = F.relu(self.node(x) + self.context(h).unsqueeze(1))
        z_cards, z_hints = z[:, :y], z[:, y:]
        scale = float(s.grid - 1)
        rows = torch.round(x[:, :y, s.row : s.row + 1] * scale)
        cols = torch.round(x[:, :y, s.col : s.col + 1] * scale)
        near = is_one((rows - self.cell_rows).abs() + (cols - self.cell_cols).abs())
        touching = is_one((rows - rows.transpose(1, 2)).abs() + (cols - cols.transpose(1, 2)).abs())
        cards = F.relu(z_cards + self.message(touching @ z_cards))
        q, k = self.move_query(cards), self.move_key(cards)
        own = (q * k).sum(2, keepdim=True)
        moves = q @ self.cell.t() + (q @ k.transpose(1, 2)) @ near - near * own
        observe = self.observe(cards).reshape(b, y)
        place = self.hint_query(z_hints) @ self.hint_key(cards).transpose(1, 2)
        if self.pool:
            other = self.other(torch.cat([h, cards.mean(1), cards.amax(1)], 1))
        else:
            other = self.other(h)
        logits = torch.cat([other[:, :2], observe, moves.reshape(b, -1), other[:, 2:3], place.reshape(b, -1)], 1)
        colours = self.colour(cards) if self.colour is not None else None
        return logits, colours


class ActorCritic(nn.Module):
    """Encoder → Linear → ReLU → GRU → actor (dense or pointer) and critic."""

    def __init__(self, network: dict, ppo: dict, s: Shapes):
        super().__init__()
        h = network["hidden"]
        self.hidden_size = h
        self.encoder = MlpEncoder(s, h)
        self.embed = linear(h, h, math.sqrt(2))
        self.memory = GruCell(h, h)
        # network.head_layers: the paper's +1HL / +2HL between the memory and the heads.
        self.head_layers = nn.ModuleList(linear(h, h, math.sqrt(2)) for _ in range(network.get("head_layers", 0)))
        gain = network["actor_gain"]
        if network["head"] == "pointer":
            self.actor = None
            self.pointer = PointerHead(s, h, network["pointer_pool"], ppo["belief_aux"] > 0, gain)
        else:
            self.actor = linear(h, s.actions, gain)
            self.pointer = None
        self.central = linear(h + s.cards * s.colours, h, math.sqrt(2)) if network["critic"] == "central" else None
        self.critic = linear(h, 1, network["critic_gain"])

    def project(self, obs: torch.Tensor) -> torch.Tensor:
        """The GRU's input map of observations ``[B, L]``: ``[B, 3H]``."""
        return self.memory.input(F.relu(self.embed(self.encoder(obs))))

    def recur(self, obs: torch.Tensor, h: torch.Tensor, keep: torch.Tensor) -> torch.Tensor:
        """One step: the new states ``[B, H]`` (``keep`` 0 zeroes a row's state first)."""
        return self.memory.step(self.project(obs), h * keep.unsqueeze(1))

    def unroll(self, obs: torch.Tensor, h0: torch.Tensor, keep: torch.Tensor) -> torch.Tensor:
        """States after every step of ``B`` sequences of ``T`` steps: ``[B·T, H]``, row
        ``b·T + t`` (observations ``[B, T, L]``, ``keep`` ``[B, T]``)."""
        b, t, l = obs.shape
        gx = self.project(obs.reshape(b * t, l)).reshape(b, t, -1)
        h, states = h0, []
        for s in range(t):
            h = self.memory.step(gx[:, s], h * keep[:, s : s + 1])
            states.append(h)
        return torch.stack(states, 1).reshape(b * t, -1)

    def head_input(self, states: torch.Tensor) -> torch.Tensor:
        """What the heads read of memory states: through the ``head_layers``."""
        for layer in self.head_layers:
            states = F.relu(layer(states))
        return states

    def heads(self, obs: torch.Tensor, states: torch.Tensor):
        """Action logits ``[B, N_a]`` and colour logits (or ``None``) of rows' observations
        (read by the pointer head) and states."""
        states = self.head_input(states)
        if self.pointer is not None:
            return self.pointer(obs, states)
        return self.actor(states), None

    def values(self, states: torch.Tensor, truth_one_hot: torch.Tensor | None) -> torch.Tensor:
        """State values ``[B]``; a central critic also reads every card's true colour
        (``[B, Y·C]`` one-hot)."""
        x = self.head_input(states)
        if self.central is not None:
            x = F.relu(self.central(torch.cat([x, truth_one_hot], 1)))
        return self.critic(x).squeeze(1)


def supported(config: dict) -> None:
    """Raise ``ValueError`` naming the field where ``config`` asks for what this trainer
    does not implement (``yokai train`` does)."""
    n, p = config["network"], config["ppo"]
    encoder = n.get("encoder") or ("mlp" if n["preset"] == "compact" else "cnn")
    refusals = [
        (encoder != "mlp", "network.encoder", f"{encoder!r}: the PyTorch trainer has the compact network (mlp) only"),
        (n["memory"] != "gru", "network.memory", f"{n['memory']!r}: the PyTorch trainer has the GRU only"),
        (config["obl"]["level"] > 0, "obl.level", "Off-Belief Learning runs in `yokai train` only"),
        (p["cluster_shaping"] > 0, "ppo.cluster_shaping", "not implemented in the PyTorch trainer"),
        (p["belief_aux"] > 0 and n["head"] != "pointer", "ppo.belief_aux", "needs network.head = \"pointer\""),
    ]
    for bad, field, why in refusals:
        if bad:
            raise ValueError(f"training config: {field} = {why}")
