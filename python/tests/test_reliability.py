"""The Python package under hostile use (issue 66): `save=` through the command line's output
guard and locks; Python values that cannot crash the interpreter (depth, sizes, keys bounded,
the messages short); the contact sweep's options checked as `kecsim contact` checks them; Ctrl-C
and a progress callback that is slow, raises or answers a false value other than False.

Each hostile call that could crash the interpreter runs in a subprocess: a crash (a signal, an
abort) fails the test instead of ending pytest.
"""

import os
import pathlib
import shutil
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import kecsim

REPO = pathlib.Path(__file__).resolve().parents[2]
TINY = {"simulation.duration_s": 0.2}
viewer = pytest.mark.skipif(
    not kecsim.has_viewer(),
    reason="save= needs the package built with the viewer: "
    "pip install ./python --config-settings=build-args=\"--features viewer\"",
)


def kecsim_bin():
    if os.environ.get("KECSIM_BIN"):
        return pathlib.Path(os.environ["KECSIM_BIN"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = target / "release" / "kecsim"
    if not path.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "kecsim"], cwd=REPO, check=True)
    return path


def python(code, timeout=120):
    """Runs `code` in a fresh interpreter: (returncode, stdout, stderr). A negative return code
    is a crash by a signal (SIGSEGV: -11), 134 an abort."""
    p = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True, text=True, timeout=timeout,
    )
    return p.returncode, p.stdout, p.stderr


def assert_no_crash(rc, out, err):
    assert rc == 0, f"the interpreter ended with {rc} (a crash: < 0 is a signal, 134 an abort)\n{out}\n{err[-3000:]}"


# -- save= through the output guard (class 2) -------------------------------------------------


def scene_reading_a_profile(tmp_path):
    """A scene file whose wheel profile is a file beside it (which the run reads)."""
    shutil.copy(REPO / "profiles" / "ms-tram.csv", tmp_path / "wheel.csv")
    text = kecsim.default_scene().replace('wheel = "ms-tram"', 'wheel = "wheel.csv"', 1)
    assert 'wheel = "wheel.csv"' in text
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    return scene


@viewer
@pytest.mark.parametrize("target", ["scene", "profile", "symlink", "readonly"])
def test_save_never_writes_over_what_the_run_reads_nor_a_read_only_file(tmp_path, target):
    scene = scene_reading_a_profile(tmp_path)
    if target == "scene":
        path, named = scene, "scene.toml"
    elif target == "profile":
        path, named = tmp_path / "wheel.csv", "wheel.csv"
    elif target == "symlink":
        path = tmp_path / "link.rrd"
        path.symlink_to(scene)
        named = "scene.toml"
    else:
        path = tmp_path / "old.rrd"
        path.write_bytes(b"an earlier recording, kept read-only")
        path.chmod(0o444)
        named = "read-only"
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    with pytest.raises(kecsim.KecsimError) as e:
        kecsim.run(scene, TINY, save=path)
    message = str(e.value)
    assert "save=" in message and str(path) in message and named in message, message
    assert isinstance(e.value, ValueError)
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.is_file()}
    assert after == before, "a file changed or a part file was left"


