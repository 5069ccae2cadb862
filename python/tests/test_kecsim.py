"""The Python package against the command line: the same scene and overrides give the CLI's CSV
and JSON to the last digit written; scenes from strings; overrides; errors naming the key; a
stopped run returning what it computed; Ctrl-C.

The `kecsim` binary: $KECSIM_BIN, else $CARGO_TARGET_DIR/release/kecsim, else the repository's
target/release/kecsim (built with `cargo build --release` where it is missing).
"""

import csv
import json
import math
import os
import pathlib
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import kecsim

REPO = pathlib.Path(__file__).resolve().parents[2]
SHORT = {"simulation.duration_s": 2.0}


def kecsim_bin():
    if os.environ.get("KECSIM_BIN"):
        return pathlib.Path(os.environ["KECSIM_BIN"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = target / "release" / "kecsim"
    if not path.exists():
        subprocess.run(["cargo", "build", "--release", "--bin", "kecsim"], cwd=REPO, check=True)
    return path


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def scene_with(tmp_path, replacements):
    """The default scene with `key = value` lines replaced (the CLI reads files only)."""
    text = kecsim.default_scene()
    for old, new in replacements:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_arrays_equal_the_cli_csv_and_summary_the_json(tmp_path):
    """`kecsim run SCENE --speed 15 --csv --json` and `kecsim.run(SCENE, overrides)`: every
    column of every wheelset equal to the last digit written (the CSV's %.9e), the same rows,
    the same summary keys and values (but the wall times)."""
    base = kecsim.default_scene()
    duration_line = next(l for l in base.splitlines() if l.startswith("duration_s"))
    scene = scene_with(tmp_path, [(duration_line, "duration_s = 2.0")])
    out = tmp_path / "csv"
    subprocess.run(
        [str(kecsim_bin()), "run", str(scene), "--speed", "15", "--csv", str(out),
         "--json", str(tmp_path / "run.json"), "--save", str(tmp_path / "run.rrd")],
        cwd=tmp_path, check=True, capture_output=True,
    )
    r = kecsim.run(str(scene), {"simulation.speed_m_s": 15.0})
    assert r.summary["outcome"] == "completed" and not r.interrupted and r.failure is None
    assert list(r.wheelsets) == ["w1", "w2", "w3", "w4", "w5", "w6"]
    for name, columns in r.wheelsets.items():
        header, rows = read_csv(out / f"{name}.csv")
        assert list(columns) == header == kecsim.csv_columns()
        assert all(len(a) == len(rows) for a in columns.values())
        for k, col in enumerate(header):
            written = np.array([float(row[k]) for row in rows])
            ours = np.array([float("%.9e" % v) for v in columns[col]])
            same = (written == ours) | (np.isnan(written) & np.isnan(ours))
            assert same.all(), (name, col, np.flatnonzero(~same)[:5])
    cli = json.loads((tmp_path / "run.json").read_text())
    assert set(cli) == set(r.summary)
    for key in cli:
        if key in ("wall_s", "realtime_factor", "preprocessing_s"):
            continue
        assert cli[key] == r.summary[key], key


def test_a_scene_from_a_string():
    text = kecsim.default_scene()
    assert "\n" in text and not os.path.exists(text.splitlines()[0])
    r = kecsim.run(text, SHORT)
    t = r.wheelsets["w1"]["t_s"]
    assert t[-1] == pytest.approx(2.0, abs=1e-12)
    assert r.summary["samples"] == len(t)


def test_an_override_of_speed_and_duration():
    r = kecsim.run(kecsim.default_scene(), {"simulation.speed_m_s": 10, "simulation.duration_s": 1.5})
    w = r.wheelsets["w3"]
    assert w["t_s"][-1] == pytest.approx(1.5, abs=1e-12)
    # The speed loop holds V: 10 m/s at the start, within 1 % at the end.
    assert w["speed_m_s"][0] == pytest.approx(10.0, rel=1e-9)
    assert w["speed_m_s"][-1] == pytest.approx(10.0, rel=1e-2)
    # The distance run is the speed's integral.
    s = w["s_m"]
    assert s[-1] - s[0] == pytest.approx(np.trapezoid(w["speed_m_s"], w["t_s"]), rel=1e-3)


def test_a_bad_key_raises_with_the_key_named():
    with pytest.raises(kecsim.ScenarioError) as e:
        kecsim.run(kecsim.default_scene(), {"simulation.sped_m_s": 10.0})
    assert "simulation.sped_m_s" in str(e.value) and "unknown field" in str(e.value)
    with pytest.raises(kecsim.ScenarioError) as e:
        kecsim.run(kecsim.default_scene(), {"simulation.speed_m_s": "fast"})
    assert "simulation.speed_m_s" in str(e.value)
    # In the scenario itself: the file (here <string>) and the line.
    text = textwrap.dedent(
        """\
        schema_version = 1
        name = "x"
        [simulation]
        speed_m_s = 1.0
        duration_s = 1.0
        bogus = 3
        """
    )
    with pytest.raises(kecsim.ScenarioError) as e:
        kecsim.run(text)
    assert "<string>" in str(e.value) and "line 6" in str(e.value) and "bogus" in str(e.value)
    with pytest.raises(kecsim.ScenarioError) as e:
        kecsim.run("no/such/scene.toml")
    assert "no/such/scene.toml" in str(e.value)
    with pytest.raises(TypeError):
        kecsim.run(kecsim.default_scene(), SHORT, speed=3)
    with pytest.raises(TypeError) as e:
        kecsim.run(kecsim.default_scene(), {"simulation.speed_m_s": object()})
    assert "simulation.speed_m_s" in str(e.value)


def test_a_file_error_names_the_file_and_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(kecsim.default_scene().replace("[simulation]\n", "[simulation]\nsped = 1\n", 1))
    with pytest.raises(kecsim.ScenarioError) as e:
        kecsim.run(path)
    line = next(k for k, l in enumerate(path.read_text().splitlines(), 1) if l.startswith("sped ="))
    assert str(path) in str(e.value) and f"line {line}" in str(e.value), str(e.value)


def test_a_stopped_run_returns_what_it_computed():
    full = kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 3.0})
    seen = []

    def progress(t, duration):
        seen.append((t, duration))
        return t < 0.2

    part = kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 3.0}, progress=progress)
    assert part.interrupted and part.summary["stopped"] == "interrupted"
    n = len(part.wheelsets["w1"]["t_s"])
    assert 0 < n < len(full.wheelsets["w1"]["t_s"])
    assert part.wheelsets["w1"]["t_s"][-1] < 1.0
    assert seen[0][1] == 3.0 and seen[-1][0] >= 0.2
    # What it computed is the full run's beginning, to the bit, on the output grid; the
    # integrator ends at the step where the stop found it, with one more sample there (between
    # two output times) unless the grid just gave one.
    t_full, t_part = full.wheelsets["w1"]["t_s"], part.wheelsets["w1"]["t_s"]
    on_grid = n
    if t_part[-1] != t_full[n - 1]:
        assert t_full[n - 2] < t_part[-1] < t_full[n - 1]
        on_grid = n - 1
    for col in ("t_s", "y_mm", "yaw_mrad"):
        assert np.array_equal(part.wheelsets["w1"][col][:on_grid], full.wheelsets["w1"][col][:on_grid], equal_nan=True), col


