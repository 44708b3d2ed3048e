"""The Python API misused, as a careless user or an adversary would: every
public function and method called with values drawn at random (seeded) from
pools of bad ones (NaN, infinities, negatives, 2**64, -1, 10**12, str,
None, lists, numpy arrays of the wrong dtype or shape, a list holding
itself) and a few good ones.

Run as a script (test_misuse.py does, in an empty directory, so that a
crash is a failed test and not a dead test run): `_fuzz_misuse.py SEED N`.
Each call must return, or raise ValueError or TypeError (KeyError for a
column that is not there) with a message on one line; anything else is
printed as `BAD <json>`. Prints `cases N` at the end.

The good values are chosen so that a call which succeeds is cheap: tiny
runs, one or two cases, a rare-event target that holds at once."""

import json
import math
import random
import sys
import time

import numpy as np

import tippetop as tt

NAN, INF = float("nan"), float("inf")

SELF = []
SELF.append(SELF)
DEEP = [1.0]
for _ in range(10_000):
    DEEP = [DEEP]

# A step cap keeps every run of a case cheap (a sweep may set t_end = 1 s).
NANO = tt.Scenario.preset("nano").set_many(
    {"solver.t_end": 1e-10, "solver.samples": 3, "solver.max_steps": 20000}
)
ENS = tt.Scenario.from_toml(
    """preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
t_end = 1e-13
samples = 2
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 1
"""
)
SNAP = tt.Simulation(NANO).snapshot()
OTHER_SNAP = tt.Simulation(NANO.set("surface.friction", 0.25)).snapshot()
TRAJ = tt.run(NANO)

# Values of a bool argument (pose, step_check), good and bad.
SWITCHES = [True, False, None, 1, "yes", np.bool_(False)]

# Values of every kind; the good ones are few and cheap.
ANY = [
    NAN, INF, -INF, -1, 0, 1, 2, -1.5, 1e300, -1e300, 2**64, -(2**64), 2**63, 10**12,
    "", "x", "nan", "1\n[top]\nradius = 1", "a\x00b", "\u00e9" * 3, b"1",
    None, True, False, [], [1, 2], [[1.0]], (), {}, {"a": 1}, 1 + 2j, object(),
    np.float32(1.5), np.float64(NAN), np.int64(2), np.uint64(2**64 - 1), np.bool_(True),
    np.array([1.0, 2.0]), np.array([[1.0]]), np.array(["a"]), np.array(3),
    np.array([], dtype=object), np.zeros((2, 2), dtype=np.int8), SELF, DEEP,
]
COUNTS = [None, 1, 2, 0, -1, 2**64, -(2**64), 2**63, 10**12, 10**6 + 1, 4294967297,
          "3", 2.0, NAN, True, np.int64(2), np.uint64(2**64 - 1), [2], np.array([2]), None]
FLOATS = [None, NAN, INF, -INF, -1.0, 0.0, 1e-12, 0.5, 1e300, "1", True, np.float32(0.5),
          np.array([0.5]), [0.5], 2**64]
KEYS = ["top.offset", "surface.friction", "solver.samples", "solver.t_end", "solver.dt",
        "thermal.seed", "thermal.run", "initial.spin", "force.0.hx", "solver.method",
        "top.radius", "surface.friction_law", "", "x", "x.y", "top", "top.", ".top",
        "a=b", "top.offset\n", "force.99999999999999999999.hx", None, 1]
CONDITIONS = [None, "theta>0.2", "theta<0.05", "theta>0", "theta<4", "t>-1", "", "x", "theta", "theta>nan",
              "theta>inf", "theta<1,", ",", "a\x00b", "theta>1e400", 3, b"theta>0"]
SCENARIOS = [NANO, NANO, ENS, None, "nano", 1, TRAJ, SNAP]


def r(value, n=40):
    """repr(value), cut to n characters (a list a million levels deep has
    none that Python can build)."""
    try:
        return repr(value)[:n]
    except RecursionError:
        return "<deeply nested list>"


def pick(rng, pool):
    return pool[rng.randrange(len(pool))]


