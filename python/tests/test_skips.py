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
    for never in ["needs the yokai binary: scripts/test.sh builds it before pytest",
                  "needs YOKAI_LEAN_PYTHON (scripts/test.sh builds it)",
                  "could not import 'ray': No module named 'ray'"]:
        assert not conftest.allowed(never), never
