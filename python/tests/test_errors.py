"""Every documented error is raised as a Python exception with the engine's message."""

import numpy as np
import pytest

import yokai


def test_exception_hierarchy():
    for cls in [yokai.ConfigError, yokai.IllegalActionError, yokai.ReplayError]:
        assert issubclass(cls, yokai.YokaiError)
    assert issubclass(yokai.YokaiError, ValueError)


@pytest.mark.parametrize("name", ["9c-5p-perfect", "nonsense", "no/such/file.toml"])
def test_bad_config_names(name):
    with pytest.raises(yokai.ConfigError):
        yokai.Env(name)
    with pytest.raises(yokai.ConfigError):
        yokai.VecEnv(name, num_envs=2)


def test_broken_toml_names_the_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text('preset = "9c"\nplayers = 2\ncolour = 3\n')
    with pytest.raises(yokai.ConfigError, match="broken.toml"):
        yokai.Env(str(path))


@pytest.mark.parametrize(
    "kwargs",
    [{"num_envs": 0}, {"obs": "pixels"}, {"obs": "image-secret"}, {"threads": 0}],
)
def test_bad_vec_env_options(kwargs):
    with pytest.raises(yokai.ConfigError):
        yokai.VecEnv("9c-2p-perfect", **{"num_envs": 2, **kwargs})


@pytest.mark.parametrize("dtype", ["float64", "int16", "not-a-dtype"])
def test_bad_dtype(dtype):
    with pytest.raises(ValueError, match="float32 or uint8"):
        yokai.VecEnv(num_envs=2, dtype=dtype)


def test_a_num_envs_too_large_for_memory_is_a_memory_error_not_a_crash():
    # 2^40 games need more memory than a process can address: refused before any games
    # are dealt, naming the size, and the interpreter lives on.
    with pytest.raises(MemoryError, match=r"num_envs = 1099511627776 needs .* TB"):
        yokai.VecEnv("9c-2p-perfect", num_envs=2**40)
    assert yokai.VecEnv("9c-2p-perfect", num_envs=2).num_envs == 2


def test_illegal_action_in_a_batch_names_env_and_reason_and_changes_nothing():
    venv = yokai.VecEnv(num_envs=3, seed=0)
    out = venv.reset()
    before = out["obs"].copy()
    masks = out["legal_mask"].copy()
    boards = [venv.render(i) for i in range(3)]
    actions = venv.sample_actions(0).astype(np.int64)
    move = yokai.Env().action_index("move card 4 to r0c0")
    actions[2] = move  # substep 0: MOVE is not allowed
    with pytest.raises(yokai.IllegalActionError, match=r"env 2: seat 0 cannot play `move card 4 to r0c0`: substep 0"):
        venv.step(actions)
    # Nothing moved, in env 2 or the legal envs 0 and 1 (the arrays are live views of the
    # environment's buffers): the same observations, masks and boards, and the next legal
    # step plays as in a twin that never saw the refusal.
    np.testing.assert_array_equal(out["obs"], before)
    np.testing.assert_array_equal(out["legal_mask"], masks)
    assert [venv.render(i) for i in range(3)] == boards
    twin = yokai.VecEnv(num_envs=3, seed=0)
    twin.reset()
    legal = venv.sample_actions(0)
    np.testing.assert_array_equal(venv.step(legal)["obs"], twin.step(legal)["obs"])


def test_waiting_seat_must_play_noop():
    venv = yokai.VecEnv(num_envs=2)
    venv.reset()
    joint = np.zeros((2, 2), dtype=np.int64)
    joint[:, 0] = venv.sample_actions(0)
    joint[1, 1] = 3
    with pytest.raises(yokai.IllegalActionError, match="other seats must submit NOOP"):
        venv.step(joint)


def test_action_index_out_of_range():
    venv = yokai.VecEnv(num_envs=2)
    venv.reset()
    with pytest.raises(yokai.IllegalActionError, match="env 0"):
        venv.step(np.array([venv.num_actions, 1]))
    with pytest.raises(ValueError, match="not an action index"):
        venv.step(np.array([-1, 1]))


@pytest.mark.parametrize("shape", [(3,), (2, 3), (2, 2, 1), ()])
def test_wrong_action_shape(shape):
    venv = yokai.VecEnv(num_envs=2)
    venv.reset()
    with pytest.raises(ValueError, match=r"shape \(2,\) or \(2, 2\)"):
        venv.step(np.ones(shape, dtype=np.int64))


def test_non_integer_actions():
    venv = yokai.VecEnv(num_envs=2)
    venv.reset()
    with pytest.raises(TypeError, match="float64"):
        venv.step(np.array([1.0, 2.0]))


def test_env_illegal_action_leaves_game_unchanged():
    env = yokai.Env(seed=3)
    with pytest.raises(yokai.IllegalActionError, match="substep 0 allows only OBSERVE or END"):
        env.step("reveal hint")
    assert env.steps == 0
    with pytest.raises(yokai.IllegalActionError, match="not an action name"):
        env.step("fly away")
    with pytest.raises(yokai.IllegalActionError):
        env.step(10_000)
    with pytest.raises(TypeError):
        env.step(1.5)
    with pytest.raises(ValueError, match="no seat 5"):
        env.legal_actions(5)
    with pytest.raises(ValueError, match="one action per seat"):
        env.step_joint([1])


def test_finished_game_refuses_actions():
    env = yokai.Env(seed=0)
    env.step("end")
    assert env.done
    with pytest.raises(yokai.IllegalActionError, match="game is over"):
        env.step("end")


def test_bad_replays():
    with pytest.raises(yokai.ReplayError, match="not a valid episode record"):
        yokai.Env.from_replay("{not json")
    env = yokai.Env(seed=3)
    env.step(env.legal_actions()[-1])
    text = env.to_replay().replace('"actions":[', '"actions":[2,')
    # Two OBSERVEs, then a third where MOVE is due (or OBSERVE twice the same card).
    text = text.replace('"actions":[2,', '"actions":[2,2,')
    with pytest.raises(yokai.ReplayError, match="step 1"):
        yokai.Env.from_replay(text)


def test_every_out_of_range_or_wrongly_typed_action_is_a_clear_error_and_changes_nothing():
    env = yokai.Env(seed=3)
    n = env.num_actions
    for bad in [2**70, -1, n, np.uint64(2**63), np.int64(-5)]:
        with pytest.raises(yokai.IllegalActionError, match="not an action index|out of range"):
            env.step(bad)
    # bool is not an action index (True would otherwise be END), nor is a float.
    for bad in [True, False, 1.5, None]:
        with pytest.raises(TypeError, match="an action is an int index or a name"):
            env.step(bad)
    # NumPy integers are indices like Python ints.
    assert env.steps == 0
    env.step(np.int32(env.legal_actions()[0]))
    assert env.steps == 1
    # Seats out of range are ValueErrors naming the seat, whatever their sign.
    for seat in [-1, 2]:
        with pytest.raises(ValueError, match="no seat"):
            env.legal_actions(seat)
    venv = yokai.VecEnv(num_envs=2)
    venv.reset()
    with pytest.raises(yokai.IllegalActionError, match="not an action index"):
        venv.step(np.array([-1, 2]))
    with pytest.raises(ValueError, match="no seat -1"):
        venv.render(0, -1)
    with pytest.raises(ValueError, match="no game -1"):
        venv.render(-1)
