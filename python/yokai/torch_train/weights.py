"""One weight format shared with the Rust trainer: SafeTensors with the Rust network's
tensor names and layouts (a linear layer's ``weight`` is ``[d_in, d_out]``, the transpose
of ``nn.Linear``'s) and the training config and game as metadata. ``yokai eval``, ``yokai
serve``, ``yokai play`` and ``yokai.Agent`` load such a file as a policy; ``yokai export``
writes one from a Rust run, which ``load`` reads back into the PyTorch network.
"""

from __future__ import annotations

import os

import torch
from safetensors import safe_open
from safetensors.torch import save_file

from .network import ActorCritic


def _is_linear_weight(name: str, tensor: torch.Tensor) -> bool:
    return name.endswith(".weight") and tensor.dim() == 2


def save(model: ActorCritic, path: str, metadata: dict[str, str]) -> None:
    """Write ``model``'s parameters to ``path`` (replaced atomically) with ``metadata``."""
    tensors = {}
    for name, p in model.state_dict().items():
        t = p.detach().to("cpu", torch.float32)
        tensors[name] = (t.t() if _is_linear_weight(name, t) else t).contiguous()
    tmp = f"{path}.tmp"
    save_file(tensors, tmp, metadata=metadata)
    os.replace(tmp, path)


def load(model: ActorCritic, path: str) -> ActorCritic:
    """Load the SafeTensors file ``path`` (this format) into ``model``: every tensor must be
    there with the network's shape, and none left over."""
    state = {}
    with safe_open(path, "pt") as f:
        for name in f.keys():
            t = f.get_tensor(name)
            state[name] = t.t() if _is_linear_weight(name, t) else t
    want = model.state_dict()
    missing, extra = sorted(set(want) - set(state)), sorted(set(state) - set(want))
    wrong = [n for n in want if n in state and state[n].shape != want[n].shape]
    if missing or extra or wrong:
        raise ValueError(f"{path}: not this network's weights (missing {missing}, unexpected {extra}, other shapes {wrong})")
    model.load_state_dict(state)
    return model
