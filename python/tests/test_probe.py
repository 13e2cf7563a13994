"""Linear probes from Python: on synthetic memories with a known answer, and on the
memories of a trained policy recorded, saved and loaded again."""

import numpy as np
import pytest

import yokai
from test_trained import run_dir  # noqa: F401  (the module-scoped trained run)

CARDS, COLOURS = 9, 3


def synthetic(noise_only, episodes=200, steps=10, seed=0):
    """Records of 9c games where the state is every card's colour one-hot (plus a little
    noise), or pure noise."""
    rng = np.random.default_rng(seed)
    rows = episodes * steps
    colours = np.tile(np.repeat(np.arange(COLOURS), CARDS // COLOURS), (episodes, 1))
    for row in colours:
        rng.shuffle(row)
    colours = np.repeat(colours, steps, axis=0).astype(np.uint8)
    if noise_only:
        states = rng.normal(size=(rows, CARDS * COLOURS))
    else:
        states = np.eye(COLOURS)[colours].reshape(rows, -1) + 0.1 * rng.normal(size=(rows, CARDS * COLOURS))
    return {
        "states": states.astype(np.float32),
        "colours": colours,
        "seen": np.zeros((rows, CARDS), dtype=bool),
        "steps": np.tile(np.arange(steps), episodes),
        "episodes": np.repeat(np.arange(episodes), steps),
    }


def test_a_linear_code_is_read_and_noise_is_not():
    coded = yokai.probe_accuracy("9c-2p-perfect", synthetic(False))
    assert coded["chance"] == pytest.approx(1 / 3)
    assert list(coded["step"]) == list(range(10))
    assert (coded["rows"] == 40).all()  # episodes 0, 5, 10, …: 40 of 200 held out
    assert coded["all"].min() > 0.99
    assert np.isnan(coded["unseen"]).sum() == 0  # nothing seen: every card is unseen
    noise = yokai.probe_accuracy("9c-2p-perfect", synthetic(True))
    assert abs(noise["all"].mean() - 1 / 3) < 0.05
    # The oracle has seen nothing: it names the most common colour left (a third right).
    assert abs(noise["oracle_all"].mean() - 1 / 3) < 1e-9
    assert "head" not in noise  # no belief head's guesses in the records
    # A belief head that names every colour right but card 0's: 8 of 9 at every step.
    head = synthetic(True)["colours"].copy()
    head[:, 0] = (head[:, 0] + 1) % COLOURS
    guessed = yokai.probe_accuracy("9c-2p-perfect", dict(synthetic(True), head=head))
    assert np.allclose(guessed["head"], 8 / 9) and np.allclose(guessed["head_unseen"], 8 / 9)


def test_records_of_a_trained_policy_round_trip_through_npz(run_dir, tmp_path):  # noqa: F811
    records = yokai.probe_records([str(run_dir), str(run_dir)], games=30, seed=4)
    n, h = records["states"].shape
    assert h == 16 and records["colours"].shape == (n, CARDS) and records["seen"].shape == (n, CARDS)
    assert set(np.unique(records["episodes"])) == set(range(30))
    # Every game starts at step 0 with both seats recorded, and nothing is seen before
    # the first action.
    first = records["steps"] == 0
    assert first.sum() == 60 and not records["seen"][first].any()
    assert (np.sort(records["colours"][0]) == np.repeat(np.arange(COLOURS), 3)).all()
    again = yokai.probe_records([str(run_dir), str(run_dir)], games=30, seed=4)
    assert all((records[k] == again[k]).all() for k in records)
    np.savez(tmp_path / "memories.npz", **records)
    loaded = dict(np.load(tmp_path / "memories.npz"))
    direct = yokai.probe_accuracy("9c-2p-perfect", records, min_rows=5)
    saved = yokai.probe_accuracy("9c-2p-perfect", loaded, min_rows=5)
    assert all(np.array_equal(direct[k], saved[k], equal_nan=True) for k in direct if k != "chance")
    cross = yokai.probe_accuracy("9c-2p-perfect", records, test=records, min_rows=5)
    assert cross["rows"][0] == 60
    # Where each card lies: the deal's 3 × 3 square in the middle of the 9 × 9 grid at the
    # first state, and probes by position read those positions.
    cells = records["cells"]
    assert cells.shape == (n, CARDS)
    middle = {r * 9 + c for r in range(3, 6) for c in range(3, 6)}
    assert all(set(row) == middle for row in cells[first])
    by_position = yokai.probe_accuracy("9c-2p-perfect", loaded, min_rows=5, by="position")
    assert by_position["rows"][0] == 12  # the held-out games (0, 5, …, 25), both seats
    # Nothing is seen at the first state: the oracle names one colour for all 9 occupied
    # positions, right on exactly 3 of them.
    assert by_position["oracle_all"][0] == pytest.approx(1 / 3)
    with pytest.raises(ValueError, match='by is "card" or "position"'):
        yokai.probe_accuracy("9c-2p-perfect", records, by="cell")
    without = {k: v for k, v in records.items() if k != "cells"}
    with pytest.raises(ValueError, match='needs the cards\' positions: records has no "cells"'):
        yokai.probe_accuracy("9c-2p-perfect", without, by="position")
    with pytest.raises(ValueError, match="cell 81 is not on 9c-2p-perfect's board"):
        yokai.probe_accuracy("9c-2p-perfect", dict(records, cells=np.full_like(cells, 81)), by="position")


def test_bad_records_name_what_is_wrong():
    good = synthetic(False, episodes=10)
    for key, value, message in [
        ("colours", good["colours"][:, :5], "colours has shape"),
        ("steps", good["steps"][:-1], "steps and episodes need"),
        ("colours", good["colours"] + 3, r"colour \d does not exist in 9c-2p-perfect"),
        ("states", np.full_like(good["states"], np.nan), "NaN"),
        ("head", good["colours"][:, :5], "head has shape"),
        ("head", good["colours"] + 3, r"head: colour \d does not exist"),
    ]:
        bad = dict(good, **{key: value})
        with pytest.raises(ValueError, match=message):
            yokai.probe_accuracy("9c-2p-perfect", bad)
    with pytest.raises(ValueError, match='no "seen" array'):
        yokai.probe_accuracy("9c-2p-perfect", {k: v for k, v in good.items() if k != "seen"})
    with pytest.raises(yokai.ConfigError):
        yokai.probe_accuracy("9c-9p-nonsense", good)
    with pytest.raises(ValueError, match="one policy per seat"):
        yokai.probe_records([])
