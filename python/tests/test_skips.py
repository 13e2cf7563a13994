"""The allowed-skip list (conftest.py): a listed reason is allowed only where its flag says
it holds; anything else never is."""

import conftest


def test_a_listed_reason_is_allowed_only_where_its_flag_is_set(monkeypatch):
    torch = "could not import 'torch': No module named 'torch'"
    browser = "needs Debian's chromium and chromium-driver"
    monkeypatch.delenv("YOKAI_TORCH_MISSING", raising=False)
    monkeypatch.delenv("YOKAI_NO_BROWSER", raising=False)
    assert not conftest.allowed(torch) and not conftest.allowed(browser)
    monkeypatch.setenv("YOKAI_TORCH_MISSING", "1")
    assert conftest.allowed(torch) and not conftest.allowed(browser)
    monkeypatch.setenv("YOKAI_NO_BROWSER", "1")
    assert conftest.allowed(browser)
    for jax in ["could not import 'jax': No module named 'jax'",
                "could not import 'jaxmarl': No module named 'jaxmarl'"]:
        monkeypatch.delenv("YOKAI_JAX_UNSUPPORTED", raising=False)
        assert not conftest.allowed(jax), jax
        monkeypatch.setenv("YOKAI_JAX_UNSUPPORTED", "1")
        assert conftest.allowed(jax), jax
    # The flag covers jax and jaxmarl, not any module whose name starts with "jax".
    assert not conftest.allowed("could not import 'jax_other': No module named 'jax_other'")
    for never in ["needs the yokai binary: scripts/test.sh builds it before pytest",
                  "needs YOKAI_LEAN_PYTHON (scripts/test.sh builds it)",
                  "could not import 'ray': No module named 'ray'"]:
        assert not conftest.allowed(never), never
