"""`yokai serve` in a real headless browser (Debian's Chromium driven by Selenium): a whole
game against the `belief` bot played by clicking cards, cells and hints, then the page's
log and result checked against the server's record. Screenshots of a few steps go to
``$YOKAI_SCREENSHOTS`` when set (docs/img/play-*.png were made that way)."""

import json
import os
import pathlib
import shutil
import subprocess
import time
import urllib.request

import pytest

from test_trained import BINARY

webdriver = pytest.importorskip("selenium.webdriver")
from selenium.webdriver.common.by import By  # noqa: E402

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
DRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"


@pytest.fixture
def server(tmp_path):
    if not BINARY.exists():
        pytest.skip("needs the yokai binary: scripts/test.sh builds it before pytest")
    proc = subprocess.Popen(
        [str(BINARY), "serve", "--port", "0", "--seats", "human,belief", "--records", str(tmp_path / "records")],
        stderr=subprocess.PIPE, text=True,
    )
    line = proc.stderr.readline()
    base = next(w for w in line.split() if w.startswith("http://")).rstrip("/")
    yield base, tmp_path / "records"
    proc.kill()
    proc.wait()


@pytest.fixture
def browser(tmp_path):
    if not (pathlib.Path(CHROMIUM).exists() and pathlib.Path(DRIVER).exists()):
        pytest.skip("needs Debian's chromium and chromium-driver")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--window-size=1200,1000", f"--user-data-dir={tmp_path / 'chromium'}"]:
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(executable_path=DRIVER))
    yield driver
    driver.quit()


def wait_for(driver, states, timeout=30):
    end = time.time() + timeout
    while time.time() < end:
        state = driver.find_element(By.TAG_NAME, "body").get_attribute("data-state")
        if state in states:
            return state
        time.sleep(0.05)
    raise AssertionError(f"the page stayed {state!r}, not {states}")


def click_first(driver, selector):
    found = driver.find_elements(By.CSS_SELECTOR, selector)
    if not found:
        return False
    found[0].click()
    return True


def play_turn_by_clicks(driver):
    """One action by clicking the board or the hints, the way a person would."""
    status = driver.find_element(By.ID, "status").text
    if "observe" in status:
        assert click_first(driver, "#board g.card.clickable"), status
    elif "move a card" in status:
        if not click_first(driver, "#board g.card.clickable"):
            driver.find_element(By.ID, "noop").click()
            return
        assert click_first(driver, "#board rect.cell.target"), "no target cell highlighted"
    else:  # reveal or place a hint
        assert click_first(driver, "#hints .hint.clickable"), status
        # A revealed hint selected for PLACE: now the cards it may go on are clickable.
        if driver.find_elements(By.CSS_SELECTOR, "#hints .hint.selected"):
            assert click_first(driver, "#board g.card.clickable"), "no card to place the hint on"


def test_a_whole_game_by_clicks_matches_the_record(server, browser):
    base, records = server
    shots = os.environ.get("YOKAI_SCREENSHOTS")
    browser.get(base + "/")
    # Every action's answer comes 150 ms late, as on a loaded machine: while it is on its way
    # the page must not say it is the player's turn (it once did, and this test clicked cards
    # that the answer then replaced).
    browser.execute_script("""
        const fetchNow = window.fetch;
        window.fetch = async (url, init) => {
            const answer = await fetchNow(url, init);
            if (String(url).endsWith('/actions')) await new Promise((r) => setTimeout(r, 150));
            return answer;
        };""")
    browser.find_element(By.CSS_SELECTOR, "#speed option[value='0']").click()
    wait_for(browser, {"your-turn"})
    # Before seat 0 observes anything, no colour is shown (grey cards only).
    fills = {r.get_attribute("fill") for r in browser.find_elements(By.CSS_SELECTOR, "#board g.card rect")}
    assert fills == {"#8a8276"}, fills
    if shots:
        browser.save_screenshot(os.path.join(shots, "play-start.png"))
    clicks = 0
    while wait_for(browser, {"your-turn", "over"}) == "your-turn":
        play_turn_by_clicks(browser)
        clicks += 1
        if shots and clicks == 6:
            browser.save_screenshot(os.path.join(shots, "play-middle.png"))
        assert clicks < 300, "the game does not end"
    if shots:
        browser.save_screenshot(os.path.join(shots, "play-end.png"))
    game_id = browser.execute_script("return new URLSearchParams(location.search).get('game')")
    session = browser.execute_script("return localStorage.getItem('yokai-session')")
    # The session is the server's: 128 random bits, not an id the page made up.
    assert len(session) == 32 and all(c in "0123456789abcdef" for c in session), session
    record_path = records / session / f"{game_id}.jsonl"
    lines = [json.loads(line) for line in record_path.read_text().splitlines()]
    steps = [line for line in lines if line["type"] == "step"]
    outcome = next(line["outcome"] for line in lines if line["type"] == "outcome")
    served = urllib.request.urlopen(f"{base}/api/games/{game_id}/replay?session={session}").read().decode()
    assert served == record_path.read_text()
    # The log the page shows is the recorded game, step for step.
    log = [li.text for li in browser.find_elements(By.CSS_SELECTOR, "#log li")]
    assert len(log) == len(steps) and clicks == sum(1 for s in steps if s["seat"] == 0)
    for shown, step in zip(log, steps):
        assert shown.startswith(f"seat {step['seat']} (") and shown.endswith(step["name"]), (shown, step)
    status = browser.find_element(By.ID, "status").text
    assert f"R = {outcome['reward']} " in status, status
    # Every card's true colour is shown at the end.
    fills = [r.get_attribute("fill") for r in browser.find_elements(By.CSS_SELECTOR, "#board g.card rect")]
    assert "#8a8276" not in fills and len(fills) == 9
    # The replay tab shows the same game, one board per step, with a timeline.
    browser.find_element(By.CSS_SELECTOR, "nav .tab[data-tab='replay']").click()
    browser.find_element(By.ID, "replay-current").click()
    end = time.time() + 10
    while browser.find_element(By.ID, "timeline").get_attribute("max") != str(len(steps)):
        assert time.time() < end, "the replay did not load"
        time.sleep(0.05)
    if shots:
        browser.save_screenshot(os.path.join(shots, "play-replay.png"))
    # And the summary counts it.
    browser.find_element(By.CSS_SELECTOR, "nav .tab[data-tab='summary']").click()
    end = time.time() + 10
    while "games" not in browser.find_element(By.ID, "summary-table").text:
        assert time.time() < end, "no summary"
        time.sleep(0.05)
    assert f"{float(outcome['reward']):.2f}" in browser.find_element(By.ID, "summary-table").text
