"""The suite's one list of allowed skips, enforced when scripts/test.sh runs it.

A test may skip only for a reason listed here, and only when scripts/test.sh has said the
reason holds on this machine (the environment variable beside it). Under scripts/test.sh
(``YOKAI_STRICT_SKIPS=1``) any other skip fails the run: the binary missing, a test
dependency missing, the lean package missing are faults of the set-up that CI must never
pass over. Run alone (plain ``pytest``), skips are reported as usual.
"""

import os
import re

import pytest

# reason pattern -> (environment flag scripts/test.sh sets when it holds, why it may hold)
ALLOWED_SKIPS = {
    r"could not import 'torch'": (
        "YOKAI_TORCH_MISSING",
        "PyPI's PyTorch download failed three times, or the disk has under 7 GB free",
    ),
    r"could not import '(jax|jaxmarl)'": (
        "YOKAI_JAX_UNSUPPORTED",
        "Python below 3.11, for which the `test` extra installs no jax or jaxmarl",
    ),
    r"needs Debian's chromium and chromium-driver": (
        "YOKAI_NO_BROWSER",
        "not root on Debian, so the browser could not be installed",
    ),
}

_skips = []


def allowed(reason):
    """Whether a skip for ``reason`` is allowed on this machine now."""
    return any(re.search(pattern, reason) and os.environ.get(flag) == "1"
               for pattern, (flag, _) in ALLOWED_SKIPS.items())


def pytest_runtest_logreport(report):
    if report.skipped and isinstance(report.longrepr, tuple):
        _skips.append((report.nodeid, str(report.longrepr[2])))


def pytest_sessionfinish(session, exitstatus):
    if os.environ.get("YOKAI_STRICT_SKIPS") != "1":
        return
    refused = [(node, reason) for node, reason in _skips if not allowed(reason)]
    if refused:
        lines = "\n".join(f"  {node}: {reason}" for node, reason in refused)
        print(f"\nskipped for a reason scripts/test.sh does not allow here "
              f"(python/tests/conftest.py lists the allowed ones):\n{lines}")
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
