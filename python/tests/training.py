"""What the tests that train share: the ``yokai`` binary ``scripts/test.sh`` builds before
pytest, a tiny training config, and a call that trains seed 0 of it."""

import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = ROOT / "target" / "release" / "yokai"

TINY = """
game = "9c-2p-perfect"
[network]
preset = "compact"
hidden = 16
[ppo]
num_envs = 8
rollout_steps = 8
minibatches = 2
epochs = 1
total_steps = 128
"""


def train_tiny(folder: pathlib.Path, config: str = TINY, *args: str) -> pathlib.Path:
    """Train seed 0 of ``config`` (TOML text) into ``folder/runs`` with ``yokai train``
    and ``args``; returns the run directory. Skips where the binary is missing."""
    if not BINARY.exists():
        pytest.skip("needs the yokai binary: scripts/test.sh builds it before pytest")
    path = folder / "tiny.toml"
    path.write_text(config)
    out = folder / "runs"
    subprocess.run(
        [str(BINARY), "train", str(path), "--seeds", "0", "--out", str(out), "--eval-games", "0", *args],
        check=True,
        capture_output=True,
    )
    return out / "seed-0"
