"""Property-based fuzzing of the Python arguments (Hypothesis): any object passed as an
action, a seat, an action name, a config or a batch of actions either works as documented
or raises the documented exception (``IllegalActionError``, ``TypeError``, ``ValueError``,
``ConfigError``) with the game unchanged; never a Rust panic (which PyO3 raises as a
``BaseException``) and never a silently accepted wrong value. CI runs a few hundred cases per
test; ``YOKAI_FUZZ_CASES=N`` runs longer sessions."""

import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import yokai

CASES = int(os.environ.get("YOKAI_FUZZ_CASES", "300"))
FUZZ = settings(max_examples=CASES, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# Any Python value a caller might pass where an action, a seat or a name goes.
numpy_ints = st.sampled_from([np.int8, np.int32, np.int64, np.uint8, np.uint32, np.uint64])
anything = st.one_of(
    st.integers(min_value=-(2**80), max_value=2**80),
    st.integers(min_value=-3, max_value=800),
    st.tuples(numpy_ints, st.integers(min_value=0, max_value=2**31)).map(lambda t: t[0](t[1] % np.iinfo(t[0]).max)),
    st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(),
    st.none(),
    st.text(max_size=40),
    st.sampled_from(["end", "observe card 4", "move card 4 to r0c0", "reveal hint", "place hint 0 on card 2", "noop"]),
    st.lists(st.integers(min_value=0, max_value=10), max_size=3),
    st.binary(max_size=8),
)


def _mid_game(seed, steps):
    """A game some legal steps in (deterministic in seed and steps)."""
    env = yokai.Env("9c-2p-perfect", seed=seed)
    for k in range(steps):
        if env.done:
            break
        legal = [a for a in env.legal_actions() if env.action_name(a) != "end"] or env.legal_actions()
        env.step(legal[(seed + k * 7) % len(legal)])
    return env


def _is_index(x):
    return isinstance(x, (int, np.integer)) and not isinstance(x, (bool, np.bool_))


@FUZZ
@given(seed=st.integers(0, 50), steps=st.integers(0, 40), action=anything)
def test_any_object_as_an_action_plays_it_or_is_refused_with_the_game_unchanged(seed, steps, action):
    env = _mid_game(seed, steps)
    before = env.to_replay()
    legal = set(env.legal_actions()) if not env.done else set()
    try:
        env.step(action)
    except yokai.IllegalActionError:
        assert env.to_replay() == before
        if _is_index(action):
            assert int(action) not in legal
        return
    except TypeError as e:
        assert "an action is an int index or a name" in str(e), e
        assert not _is_index(action) and not isinstance(action, str)
        assert env.to_replay() == before
        return
    # Accepted: a legal index, or the name of a legal action; either way that action is the
    # one played, and the game moved one step.
    played = env.history[-1]
    assert played in legal
    if _is_index(action):
        assert int(action) == played
    else:
        assert isinstance(action, str) and env.action_index(action) == played
    assert env.steps == len(env.history) == len(yokai.Env.from_replay(before).history) + 1


@FUZZ
@given(text=st.one_of(st.text(max_size=40), st.sampled_from(["end", "observe card 8", "move card 0 to r2c4", "place hint 1 on card 3"])))
def test_any_text_as_an_action_name_is_an_index_that_prints_back_or_an_illegal_action_error(text):
    env = yokai.Env("9c-2p-perfect", seed=1)
    try:
        index = env.action_index(text)
    except yokai.IllegalActionError:
        return
    assert 0 <= index < env.num_actions
    assert env.action_index(env.action_name(index)) == index


@FUZZ
@given(seat=anything)
def test_any_object_as_a_seat_is_a_seat_or_a_clear_error(seat):
    """A seat is an int in range (or None: the acting seat). Anything else is a ValueError
    naming the seat (ints out of range, however large) or a TypeError (bool, non-ints), in
    every method that takes a seat."""
    env = yokai.Env("9c-3p-perfect", seed=2)
    agent = yokai.Agent("random")
    valid = _is_index(seat) and 0 <= int(seat) < 3
    calls = [env.legal_actions, env.legal_mask, env.render, env.observation,
             lambda s: agent.observe(env, s, 0)]
    for call in calls:
        try:
            call(seat)
        except ValueError as e:
            assert _is_index(seat) and not valid and "no seat" in str(e), (seat, e)
        except TypeError as e:
            assert not _is_index(seat) and "a seat is an int" in str(e), (seat, e)
        else:
            assert valid or (seat is None and call is not calls[-1]), seat
    if valid:
        assert env.legal_actions(seat) == env.legal_actions(int(seat))


@FUZZ
@given(
    dtype=st.sampled_from([np.int64, np.int32, np.uint8, np.uint64, np.float64, np.bool_, object]),
    shape=st.sampled_from([(2,), (2, 2), (3,), (2, 3), (), (1, 2, 2)]),
    values=st.lists(st.one_of(st.integers(min_value=-5, max_value=1000), st.integers(min_value=0, max_value=12)),
                    min_size=8, max_size=8),
    seed=st.integers(0, 20),
)
def test_any_batch_of_actions_steps_or_is_refused_and_the_batch_still_steps(dtype, shape, values, seed):
    """Non-integer dtypes are a TypeError, a wrong shape a ValueError, an illegal action an
    IllegalActionError, each with every game unchanged; legal actions step."""
    venv = yokai.VecEnv("9c-2p-perfect", num_envs=2, seed=seed)
    out = venv.reset()
    mask, acting = out["legal_mask"].copy(), out["acting_seat"].copy()
    size = int(np.prod(shape))
    try:
        actions = np.array(values[:size], dtype=np.int64).astype(dtype).reshape(shape)
    except (ValueError, OverflowError):
        return
    boards = [venv.render(i) for i in range(2)]
    chosen = [int(a) for a in actions.ravel()] if shape in [(2,), (2, 2)] else []
    if shape == (2,):
        legal = all(0 <= a < venv.num_actions and mask[i, acting[i], a] for i, a in enumerate(chosen))
    else:
        legal = all(0 <= a < venv.num_actions and mask[k // 2, k % 2, a] for k, a in enumerate(chosen))
    try:
        venv.step(actions)
    except TypeError as e:
        assert dtype in (np.float64, np.bool_, object), e
    except yokai.IllegalActionError as e:
        assert shape in [(2,), (2, 2)] and dtype not in (np.float64, np.bool_, object) and not legal, e
    except ValueError as e:
        assert "shape" in str(e) and shape not in [(2,), (2, 2)], e
    else:
        assert dtype not in (np.float64, np.bool_, object) and legal, (actions, chosen)
        boards = None
    if boards is not None:
        assert [venv.render(i) for i in range(2)] == boards
    # Refused or not, the batch goes on with legal actions exactly as a twin batch that
    # was only ever given the steps that were accepted.
    twin = yokai.VecEnv("9c-2p-perfect", num_envs=2, seed=seed)
    twin.reset()
    if boards is None:
        twin.step(actions)
    out, want = venv.step(venv.sample_actions(seed)), twin.step(twin.sample_actions(seed))
    for key in ("obs", "legal_mask", "acting_seat", "reward", "shaping", "done"):
        assert np.array_equal(out[key], want[key]), key


@FUZZ
@given(name=st.text(max_size=30), num_envs=st.integers(min_value=-(2**70), max_value=5))
def test_any_config_name_and_size_is_a_game_or_a_config_error(name, num_envs):
    try:
        env = yokai.Env(name)
    except yokai.ConfigError:
        pass
    else:
        assert env.config in yokai.configs() or os.path.exists(name)
    try:
        venv = yokai.VecEnv("9c-2p-perfect", num_envs=num_envs)
    except (yokai.ConfigError, OverflowError) as e:
        assert num_envs <= 0, e
    else:
        assert num_envs >= 1 and venv.num_envs == num_envs
