"""The package built without the trainer (``--no-default-features``: no burn) at run time:
environments and bots work, and whatever needs the trainer is an error that says how to
get it. ``scripts/test.sh`` builds that wheel into ``.venv-lean`` and names its Python in
``YOKAI_LEAN_PYTHON``; without it this test is skipped."""

import os
import subprocess

import pytest

LEAN = os.environ.get("YOKAI_LEAN_PYTHON")

CHECK = r"""
import yokai
env = yokai.play("9c-2p-perfect", ["belief", "greedy"], seed=4)
assert env.done and env.outcome["reward"] is not None
vec = yokai.VecEnv("9c-2p-perfect", num_envs=4, seed=1)
assert vec.num_envs == 4
for call in (lambda: yokai.Agent(PATH), lambda: yokai.probe_accuracy([])):
    try:
        call()
    except yokai.YokaiError as e:
        assert "default features" in str(e), e
    else:
        raise AssertionError("a trained policy loaded without the trainer")
print("lean ok", yokai.__version__)
"""


@pytest.mark.skipif(not LEAN, reason="needs YOKAI_LEAN_PYTHON (scripts/test.sh builds it)")
def test_the_lean_build_plays_and_says_what_it_lacks(tmp_path):
    # Any existing file is taken for a policy path; this one is not even a policy.
    path = tmp_path / "policy.ykp"
    path.write_bytes(b"not a policy")
    out = subprocess.run([LEAN, "-c", CHECK.replace("PATH", repr(str(path)))],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("lean ok"), out.stdout
