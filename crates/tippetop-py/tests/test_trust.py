"""Issue 26 ("Trust under attack") in Python: snapshots belong to their
scenario, the long calls stop on Ctrl-C within a second, arguments of the
wrong type or out of range raise TypeError / ValueError, and the limits
(input files, sweep size) are refused up front."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

import tippetop as tt


# --- snapshots carry their scenario -------------------------------------------


def test_restore_refuses_a_snapshot_of_another_scenario():
    """A snapshot of another scenario used to be accepted, after which
    summary['scenario'] named the wrong run; now ValueError, and the
    simulation is left as it was."""
    nano = tt.Scenario.preset("nano").set("solver.t_end", 2e-6)
    other = nano.set("surface.friction", 0.2)
    a, b = tt.Simulation(nano), tt.Simulation(other)
    a.integrate_to(1e-6)
    b.integrate_to(1.5e-6)
    before, t_before = a.state, a.time
    with pytest.raises(ValueError, match="another scenario"):
        a.restore(b.snapshot())
    assert a.state == before and a.time == t_before
    a.integrate_to(2e-6)
    tr = a.into_trajectory()
    assert tr.summary["scenario"] == nano.to_toml()
    # A snapshot of the same scenario, from another Simulation, is fine.
    c = tt.Simulation(nano)
    c.integrate_to(0.5e-6)
    a.restore(c.snapshot())
    assert a.time == c.time


# --- Ctrl-C --------------------------------------------------------------------

# A run of about a minute without an interrupt: the classical top spun at
# 1e7 rad/s needs millions of steps.
LONG = textwrap.dedent(
    """
    import sys, time
    import tippetop as tt
    sc = (tt.Scenario.preset("classical").set("initial.spin", 1e7)
          .set("solver.t_end", 10.0))
    what = sys.argv[1]
    print("started", flush=True)
    try:
        if what == "run":
            tt.run(sc)
        else:
            sim = tt.Simulation(sc)
            sim.integrate_to(10.0)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        if what != "run":
            # The simulation stands at a step and can go on.
            t = sim.time
            assert 0.0 < t < 10.0, t
            sim.integrate_to(min(10.0, t * 1.000001))
            print("continued", flush=True)
        sys.exit(0)
    print("finished", flush=True)
    """
)


@pytest.mark.parametrize("what", ["run", "integrate_to"])
def test_ctrl_c_stops_a_long_run_within_a_second(what):
    """tt.run and Simulation.integrate_to ignored Ctrl-C for 20 s or more:
    SIGINT to a process in the middle of one now raises KeyboardInterrupt
    within a second."""
    p = subprocess.Popen(
        [sys.executable, "-c", LONG, what],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert p.stdout.readline().strip() == "started"
        time.sleep(1.0)  # well inside the run
        assert p.poll() is None, "the run ended before the signal"
        sent = time.perf_counter()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=30)
        took = time.perf_counter() - sent
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert "interrupted" in out, (out, err)
    if what == "integrate_to":
        assert "continued" in out, (out, err)
    assert p.returncode == 0, (out, err)
    assert took < 1.0, f"{what}: {took:.2f} s from SIGINT to exit"


# --- argument types and ranges --------------------------------------------------


def test_set_many_wants_a_mapping():
    """set_many(list) and set_many(None) raised AttributeError: TypeError."""
    sc = tt.Scenario.preset("classical")
    for bad in ([("surface.friction", 0.2)], None, 3, "surface.friction=0.2"):
        with pytest.raises(TypeError, match="set_many"):
            sc.set_many(bad)
    with pytest.raises(TypeError, match="set_many"):
        sc.set_many({1: 0.2})
    assert sc.set_many({"surface.friction": 0.2}).get("surface.friction") == 0.2


ENSEMBLE = tt.Scenario.from_toml(
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


def test_ensemble_runs_and_threads_out_of_range_are_value_errors():
    """ensemble(sc, 2**64) raised OverflowError: ValueError naming runs;
    a value of another type is TypeError."""
    for runs in (2**64, -(2**70), -1, 0, 1_000_001):
        with pytest.raises(ValueError, match="runs"):
            tt.ensemble(ENSEMBLE, runs)
    for runs in ("3", 2.0, None, True):
        with pytest.raises(TypeError, match="runs"):
            tt.ensemble(ENSEMBLE, runs)
    for threads in (2**64, 0, -1, 1025):
        with pytest.raises(ValueError, match="threads"):
            tt.ensemble(ENSEMBLE, 2, threads=threads)
    with pytest.raises(TypeError, match="threads"):
        tt.ensemble(ENSEMBLE, 2, threads="2")
    vary = {"top.offset": (3e-4, 6e-3, 2)}
    with pytest.raises(ValueError, match="threads"):
        tt.sweep(tt.Scenario.preset("classical"), vary, threads=2**64)
    with pytest.raises(TypeError, match="threads"):
        tt.sweep(tt.Scenario.preset("classical"), vary, threads=1.5)
    out = tt.ensemble(ENSEMBLE, 2, threads=1)
    assert list(out["run"]) == [0.0, 1.0]


def test_sweep_size_is_refused_up_front():
    """A sweep whose result would not fit the memory bound (more than
    1 000 000 cases) is refused before anything runs."""
    sc = tt.Scenario.preset("classical")
    start = time.perf_counter()
    with pytest.raises(ValueError, match="1000000"):
        tt.sweep(sc, {"top.offset": (3e-4, 6e-3, 1001), "surface.friction": (0.1, 0.2, 1000)})
    assert time.perf_counter() - start < 5.0


def test_scenario_files_over_16_mib_are_refused(tmp_path):
    """Scenario.from_file reads at most 16 MiB + 1 byte (so /dev/zero is
    refused at once) and names the file."""
    big = tmp_path / "big.toml"
    big.write_bytes(b'preset = "classical"\n#' + b"x" * (16 << 20))
    with pytest.raises(ValueError, match="16 MiB"):
        tt.Scenario.from_file(big)
    if os.path.exists("/dev/zero"):
        with pytest.raises(ValueError, match="/dev/zero"):
            tt.Scenario.from_file("/dev/zero")
