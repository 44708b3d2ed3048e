"""Tests of the Python package `tippetop` (crates/tippetop-py).

Run from a virtual environment with the package installed:
    python3 -m venv .venv && .venv/bin/pip install ./crates/tippetop-py pytest
    .venv/bin/python -m pytest crates/tippetop-py/tests

The comparison with the CLI uses the `tippetop` binary of the workspace
(TIPPETOP_BIN, else target/release/tippetop or target/debug/tippetop, as
`cargo build` or `cargo test --workspace` leave it); it is skipped if there
is none.
"""

import csv
import json
import subprocess
import threading
import time

import numpy as np
import pytest

import tippetop as tt
from _helpers import bits, cli_binary, gil_counts


def assert_same_arrays(a, b):
    assert a.columns == b.columns
    assert len(a) == len(b)
    for c in a.columns:
        assert np.array_equal(bits(a[c]), bits(b[c])), c


def summary_without_wall(tr):
    s = dict(tr.summary)
    s.pop("wall_seconds")
    return s


@pytest.fixture(scope="module")
def nano():
    return tt.Scenario.preset("nano")


@pytest.fixture(scope="module")
def nano_run(nano):
    return tt.run(nano)


def test_arrays_are_float64_one_per_column(nano, nano_run):
    tr = nano_run
    n = nano.get("solver.samples")
    assert n == 1001
    assert tr.columns == list(tt.COLUMNS)
    assert tr.columns[:5] == ["t", "theta", "theta_dot", "Omega", "omega"]
    assert len(tr) == n
    for c in tr.columns:
        a = tr[c]
        assert isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == (n,), c
        assert getattr(tr, c) is a or np.array_equal(bits(getattr(tr, c)), bits(a))
    assert tr.t[0] == 0.0 and tr.t[-1] == nano.get("solver.t_end")
    assert tr.theta[0] == 0.1
    assert tr.error is None
    assert tr.summary["status"] == "ok" and tr.summary["failure"] is None
    assert tr.summary["theta_final"] == tr.theta[-1]
    with pytest.raises(KeyError):
        tr["nope"]
    with pytest.raises(AttributeError):
        tr.nope


def test_run_is_deterministic(nano, nano_run):
    again = tt.run(nano)
    assert_same_arrays(nano_run, again)
    assert summary_without_wall(nano_run) == summary_without_wall(again)