def test_a_progress_callback_error_stops_the_run_and_is_raised():
    def progress(t, duration):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        kecsim.run(kecsim.default_scene(), SHORT, progress=progress)


def test_ctrl_c_stops_the_run_and_keeps_what_it_computed(tmp_path):
    script = tmp_path / "long.py"
    script.write_text(
        textwrap.dedent(
            """\
            import signal, sys, kecsim
            # Python's own Ctrl-C handler even where SIGINT came ignored (a job started with `&`
            # by a non-interactive shell: CI launched in the background).
            signal.signal(signal.SIGINT, signal.default_int_handler)
            def progress(t, duration):
                # The signal is sent once the run has computed something: a fixed wait raced the
                # preprocessing on a busy machine (one sample kept).
                if t > 0.2 and not progress.said:
                    progress.said = True
                    print("running", flush=True)
            progress.said = False
            print("started", flush=True)
            try:
                # DOPRI5 at 1e-8 (the precision protocol's reference): tens of seconds on any
                # machine, so the signal lands mid-run however fast the default has become.
                kecsim.run(
                    kecsim.default_scene(),
                    {
                        "simulation.duration_s": 50.0,
                        "simulation.integrator.method": "dopri5",
                        "simulation.integrator.rtol": 1e-8,
                    },
                    threads=1,
                    progress=progress,
                )
            except kecsim.Interrupted as e:
                r = e.result
                print("interrupted", r.interrupted, len(r.wheelsets["w1"]["t_s"]), r.wheelsets["w1"]["t_s"][-1], flush=True)
                sys.exit(3)
            """
        )
    )
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "started"
    assert p.stdout.readline().strip() == "running"
    p.send_signal(signal.SIGINT)
    t0 = time.time()
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 3, out
    word, flag, n, t_end = out.split()
    assert word == "interrupted" and flag == "True" and int(n) > 1 and 0 < float(t_end) < 40
    assert time.time() - t0 < 10