@viewer
def test_save_is_refused_while_a_cli_run_writes_the_file(tmp_path):
    scene = scene_reading_a_profile(tmp_path)
    out = tmp_path / "out.rrd"
    lock = tmp_path / ".out.rrd.kecsim-lock"
    cli = subprocess.Popen(
        [str(kecsim_bin()), "run", str(scene), "--save", str(out)],
        cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.time() + 60
        while not lock.exists():
            assert cli.poll() is None and time.time() < deadline, "the CLI run took no lock"
            time.sleep(0.05)
        with pytest.raises(kecsim.KecsimError) as e:
            kecsim.run(scene, TINY, save=out)
        message = str(e.value)
        assert f"save= {out}" in message and f"pid {cli.pid}" in message, message
    finally:
        cli.send_signal(signal.SIGINT)
        cli.wait(timeout=60)


@viewer
def test_four_threads_saving_to_one_path_one_writes_the_others_are_refused(tmp_path):
    out = tmp_path / "one.rrd"
    barrier = threading.Barrier(4)
    outcomes = [None] * 4

    def one(k):
        barrier.wait()
        try:
            kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 3.0}, save=out)
            outcomes[k] = "ok"
        except kecsim.KecsimError as e:
            outcomes[k] = e

    threads = [threading.Thread(target=one, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(300)
    assert outcomes.count("ok") == 1, outcomes
    for e in outcomes:
        if e != "ok":
            assert f"save= {out}" in str(e) and "is writing this file" in str(e), str(e)
            assert "this process" in str(e), str(e)
    data = out.read_bytes()
    assert data[:4] == b"RRF2" and len(data) > 10_000
    assert [p.name for p in tmp_path.iterdir()] == ["one.rrd"], "a lock or part file was left"
    if shutil.which("rerun"):
        v = subprocess.run(["rerun", "rrd", "verify", str(out)], capture_output=True, text=True)
        assert v.returncode == 0, v.stderr


# -- Python values bounded (class 3) ----------------------------------------------------------


HOSTILE = {
    "a list that holds itself": "a = [1.0]; a.append(a); value = a",
    "a list nested 1e5 deep": "value = 1.0\nfor _ in range(100_000): value = [value]",
    "a tuple nested 1e5 deep": "value = 1.0\nfor _ in range(100_000): value = (value,)",
    "a list of 1e7 numbers": "value = [0.5] * 10_000_000",
    "a string of 1e7 characters": "value = 'x' * 10_000_000",
    "an integer past 64 bits": "value = 10 ** 30",
    "an integer of 1e5 digits": "import sys\nvalue = 7 ** 120_000",
    "a list of 1e3 lists of 1e3": "value = [[1.0] * 1000 for _ in range(1000)]",
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_a_hostile_override_value_raises_a_short_scenario_error(case):
    rc, out, err = python(
        HOSTILE[case]
        + textwrap.dedent(
            """
            import time, kecsim
            t = time.time()
            try:
                kecsim.profiles(kecsim.default_scene(), {"simulation.speed_m_s": value})
                print("accepted")
            except kecsim.ScenarioError as e:
                print("refused", len(str(e)), round(time.time() - t, 1))
                print(str(e))
            """
        )
    )
    assert_no_crash(rc, out, err)
    first, message = out.split("\n", 1)
    word, length, seconds = first.split()
    assert word == "refused", out
    assert int(length) < 800, message
    assert float(seconds) < 10, first
    assert "simulation.speed_m_s" in message, message


def test_the_value_limits_are_named():
    deep = 1.0
    for _ in range(40):
        deep = [deep]
    with pytest.raises(kecsim.ScenarioError, match="32 levels"):
        kecsim.profiles(kecsim.default_scene(), {"simulation.speed_m_s": deep})
    with pytest.raises(kecsim.ScenarioError, match="more than 100000 entries in all"):
        kecsim.profiles(kecsim.default_scene(), {"simulation.speed_m_s": [1.0] * 100_001})
    with pytest.raises(kecsim.ScenarioError, match="64-bit"):
        kecsim.profiles(kecsim.default_scene(), {"simulation.speed_m_s": 2**63})
    # Within the limits, the scenario's own check: a list is not a speed.
    with pytest.raises(kecsim.ScenarioError, match="the scenario does not take it"):
        kecsim.profiles(kecsim.default_scene(), {"simulation.speed_m_s": [[1.0] * 10] * 10})
    # A type with no TOML form: a ScenarioError and a TypeError.
    with pytest.raises(kecsim.ScenarioError) as e:
        kecsim.profiles(kecsim.default_scene(), {"simulation.speed_m_s": b"fast"})
    assert isinstance(e.value, TypeError) and "b'fast'" in str(e.value)


@pytest.mark.parametrize(
    "key, limit",
    [("'a.' * 49_999 + 'a'", "16 parts"), ("'x' * 10_000_000", "256 characters"), ("'simulation.' * 17 + 'x'", "16 parts")],
    ids=["50000 parts", "1e7 characters", "18 parts"],
)
def test_a_hostile_override_key_raises_a_short_scenario_error(key, limit):
    rc, out, err = python(
        f"""
        import kecsim
        key = {key}
        try:
            kecsim.profiles(kecsim.default_scene(), {{key: 1.0}})
            print("accepted")
        except kecsim.ScenarioError as e:
            print(len(str(e)))
            print(str(e))
        """
    )
    assert_no_crash(rc, out, err)
    length, message = out.split("\n", 1)
    assert int(length) < 800 and limit in message, message


# -- the contact sweep's options as the CLI's (class 12) --------------------------------------


def test_the_contact_sweep_refuses_what_kecsim_contact_refuses():
    with pytest.raises(ValueError) as e:
        kecsim.contact_sweep(kecsim.default_scene(), y_max_mm=40)
    assert "y_max_mm 40.000 mm: beyond the flange climb" in str(e.value), str(e.value)
    for step in (0.3, 5.0):
        with pytest.raises(ValueError, match="coarser than 0.25 mm"):
            kecsim.contact_sweep(kecsim.default_scene(), step_mm=step)
    for step in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="expected a positive length in mm"):
            kecsim.contact_sweep(kecsim.default_scene(), step_mm=step)
    with pytest.raises(ValueError, match="expected a positive length in mm"):
        kecsim.contact_sweep(kecsim.default_scene(), y_max_mm=float("nan"))
    # Within the flange climb and at the coarsest step: swept.
    sweep = kecsim.contact_sweep(kecsim.default_scene(), y_max_mm=3.0, step_mm=0.25)
    y = sweep["table"]["y_mm"]
    assert y[0] >= -3.0 - 0.25 and y[-1] <= 3.0 + 0.25


# -- Ctrl-C and the progress callback (class 10) ----------------------------------------------


LONG_RUN = """
    import signal, sys, time, kecsim
    signal.signal(signal.SIGINT, signal.default_int_handler)
    calls = []
    def progress(t, duration):
        calls.append(t)
        print("call", len(calls), flush=True)
        time.sleep(SLEEP)
    try:
        kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 50.0}, threads=1, progress=progress)
        print("completed", flush=True)
    except kecsim.Interrupted as e:
        print("interrupted", len(calls), e.result.interrupted, flush=True)
        sys.exit(3)
"""


@pytest.mark.parametrize("sleep", [0.5, 2.0])
def test_ctrl_c_stops_a_run_with_a_slow_callback_within_the_callback_time(tmp_path, sleep):
    script = tmp_path / "slow.py"
    script.write_text(textwrap.dedent(LONG_RUN).replace("SLEEP", repr(sleep)))
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    try:
        first = p.stdout.readline().split()
        assert first[:1] == ["call"], first
        time.sleep(0.1)
        p.send_signal(signal.SIGINT)
        t0 = time.time()
        out, _ = p.communicate(timeout=60)
        took = time.time() - t0
    finally:
        if p.poll() is None:
            p.kill()
    lines = out.split("\n")
    after = [l for l in lines if l.startswith("call")]
    assert p.returncode == 3, out
    assert len(after) <= 1, f"called {len(after)} times after the signal"
    assert lines[-2].startswith("interrupted") and lines[-2].endswith("True"), out
    assert took < sleep + 2.0, f"{took:.1f} s to stop with a {sleep} s callback"


def test_a_callback_that_raised_is_never_called_again():
    calls = []

    def progress(t, duration):
        calls.append(t)
        # (Slow first: the run computes samples meanwhile, which must not reach it after.)
        time.sleep(0.3)
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 3.0}, progress=progress)
    assert len(calls) == 1, f"called {len(calls)} times"


@pytest.mark.parametrize("false", ["numpy.False_", "0", "empty list"])
def test_a_false_answer_other_than_false_stops_the_run_and_the_callback_is_not_called_again(false):
    np = pytest.importorskip("numpy")
    answer = {"numpy.False_": np.False_, "0": 0, "empty list": []}[false]
    calls = []

    def progress(t, duration):
        calls.append(t)
        return answer if t >= 0.2 else None

    r = kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 3.0}, progress=progress)
    assert r.interrupted and r.summary["stopped"] == "interrupted"
    assert calls[-1] >= 0.2 and calls[-2] < 0.2, calls[-3:]
    assert r.wheelsets["w1"]["t_s"][-1] < 1.0


def test_an_answer_with_no_truth_value_stops_the_run_and_is_raised():
    np = pytest.importorskip("numpy")
    calls = []

    def progress(t, duration):
        calls.append(t)
        return np.array([True, False])

    with pytest.raises(ValueError, match="truth value"):
        kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 3.0}, progress=progress)
    assert len(calls) == 1
