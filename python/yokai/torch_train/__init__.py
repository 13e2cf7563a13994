"""``python -m yokai.torch_train``: the Rust trainer's PPO, network and levers in PyTorch.

It reads the same TOML presets as ``yokai train`` (``quick``, ``cpu-fast``, ``cpu``,
``cpu-op`` …, or a file, with ``--set FIELD=VALUE``), plays the games through
``yokai.TrainEnv`` (the Rust trainer's own view of them: rows, Other-Play symmetries, true
colours, what END would pay), and writes a run directory that every front end reads:

- ``policy.safetensors``: the network in the Rust network's names and layouts, with the
  training config and the game as metadata, so ``yokai eval``, ``yokai serve``,
  ``yokai play`` and ``yokai.Agent`` load it as they load a Rust policy;
- ``metrics.jsonl``: one line per update (the Rust trainer's fields);
- ``config.toml``: the resolved config; ``checkpoint.pt``: network, optimiser and update
  count, for ``--resume``.

What it implements: the compact network (MLP encoder, GRU, dense or pointer head, pooled
END input, local or central critic), PPO with normalised entropy, the END term and END
entropy bonus, the belief loss, annealed shaping and learning rate, and Other-Play. OBL,
the CNN and graph encoders, Transformer-XL and the clustering shaping are refused with the
field named (``yokai train`` has them). PyTorch is an optional dependency:
``pip install 'yokai-learning-environment[torch]'``.
"""

from .network import ActorCritic, Shapes, supported
from .ppo import Trainer, masked_log_softmax
from .weights import load, save

__all__ = ["ActorCritic", "Shapes", "Trainer", "load", "masked_log_softmax", "save", "supported"]