def test_the_contact_sweep_equals_kecsim_contact_and_the_profiles_their_files(tmp_path):
    """The default scene's pair (ms-tram on 54E1 with its arc joints blended, at 1:20,
    back-to-back 1366 mm, r0 295 mm) swept as `kecsim contact --csv` sweeps it: every column to
    the last digit written."""
    sweep = kecsim.contact_sweep(kecsim.default_scene())
    table = sweep["table"]
    subprocess.run(
        [str(kecsim_bin()), "contact", "--wheel", "ms-tram", "--rail", "54e1:blend=1", "--inclination", "1:20",
         "--back-to-back", "1366", "--wheel-radius", "295", "--csv", str(tmp_path / "sweep.csv"),
         "--save", str(tmp_path / "sweep.rrd")],
        cwd=tmp_path, check=True, capture_output=True,
    )
    header, rows = read_csv(tmp_path / "sweep.csv")
    assert list(table) == header
    for k, col in enumerate(header):
        written = np.array([float(row[k]) if row[k] else math.nan for row in rows])
        ours = np.array([float("%.12e" % v) for v in table[col]])
        same = (written == ours) | (np.isnan(written) & np.isnan(ours))
        assert same.all(), (col, np.flatnonzero(~same)[:5])
    y = table["y_mm"]
    assert len(y) > 100 and np.all(np.diff(y) > 0) and y[0] < 0 < y[-1]
    # A symmetric wheelset on a symmetric track: no rolling radius difference when centred.
    assert abs(np.interp(0.0, y, table["dr_mm"])) < 1e-6
    c = sweep["conicity"]
    assert list(c["amplitude_mm"]) == [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    # The scene's stated conicity of its stand-in wheel: 0.29 at 2 mm, 0.40 at 3 mm.
    assert c["annex_b"][1] == pytest.approx(0.29, abs=0.005)
    assert c["annex_b"][2] == pytest.approx(0.40, abs=0.005)
    assert "conicity" in sweep["report"].lower()

    prof = kecsim.profiles(kecsim.default_scene())
    assert set(prof) == {"wheel", "rail"}
    # The rail is the published 54E1 (profiles/54e1.csv, mm) with its arc joints blended: on the
    # head (|y| ≤ 25 mm, slopes ≤ 0.5) within the blend's 5.2 µm of the file, and not the file.
    assert prof["rail"]["name"] == "54e1:blend=1"
    with open(REPO / "profiles" / "54e1.csv") as f:
        rows = [l for l in f if l and not l.startswith("#")][1:]
    file_y = np.array([float(l.split(",")[0]) for l in rows])
    file_z = np.array([float(l.split(",")[1]) for l in rows])
    y, z = np.asarray(prof["rail"]["y_mm"]), np.asarray(prof["rail"]["z_mm"])
    head = np.abs(y) <= 25.0
    dz = np.abs(z[head] - np.interp(y[head], file_y, file_z))
    assert dz.max() < 0.0053 * np.sqrt(1.25) and dz.max() > 1e-4, dz.max()


def test_the_results_are_the_same_on_one_thread_and_two():
    a = kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 1.0}, threads=1)
    b = kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 1.0}, threads=2)
    for name in a.wheelsets:
        for col, v in a.wheelsets[name].items():
            assert np.array_equal(v, b.wheelsets[name][col], equal_nan=True), (name, col)
    with pytest.raises(ValueError):
        kecsim.run(kecsim.default_scene(), SHORT, threads=0)


def test_save_needs_the_viewer(tmp_path):
    if kecsim.has_viewer():
        r = kecsim.run(kecsim.default_scene(), {"simulation.duration_s": 0.5}, save=tmp_path / "a.rrd")
        assert (tmp_path / "a.rrd").stat().st_size > 0 and r.summary["outcome"] == "completed"
    else:
        with pytest.raises(ValueError, match="without the viewer"):
            kecsim.run(kecsim.default_scene(), SHORT, save=tmp_path / "a.rrd")
        assert not (tmp_path / "a.rrd").exists()
