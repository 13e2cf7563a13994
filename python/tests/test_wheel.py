"""The wheel as a user without Rust gets it: ``scripts/test.sh`` builds the abi3 manylinux
wheel with ``pip wheel ./python``, installs it (with PettingZoo) into a fresh venv, and
names that venv's Python in ``YOKAI_WHEEL_PYTHON``. Here it runs with a PATH that holds no
cargo or rustc, outside the repository: the PettingZoo API test and a pretrained agent."""

import os
import pathlib
import subprocess

import pytest

WHEEL_PYTHON = os.environ.get("YOKAI_WHEEL_PYTHON")

CHECK = r"""
import shutil, sys
assert shutil.which("cargo") is None and shutil.which("rustc") is None, "a Rust toolchain is on PATH"
import yokai
from yokai import zoo
from pettingzoo.test import parallel_api_test
assert "site-packages" in yokai.__file__, yokai.__file__
parallel_api_test(zoo.parallel_env(config="9c-2p-perfect"), num_cycles=100)
agents = [yokai.Agent.pretrained("quick", 0, agent_seed=s) for s in (0, 1)]
rewards = [yokai.play("9c-2p-perfect", agents, seed=s).outcome["reward"] for s in range(20)]
print("wheel ok", yokai.__version__, sum(rewards) / len(rewards))
"""


@pytest.mark.skipif(not WHEEL_PYTHON, reason="needs YOKAI_WHEEL_PYTHON (scripts/test.sh builds the wheel)")
def test_the_wheel_runs_without_a_rust_toolchain(tmp_path):
    python = pathlib.Path(WHEEL_PYTHON)
    env = {"PATH": f"{python.parent}:/usr/bin:/bin", "HOME": str(tmp_path)}
    assert "cargo" not in env["PATH"]
    out = subprocess.run([str(python), "-c", CHECK], capture_output=True, text=True,
                         timeout=300, cwd=tmp_path, env=env)
    assert out.returncode == 0, out.stderr
    words = out.stdout.splitlines()[-1].split()
    assert words[:2] == ["wheel", "ok"], out.stdout
    # The pretrained agent plays as documented (self-play R 5.27), far above greedy's 0.51.
    assert float(words[3]) > 2.0, out.stdout