def grid(rng):
    """A value of vary[key]: a (lo, hi, n) tuple, a list or array, or junk."""
    r = rng.random()
    if r < 0.5:
        t = (pick(rng, FLOATS), pick(rng, FLOATS), pick(rng, [1, 2, 0, -1, 2**64, 10**12, 2.5, "2", None]))
        if rng.random() < 0.2:
            t += (pick(rng, ["log", "lin", "", None, 1]),)
        return t
    if r < 0.8:
        return pick(rng, [[1e-11, 2e-11], np.array([1e-11]), [NAN], ["a"], [[1.0]], [],
                          np.array([[1e-11]]), np.array(["x"]), range(2), SELF, DEEP])
    return pick(rng, ANY)


def kwargs(rng, names):
    """Some of `names` as keyword arguments, each from its pool."""
    out = {}
    for name, pool in names:
        if rng.random() < 0.35:
            out[name] = pick(rng, pool)
    return out


def case(rng):
    """One call: (a label, a function of no argument)."""
    k = rng.randrange(19)
    if k == 0:
        key, value = pick(rng, KEYS), pick(rng, ANY)
        return f"Scenario.set({r(key, 40)}, {r(value, 40)})", lambda: NANO.set(key, value)
    if k == 1:
        d = {pick(rng, KEYS): pick(rng, ANY) for _ in range(rng.randrange(3))}
        arg = d if rng.random() < 0.8 else pick(rng, ANY)
        return f"Scenario.set_many({r(arg, 60)})", lambda: NANO.set_many(arg)
    if k == 2:
        name = pick(rng, ["nano", "classical", "", "NANO", "x", None, 1, "nano\n"])
        return f"Scenario.preset({r(name)})", lambda: tt.Scenario.preset(name)
    if k == 3:
        base = NANO.to_toml()
        mutations = [
            lambda t: t.replace("=", "==", 1),
            lambda t: t.replace("1", "nan", 1),
            lambda t: t + "\n[solver]\nsamples = 10000000000\n",
            lambda t: t + "\nunknown = 1\n",
            lambda t: "a = " + "[" * 5000 + "]" * 5000,
            lambda t: t[: len(t) // 2],
            lambda t: t.replace("[solver]", "[solver]\nsamples = -1", 1),
            lambda t: 'preset = "nano"\n[thermal]\nseed = 18446744073709551616\n',
            lambda t: None,
            lambda t: b"preset = 1",
        ]
        text = pick(rng, mutations)(base)
        return f"Scenario.from_toml(<{r(text, 40)}>)", lambda: tt.Scenario.from_toml(text)
    if k == 4:
        path = pick(rng, ["", "/nonexistent/x.toml", "/dev/null", "/", ".", "a\x00b", None, 1,
                          b"/dev/null", ["x"]])
        return f"Scenario.from_file({r(path)})", lambda: tt.Scenario.from_file(path)
    if k == 5:
        key = pick(rng, KEYS + ["top.radius", "force.0", "force.0.hx.y"])
        return f"Scenario.get({r(key)})", lambda: NANO.get(key)
    if k == 6:
        sc, pose = pick(rng, SCENARIOS), pick(rng, SWITCHES)
        return f"run({r(sc, 30)}, pose={r(pose)})", lambda: tt.run(sc, pose=pose)
    if k == 7:
        sc = pick(rng, SCENARIOS)
        return f"Simulation({r(sc, 30)})", lambda: tt.Simulation(sc)
    if k == 8:
        t = pick(rng, FLOATS + [1e-11, 5e-11, 1e-10, 2e-10])
        return f"Simulation.integrate_to({r(t)})", lambda: tt.Simulation(NANO).integrate_to(t)
    if k == 9:
        s = pick(rng, [SNAP, OTHER_SNAP, None, NANO, 1, TRAJ])
        return f"Simulation.restore({r(s, 30)})", lambda: tt.Simulation(NANO).restore(s)
    if k == 10:
        vary = {pick(rng, KEYS[:12] + ["", "x.y", "a=b", 1]): grid(rng) for _ in range(1 + rng.randrange(2))}
        if rng.random() < 0.1:
            vary = pick(rng, ANY)
        kw = kwargs(rng, [("threads", COUNTS)])
        return f"sweep(vary={r(vary, 60)}, {r(kw, 40)})", lambda: tt.sweep(NANO, vary, **kw)
    if k == 11:
        runs = pick(rng, COUNTS[1:])
        kw = kwargs(rng, [("threads", COUNTS), ("first_passage", CONDITIONS),
                          ("step_check", SWITCHES)])
        sc = ENS if rng.random() < 0.9 else pick(rng, SCENARIOS)
        return f"ensemble({r(sc, 20)}, {r(runs)}, {r(kw, 60)})", lambda: tt.ensemble(sc, runs, **kw)
    if k in (12, 13):
        target = pick(rng, CONDITIONS[1:])
        method = pick(rng, ["direct", "direct", "ams", "exact", "x", None, 1])
        kw = kwargs(rng, [("reset", CONDITIONS), ("replicas", COUNTS), ("horizon", FLOATS),
                          ("max_steps", COUNTS), ("threads", COUNTS),
                          ("step_check", SWITCHES)])
        if method == "ams":
            kw.update(kwargs(rng, [
                ("coordinate", ["theta", "-theta", "|theta-1|", "tilt_energy", "", "x", None, 1]),
                ("particles", COUNTS), ("kill", COUNTS), ("max_trajectories", COUNTS),
                ("crossings", COUNTS), ("direct_steps", COUNTS), ("pilot_steps", COUNTS),
                ("basin", FLOATS), ("interface", FLOATS),
            ]))
        # A good rare-event call stays cheap: at most 100 steps a path, and
        # a splitting of few particles and paths.
        if kw.get("max_steps") is None:
            kw["max_steps"] = 100
        if method == "ams":
            if kw.get("particles") is None:
                kw["particles"] = 5
            if kw.get("max_trajectories") is None:
                kw["max_trajectories"] = 50
        return (f"rare({r(target)}, method={r(method)}, {r(kw, 80)})",
                lambda: tt.rare(ENS, target, method=method, **kw))
    if k == 14:
        name = pick(rng, ["theta", "t", "", "x", None, 1, "theta\n", slice(1), b"t"])
        return f"Trajectory[{r(name)}]", lambda: TRAJ[name]
    if k == 15:
        name = pick(rng, ["theta", "nope", "__class__", "_x"])
        return f"Trajectory.{name}", lambda: getattr(TRAJ, name)
    if k == 16:
        name = pick(rng, ["theta", "x", None, 1, []])
        return f"{r(name)} in Trajectory", lambda: name in TRAJ
    if k == 17:
        other = pick(rng, ANY + [NANO, SNAP, TRAJ])
        return f"Scenario == {r(other, 30)}", lambda: NANO == other
    return "repr()", lambda: [repr(x) for x in (NANO, ENS, TRAJ, tt.Simulation(NANO), SNAP)]


def main():
    seed, n = int(sys.argv[1]), int(sys.argv[2])
    verbose = "-v" in sys.argv[3:]
    rng = random.Random(seed)
    bad = 0
    for i in range(n):
        label, call = case(rng)
        if verbose:
            print(f"case {i}: {label}", file=sys.stderr, flush=True)
        start = time.perf_counter()
        try:
            call()
            took = time.perf_counter() - start
            if took > 1.0:
                print(f"SLOW {took:.1f} s case {i}: {label}", file=sys.stderr, flush=True)
            continue
        except (ValueError, TypeError) as e:
            msg = str(e)
            ok = bool(msg) and "\n" not in msg and "\r" not in msg
            kind = type(e).__name__
        except KeyError as e:
            ok = label.startswith("Trajectory[")
            msg, kind = str(e), "KeyError"
        except AttributeError as e:
            ok = label.startswith("Trajectory.")
            msg, kind = str(e), "AttributeError"
        except BaseException as e:  # noqa: BLE001 - the point of the test
            ok, msg, kind = False, str(e), type(e).__name__
        if not ok:
            bad += 1
            print("BAD " + json.dumps({"case": i, "call": label, "raised": kind, "message": msg[:300]}),
                  flush=True)
    print(f"cases {n} bad {bad}", flush=True)


if __name__ == "__main__":
    main()