def test_matches_the_cli_bit_for_bit(nano_run, tmp_path):
    exe = cli_binary()
    if exe is None:
        pytest.skip("no tippetop binary (cargo build first, or set TIPPETOP_BIN)")
    out = tmp_path / "out"
    subprocess.run(
        [str(exe), "run", "--preset", "nano", "--no-plot", "--out", str(out)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    with open(out / "trajectory.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == nano_run.columns
    for j, c in enumerate(rows[0]):
        col = np.array([float(r[j]) for r in rows[1:]])
        assert np.array_equal(bits(col), bits(nano_run[c])), c
    cli = json.loads((out / "summary.json").read_text())
    mine = nano_run.summary
    assert set(cli) == set(mine)
    for k in cli:
        if k != "wall_seconds":
            assert cli[k] == mine[k], k
    assert cli["theta_final"] == mine["theta_final"] == nano_run.theta[-1]


POSE = ["x", "y", "z", "qw", "qx", "qy", "qz", "xp", "yp"]


def test_run_without_the_pose_is_the_run_less_its_columns(nano, nano_run):
    """pose=False: the columns up to `rolling`, the same bits, the same
    summary (the pose is outside the error norm and read by no other
    rate, so no step can change)."""
    lean = tt.run(nano, pose=False)
    assert lean.columns == [c for c in tt.COLUMNS if c not in POSE]
    assert lean.columns == list(tt.COLUMNS[: len(tt.COLUMNS) - len(POSE)])
    assert len(lean) == len(nano_run)
    for c in lean.columns:
        assert np.array_equal(bits(lean[c]), bits(nano_run[c])), c
    for c in POSE:
        assert c not in lean
        with pytest.raises(KeyError):
            lean[c]
    assert summary_without_wall(lean) == summary_without_wall(nano_run)
    assert tt.run(nano, pose=True).columns == list(tt.COLUMNS)


def test_simulation_in_pieces_equals_run(nano, nano_run):
    sim = tt.Simulation(nano)
    t_end = nano.get("solver.t_end")
    for t in np.linspace(0.0, t_end, 7)[1:]:
        sim.integrate_to(float(t))
        state = sim.state
        assert set(state) == set(tt.COLUMNS)
        assert state["t"] == sim.time
    assert sim.is_finished and sim.error is None
    tr = sim.into_trajectory()
    assert_same_arrays(tr, nano_run)
    assert summary_without_wall(tr) == summary_without_wall(nano_run)


def test_snapshot_restore_continues_as_uninterrupted(nano, nano_run):
    t_end = nano.get("solver.t_end")
    sim = tt.Simulation(nano)
    sim.integrate_to(0.3 * t_end)
    saved = sim.snapshot()
    theta_mid = sim.state["theta"]
    sim.integrate_to(0.8 * t_end)
    sim.restore(saved)
    assert sim.state["theta"] == theta_mid
    # The run so far is a prefix of the whole run.
    part = sim.into_trajectory()
    assert 0 < len(part) < len(nano_run)
    assert np.array_equal(bits(part.theta), bits(nano_run.theta[: len(part)]))
    sim.integrate_to(t_end)
    assert_same_arrays(sim.into_trajectory(), nano_run)
    # A restored copy in another simulation continues the same way.
    other = tt.Simulation(nano)
    other.restore(saved)
    other.integrate_to(t_end)
    assert_same_arrays(other.into_trajectory(), nano_run)


def test_bad_input_raises_value_error_naming_the_key(nano):
    with pytest.raises(ValueError) as e:
        nano.set("top.radius", -1)
    assert str(e.value) == "top.radius: -1 is not allowed (a finite number > 0)"
    with pytest.raises(ValueError, match=r"^top\.radiu: unknown key"):
        nano.set("top.radiu", 1.0)
    with pytest.raises(ValueError, match=r"^surface\.friction: "):
        nano.set("surface.friction", float("nan"))
    with pytest.raises(ValueError, match=r"^preset: unknown preset \"big\""):
        tt.Scenario.preset("big")
    with pytest.raises(ValueError, match=r"^/no/such/file\.toml: cannot read it"):
        tt.Scenario.from_file("/no/such/file.toml")
    with pytest.raises(ValueError, match=r"^top\.radius: "):
        tt.Scenario.from_toml(nano.to_toml().replace("radius = 3.55e-10", "radius = -2.0"))
    with pytest.raises(ValueError, match=r"^t: "):
        tt.Simulation(nano).integrate_to(1.0)
    with pytest.raises(TypeError):
        nano.set("surface.friction", object())
    # All of them are Exceptions (never a BaseException that `except
    # Exception` misses).
    assert issubclass(ValueError, Exception)


def test_set_is_exact_and_returns_a_new_scenario(nano):
    x = 0.1 + 0.2  # 0.30000000000000004
    sc = nano.set("surface.friction", x)
    assert sc.get("surface.friction") == x
    assert nano.get("surface.friction") == 0.13
    assert sc.set("surface.friction", np.float64(x)) == sc
    assert sc != nano
    tiny = 1.196e-24 * (1 + 2**-52)
    assert nano.set("top.mass", tiny).get("top.mass") == tiny
    assert nano.set("solver.samples", np.int64(11)).get("solver.samples") == 11
    assert nano.set("solver.model", "rigid").get("solver.model") == "rigid"
    assert len(tt.run(nano.set("solver.samples", 11))) == 11
    # to_toml round-trips; the same as the CLI's --set.
    assert tt.Scenario.from_toml(sc.to_toml()) == sc
    assert "friction = 0.30000000000000004" in sc.to_toml()


def test_set_many_sets_keys_that_depend_on_each_other(nano):
    with pytest.raises(ValueError, match=r"^surface\.friction_eps: "):
        nano.set("surface.friction_eps", 1e-2)
    with pytest.raises(ValueError, match=r"^surface\.friction_eps: missing"):
        nano.set("surface.friction_law", "regularized")
    sc = nano.set_many({"surface.friction_law": "regularized", "surface.friction_eps": 1e-2})
    assert sc.get("surface.friction_law") == "regularized"
    assert sc.get("surface.friction_eps") == 1e-2
    text = nano.to_toml().replace('friction_law = "coulomb"', 'friction_law = "regularized"\nfriction_eps = 0.01')
    assert tt.Scenario.from_toml(text) == sc
    # In order, as repeated --set: the last wins; the result is one new scenario.
    assert nano.set_many({"surface.friction": 0.2}) == nano.set("surface.friction", 0.2)
    assert nano.set_many({}) == nano
    with pytest.raises(ValueError, match=r"^top\.radiu: unknown key"):
        nano.set_many({"surface.friction": 0.2, "top.radiu": 1.0})


def test_scenario_from_file(tmp_path, nano):
    p = tmp_path / "s.toml"
    p.write_text('preset = "nano"\n[surface]\nfriction = 0.2\n')
    sc = tt.Scenario.from_file(p)
    assert sc == nano.set("surface.friction", 0.2)
    assert tt.Scenario.from_file(str(p)) == sc


def test_partial_run_has_error_and_samples_up_to_it(nano):
    sc = nano.set("solver.max_steps", 50)
    tr = tt.run(sc)
    err = tr.error
    assert err["kind"] == "step_limit"
    assert 0 < err["time"] < sc.get("solver.t_end")
    assert err["message"].startswith("at t = ")
    assert 0 < len(tr) < 1001 and tr.t[-1] <= err["time"]
    assert tr.summary["status"] == err["message"]
    assert tr.summary["failure"] == "step_limit"
    sim = tt.Simulation(sc)
    sim.integrate_to(sc.get("solver.t_end"))
    assert sim.is_finished and sim.error == err


def test_a_runaway_is_announced_before_the_failure(nano):
    """The nano preset's long run runs away (its spin grows ~linearly to
    ~2e9 rad/s, its step falls) and fails; cut at 1.5 M steps (the same run
    until then), tt.run warns (RuntimeWarning, once per decade, decided by
    the state as the CLI's hardening_cli::a_runaway_is_announced_before_the_failure)
    before it returns the failure."""
    sc = nano.set("solver.t_end", 1.0).set("solver.max_steps", 1_500_000)
    with pytest.warns(RuntimeWarning, match="the state is running away") as rec:
        tr = tt.run(sc)
    assert tr.error is not None and tr.error["kind"] == "step_limit"
    msgs = [str(w.message) for w in rec if "running away" in str(w.message)]
    assert msgs[0].startswith("warning: the state is running away: at t = ")
    assert "has grown 10x since t = " in msgs[0]
    # Each warning's time precedes the failure's.
    assert len(msgs) <= 4


def test_the_watch_never_changes_a_step(nano, recwarn):
    """tt.run pauses every 16 384 steps to watch the state; a 1 ms nano run
    (~88 000 steps, five pauses) is bit for bit Simulation.integrate_to's
    run, which never pauses, and a run that stays gives no warning."""
    sc = nano.set("solver.t_end", 1e-3)
    tr = tt.run(sc)
    sim = tt.Simulation(sc)
    sim.integrate_to(1e-3)
    other = sim.into_trajectory()
    assert tr.summary["steps"] > 5 * 16384
    assert_same_arrays(tr, other)
    assert summary_without_wall(tr) == summary_without_wall(other)
    assert not [w for w in recwarn if "running away" in str(w.message)]


def test_run_releases_the_gil(nano):
    """A Python thread counts while tt.run is in Rust. With a switch interval
    far longer than the test, the main thread gives the GIL up only where it
    releases it itself: a pure-Python loop lets the counter stand still, a
    run lets it advance."""
    sc = nano.set("solver.t_end", 3e-4)
    control, during, tr = gil_counts(lambda: tt.run(sc))
    assert tr.error is None
    assert control == 0, "the control loop let the thread run: the test cannot tell"
    assert during > 0, "the counter stood still while tt.run ran: the GIL was held"


def test_simulation_used_from_two_threads_never_deadlocks(nano):
    """While one thread is in integrate_to (GIL released, the simulation
    locked), another that touches the simulation gets RuntimeError at once
    (never waits for the lock while holding the GIL)."""
    sc = nano.set("solver.t_end", 1e-3)
    sim = tt.Simulation(sc)
    th = threading.Thread(target=sim.integrate_to, args=(1e-3,))
    th.start()
    busy = 0
    while th.is_alive():
        try:
            sim.time
        except RuntimeError as e:
            assert "busy" in str(e)
            busy += 1
    th.join(timeout=60)
    assert not th.is_alive()
    assert sim.is_finished and sim.error is None


def test_to_pandas(nano_run):
    pd = pytest.importorskip("pandas")
    df = nano_run.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == nano_run.columns
    assert np.array_equal(bits(df["omega"].to_numpy()), bits(nano_run.omega))


_MEMORY_PROBE = """
import resource, sys, tippetop as tt
tt.run(tt.Scenario.preset("classical").set("solver.t_end", 0.01))
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
sc = tt.Scenario.preset("classical").set("solver.t_end", 1.0).set("solver.samples", 1000000)
t = tt.run(sc)
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
assert len(t) == 1000000
print((after - before) * 1024)
"""


def test_run_keeps_one_copy_of_the_rows_besides_its_arrays():
    """tt.run of 1e6 samples grows the peak by the run's rows (224 bytes
    each in Rust, docs/guide.md#limits) plus the 26 numpy columns (208
    bytes per row): 432 MB. A whole extra copy of the rows while the
    columns are gathered (33e32ba: +202 bytes per row, measured 2.06 ->
    3.07 GB at 5e6 samples) would make it ~634 MB. Bound: 432 MB + 15 %.
    In a fresh process, so that the peak is this run's (Linux maxrss in
    KiB)."""
    import sys

    out = subprocess.run(
        [sys.executable, "-c", _MEMORY_PROBE], capture_output=True, text=True, check=True
    )
    grown = int(out.stdout.strip())
    expected = 1_000_000 * (224 + 26 * 8)
    assert grown <= 1.15 * expected, f"peak grew by {grown / 1e6:.0f} MB, expected ≤ {1.15 * expected / 1e6:.0f}"
