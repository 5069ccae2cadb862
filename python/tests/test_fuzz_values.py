"""A fuzz target for the conversion of Python values into overrides (issue 66): a seeded battery of
hostile keys and values — nested lists, tuples and dicts, lists that contain themselves, nesting
1e5 deep, huge lists and strings, huge integers, NaN and infinities, bytes, sets, objects whose
``__float__`` or ``__repr__`` misbehave, lone surrogates, keys of many parts, keys that are not
strings — each handed to ``kecsim.profiles``. The only outcomes allowed are success and a kecsim
exception (``kecsim.KecsimError``); never another exception, never a crash.

The battery runs in a subprocess, so that a crash (SIGSEGV, an abort) fails the test and names
the case it died on. ``KECSIM_FUZZ_CASES`` (default 400) and ``KECSIM_FUZZ_SEED`` (default 66)
set its size and seed: ``KECSIM_FUZZ_CASES=20000 pytest python/tests/test_fuzz_values.py`` for a
longer search; a failure prints the seed and the case to replay.
"""

import os
import subprocess
import sys
import textwrap

CHILD = r'''
import decimal, fractions, math, random, sys, time
import kecsim

try:
    import numpy as np
except ImportError:  # (numpy is a dependency; kept optional here)
    np = None

# A scene that compiles in milliseconds: only the profiles (kecsim.profiles reads no more).
SCENE = 'schema_version = 1\nname = "fuzz"\n[profiles]\nwheel = "s1002"\nrail = "60e1"\ninclination = "1:40"\n'
KEYS = [
    "name", "profiles.wheel", "profiles.rail", "profiles.inclination", "schema_version",
    "simulation.speed_m_s", "simulation.duration_s", "track.irregularities.seed",
    "vehicle.wheelsets.0.name", "wheelset.back_to_back_mm",
]

# Values the scene takes (a success, then the next case on a fresh scene).
PLAUSIBLE = {"name": "renamed", "profiles.wheel": "s1002", "profiles.rail": "60e1", "profiles.inclination": "1:20"}


class BadFloat:
    def __float__(self):
        raise RuntimeError("no float here")


class StrFloat:
    def __float__(self):
        return "1.0"


class BadRepr:
    def __repr__(self):
        raise RuntimeError("no repr here")

    def __float__(self):
        raise ValueError("nor a float")


class HugeRepr:
    def __repr__(self):
        return "r" * 5_000_000


class FloatSub(float):
    pass


class IntSub(int):
    pass


class ListSub(list):
    pass


def text(rng):
    pick = rng.random()
    if pick < 0.1:
        return "x" * rng.choice([0, 1, 255, 256, 257, 100_000, 1_000_001, 3_000_000])
    alphabet = "abc.01_ \t\n\"'\\\x00\x1b\u00e9\u4e2d\U0001f600\ud800\udfff=[]{}#"
    return "".join(rng.choice(alphabet) for _ in range(rng.randrange(0, 40)))


def key(rng):
    pick = rng.random()
    if pick < 0.3:
        return rng.choice(KEYS)
    if pick < 0.45:
        parts = rng.choice([1, 2, 15, 16, 17, 100, 50_000])
        return ".".join(rng.choice(["a", "simulation", "0", "", "vehicle"]) for _ in range(parts))
    if pick < 0.55:
        return rng.choice([0, 1.5, None, b"name", ("simulation", "speed_m_s"), frozenset(), True])
    if pick < 0.6:
        return rng.choice(["", ".", "..", "a..b", ".a", "a.", "x" * 257, "x" * 10_000_000])
    return text(rng)


def nested(rng, depth, kind):
    value = rng.choice([1.0, "s", 0, True, []])
    for _ in range(depth):
        value = [value] if kind == "list" else (value,) if kind == "tuple" else {"k": value}
    return value


def value(rng, budget=3):
    pick = rng.randrange(30)
    if pick == 0:
        return rng.choice([0, 1, -1, 2**63 - 1, -(2**63), 2**63, -(2**63) - 1, 10**30, 7**50_000])
    if pick == 1:
        return rng.choice([0.0, -0.0, math.nan, math.inf, -math.inf, 1e308, 5e-324, 15.0, 19.0])
    if pick == 2:
        return text(rng)
    if pick == 3:
        return rng.choice([b"", b"fast", bytearray(b"x"), memoryview(b"ab")])
    if pick == 4:
        return rng.choice([None, object(), BadFloat(), StrFloat(), BadRepr(), HugeRepr(), print, type])
    if pick == 5:
        a = [1.0]
        a.append(a)
        return rng.choice([a, (a,), [a, a], {"self": a}])
    if pick == 6:
        return nested(rng, rng.choice([31, 32, 33, 1000, 100_000]), rng.choice(["list", "tuple", "dict"]))
    if pick == 7:
        return [0.5] * rng.choice([99_999, 100_000, 100_001, 1_000_000, 10_000_000])
    if pick == 8:
        return [["s" * 1000] * 1000] * rng.choice([1, 2])
    if pick == 9:
        return rng.choice([{1, 2}, frozenset(), range(10), iter([1]), 1 + 2j])
    if pick == 10:
        return rng.choice([decimal.Decimal("1.5"), decimal.Decimal("nan"), fractions.Fraction(1, 3)])
    if pick == 11:
        return rng.choice([FloatSub(2.5), IntSub(3), IntSub(2**70), ListSub([1.0, 2.0])])
    if pick == 12 and np is not None:
        return rng.choice([
            np.float64(15.0), np.float32("nan"), np.int64(3), np.uint64(2**64 - 1), np.bool_(True),
            np.False_, np.array([1.0, 2.0]), np.array(3.0), np.zeros((2, 2)), np.str_("kec"),
        ])
    if pick == 13:
        d = {}
        d["d"] = d
        return rng.choice([d, {"a": 1.0}, {1: 2}, {}])
    if budget > 0 and pick < 22:
        n = rng.randrange(0, 6)
        items = [value(rng, budget - 1) for _ in range(n)]
        return items if pick % 2 else tuple(items)
    return rng.choice([1.0, 15, "kec", True, False, [1.0, 2.0], ["a", "b"]])


seed, cases = int(sys.argv[1]), int(sys.argv[2])
rng = random.Random(seed)
t0 = time.time()
outcomes = {"ok": 0}
for case in range(cases):
    print("case", case, flush=True)
    k, v = key(rng), value(rng)
    if k in PLAUSIBLE and rng.random() < 0.5:
        v = PLAUSIBLE[k]
    try:
        kecsim.profiles(SCENE, {k: v})
        outcomes["ok"] += 1
    except kecsim.KecsimError as e:
        name = type(e).__name__
        outcomes[name] = outcomes.get(name, 0) + 1
        if len(str(e)) > 20_000:
            print("LONG MESSAGE", len(str(e)), repr(str(e)[:300]), flush=True)
            sys.exit(2)
    except BaseException as e:
        print("NOT A KECSIM EXCEPTION", type(e).__name__, repr(str(e)[:300]), flush=True)
        sys.exit(2)
    del k, v
print("done", round(time.time() - t0, 1), sorted(outcomes.items()), flush=True)
'''


def test_no_python_value_crashes_the_conversion(tmp_path):
    seed = int(os.environ.get("KECSIM_FUZZ_SEED", "66"))
    cases = int(os.environ.get("KECSIM_FUZZ_CASES", "400"))
    script = tmp_path / "fuzz.py"
    script.write_text(CHILD)
    try:
        p = subprocess.run(
            [sys.executable, str(script), str(seed), str(cases)],
            capture_output=True, text=True, timeout=max(300, cases),
        )
        out, err, rc = p.stdout, p.stderr, p.returncode
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"").decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
        raise AssertionError(f"the battery hung (seed {seed}); last lines:\n{out[-500:]}")
    lines = out.strip().split("\n")
    where = f"seed {seed}, {lines[-1] if lines else 'no output'}"
    assert rc == 0, (
        f"the interpreter ended with {rc} ({'a crash by signal %d' % -rc if rc < 0 else 'see below'}) at {where}\n"
        + "\n".join(lines[-3:]) + "\n" + err[-2000:]
    )
    assert lines[-1].startswith("done"), where
    print(lines[-1])
