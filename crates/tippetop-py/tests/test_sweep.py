"""tt.sweep: the CLI's `tippetop sweep` from Python (dict of numpy arrays,
one row per case), checked against the CLI's own sweep.csv bit for bit."""

import _thread
import csv
import json
import subprocess
import threading
import time

import numpy as np
import pytest

import tippetop as tt
from _helpers import bits, cli_binary, gil_counts

FIELDS = [
    "theta_final",
    "theta_max",
    "omega_final",
    "Omega_final",
    "first_time_theta_above_half_pi",
    "contact_lost_at",
    "negative_normal_fraction",
    "rolling_fraction",
    "J_max_rel_drift",
    "energy_final",
    "steps",
    "rhs_evaluations",
]

# Cheap classical runs (0.5 s, 51 samples); max_steps = 150 makes some cases
# fail part-way, offsets past the radius (15 mm) make some invalid: the
# sweep has rows of all three kinds.
SETS = [("solver.t_end", 0.5), ("solver.samples", 51), ("solver.max_steps", 150)]


@pytest.fixture(scope="module")
def base():
    sc = tt.Scenario.preset("classical")
    for k, v in SETS:
        sc = sc.set(k, v)
    return sc


def cli_sweep(tmp_path, args):
    """Run the CLI's sweep; its sweep.csv as (header, columns): numbers
    parsed with float() from the exact text (NaN for an empty field), the
    status column as str."""
    exe = cli_binary()
    if exe is None:
        pytest.skip("no tippetop binary (cargo build first, or set TIPPETOP_BIN)")
    out = tmp_path / "cli"
    subprocess.run(
        [str(exe), "sweep", *args, "--quiet", "--out", str(out)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    with open(out / "sweep.csv", newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    cols = {}
    for j, name in enumerate(header):
        if name == "status":
            cols[name] = [r[j] for r in body]
        else:
            cols[name] = np.array([float(r[j]) if r[j] else np.nan for r in body])
    return header, cols


def assert_same_sweep(a, b):
    assert list(a) == list(b)
    for k in a:
        if k == "status":
            assert list(a[k]) == list(b[k])
        else:
            assert np.array_equal(bits(a[k]), bits(b[k])), k


def cli_args(extra_sets=()):
    args = ["--preset", "classical"]
    for k, v in list(SETS) + list(extra_sets):
        args += ["--set", f"{k}={v}"]
    return args


def test_sweep_equals_the_cli_sweep_csv_bit_for_bit(base, tmp_path):
    vary = {"top.offset": (3e-4, 0.02, 6), "surface.friction": (0.1, 0.3, 2)}
    sw = tt.sweep(base, vary=vary, threads=2)
    header, cli = cli_sweep(
        tmp_path,
        cli_args()
        + ["--vary", "top.offset=3e-4:0.02:6", "--vary", "surface.friction=0.1:0.3:2"]
        + ["--threads", "2"],
    )
    assert list(sw) == header == ["top.offset", "surface.friction"] + FIELDS + ["status"]
    assert len(sw["status"]) == 12
    for k in header:
        if k == "status":
            assert list(sw[k]) == cli[k]
        else:
            a = sw[k]
            assert isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == (12,), k
            assert np.array_equal(bits(a), bits(cli[k])), k
    status = list(sw["status"])
    # The three kinds of row are there: ok, failed part-way (summary up to
    # the failure), invalid (no summary: NaN).
    assert "ok" in status
    failed = [i for i, s in enumerate(status) if "step limit" in s or "max_steps" in s]
    assert failed and all(np.isfinite(sw["theta_final"][i]) for i in failed)
    invalid = [i for i, s in enumerate(status) if s.startswith("top.offset: ")]
    assert invalid and all(np.isnan(sw["theta_final"][i]) for i in invalid)
    # The grid: the first key varies slowest.
    assert list(sw["surface.friction"][:4]) == [0.1, 0.3, 0.1, 0.3]
    assert sw["top.offset"][0] == sw["top.offset"][1] == 3e-4


def test_log_grid_and_a_file_scenario_equal_the_cli(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(
        'preset = "classical"\n[solver]\nt_end = 0.3\nsamples = 31\n'
        "[surface]\nfriction = 0.2\n"
    )
    sc = tt.Scenario.from_file(p).set("top.mass", 0.02)
    sw = tt.sweep(sc, vary={"top.inertia_axial": (1e-6, 2e-6, 3, "log")}, threads=1)
    header, cli = cli_sweep(
        tmp_path,
        [str(p), "--set", "top.mass=0.02", "--vary", "top.inertia_axial=1e-6:2e-6:3:log"],
    )
    assert list(sw) == header
    assert_same_sweep(sw, cli)
    assert list(sw["status"]) == ["ok"] * 3


def test_threads_do_not_change_the_result(base):
    vary = {"top.offset": (3e-4, 0.012, 5), "surface.friction": [0.3, 0.1]}
    one = tt.sweep(base, vary=vary, threads=1)
    two = tt.sweep(base, vary=vary, threads=2)
    default = tt.sweep(base, vary=vary)
    assert_same_sweep(one, two)
    assert_same_sweep(one, default)


def test_values_as_given_equal_the_grid(base):
    grid = tt.sweep(base, vary={"top.offset": (3e-4, 6e-3, 4)}, threads=2)
    values = grid["top.offset"]
    assert values[0] == 3e-4 and values[-1] == 6e-3
    as_array = tt.sweep(base, vary={"top.offset": values}, threads=2)
    as_list = tt.sweep(base, vary={"top.offset": [float(v) for v in values]}, threads=2)
    assert_same_sweep(as_array, grid)
    assert_same_sweep(as_list, grid)
    # Taken as given: any order, repeats, exact floats.
    x = 0.1 + 0.2
    sw = tt.sweep(base, vary={"surface.friction": [x, 0.1, x]}, threads=2)
    assert list(sw["surface.friction"]) == [x, 0.1, x]
    assert sw["theta_final"][0] == sw["theta_final"][2]
    # A case of the sweep equals its own run.
    tr = tt.run(base.set("surface.friction", x))
    assert sw["theta_final"][0] == tr.summary["theta_final"]
    assert sw["steps"][0] == tr.summary["steps"]


@pytest.mark.parametrize(
    "vary, threads, message",
    [
        ({"top.ofset": (1e-3, 2e-3, 3)}, None, r"^top\.ofset: unknown key"),
        ({"top.offset": (1e-3, 2e-3, 0)}, None, r"^top\.offset: N = 0 in --vary \(N >= 1\)$"),
        ({"top.offset": (1e-3, 2e-3, 2.5)}, None, r"^top\.offset: N \"2\.5\" is not a whole"),
        ({"top.offset": (1e-3, 2e-3)}, None, r"^top\.offset: .* is not FROM:TO:N\[:log\]"),
        ({"top.offset": (1e-3, 2e-3, 3, "lin")}, None, r"^top\.offset: unknown spacing \"lin\""),
        ({"top.offset": (0.0, 2e-3, 3, "log")}, None, r"^top\.offset: log spacing"),
        ({"top.offset": (float("nan"), 2e-3, 3)}, None, r"^top\.offset: FROM = NaN"),
        ({"top.offset": (0.1, 0.2, 3)}, None, r"^top\.offset: 0\.1 is out of range"),
        ({"top.offset": []}, None, r"^top\.offset: no values given"),
        ({"top.offset": [1e-3, float("inf")]}, None, r"^top\.offset: value 1 = inf"),
        ({"top.offset": [1e-3, "x"]}, None, r"^top\.offset: value 1 \('x'\) is not a number"),
        ({"top.offset": 1e-3}, None, r"^top\.offset: a value of type float is not a grid"),
        ({"top.offset": "1e-3:2e-3:3"}, None, r"^top\.offset: .* is not a grid"),
        ({"surface.friction": (-1.0, -0.5, 2)}, None, r"^surface\.friction: "),
        ({"top.offset": ("1e-3:2e-3:3",)}, None, r"^top\.offset: '1e-3:2e-3:3' in \(lo, hi, n\)"),
        ({"top.offset=1": (1e-3, 2e-3, 3)}, None, r"^top\.offset=1: not a scenario key"),
        ({"top.offset=1": [1e-3]}, None, r"^top\.offset=1: not a scenario key"),
        ({" ": [1e-3]}, None, r"^ : not a scenario key"),
        ({}, None, r"^vary: no keys given"),
        ({"top.offset": (1e-3, 2e-3, 3)}, 0, r"^--threads: 0 threads \(1 to 1024"),
        ({"top.offset": (1e-3, 2e-3, 3)}, -2, r"^--threads: -2 threads \(1 to 1024"),
        ({"top.offset": (1e-3, 2e-3, 3)}, 5000, r"^--threads: 5000 threads"),
    ],
)
def test_bad_input_raises_value_error_naming_the_key(base, vary, threads, message):
    with pytest.raises(ValueError, match=message) as e:
        tt.sweep(base, vary=vary, threads=threads)
    assert "\n" not in str(e.value)


def test_bad_input_has_the_cli_line(base, tmp_path):
    """The message is the CLI's stderr line without `error: `."""
    exe = cli_binary()
    if exe is None:
        pytest.skip("no tippetop binary (cargo build first, or set TIPPETOP_BIN)")
    for spec, vary in [
        ("top.ofset=1e-3:2e-3:3", {"top.ofset": (1e-3, 2e-3, 3)}),
        ("top.offset=1e-3:2e-3:3:lin", {"top.offset": (1e-3, 2e-3, 3, "lin")}),
        ("top.offset=0.1:0.2:3", {"top.offset": (0.1, 0.2, 3)}),
    ]:
        p = subprocess.run(
            [str(exe), "sweep", *cli_args(), "--vary", spec, "--quiet"]
            + ["--out", str(tmp_path / "bad")],
            capture_output=True,
            text=True,
        )
        assert p.returncode == 2
        with pytest.raises(ValueError) as e:
            tt.sweep(base, vary=vary)
        assert "error: " + str(e.value) == p.stderr.strip()


def test_sweep_releases_the_gil(base):
    """As test_basic's test of tt.run: a Python thread's counter advances
    while tt.sweep runs, with a switch interval far longer than the test."""
    vary = {"top.offset": (3e-4, 6e-3, 4)}
    control, during, sw = gil_counts(lambda: tt.sweep(base, vary=vary, threads=1))
    assert len(sw["status"]) == 4
    assert control == 0, "the control loop let the thread run: the test cannot tell"
    assert during > 0, "the counter stood still while tt.sweep ran: the GIL was held"


def test_ctrl_c_stops_a_sweep(base):
    """KeyboardInterrupt (as from Ctrl-C) stops a running sweep."""
    sc = base.set("solver.max_steps", 100_000).set("solver.t_end", 20.0)
    vary = {"top.offset": (3e-4, 6e-3, 400)}
    timer = threading.Timer(0.2, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            tt.sweep(sc, vary=vary, threads=1)
    finally:
        timer.cancel()
    stopped = time.perf_counter() - start
    # Finished cases give the time the whole sweep would have taken.
    t0 = time.perf_counter()
    tt.sweep(sc, vary={"top.offset": (3e-4, 6e-3, 20)}, threads=1)
    whole = (time.perf_counter() - t0) * 20
    assert stopped < whole / 2, (stopped, whole)


# --- ensembles (tt.ensemble) ------------------------------------------------

ENSEMBLE_TOML = """preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
t_end = 1e-11
samples = 11
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 1
"""


def test_ensemble_equals_the_cli(tmp_path):
    """tt.ensemble's arrays are the CLI's ensemble.csv, bit for bit (floats
    parsed from their shortest round-trip text), whatever the threads, and
    its summary's step check is summary.json's; run K replays alone with
    tt.run."""
    import subprocess, csv, math
    f = tmp_path / "lang.toml"
    f.write_text(ENSEMBLE_TOML)
    sc = tt.Scenario.from_file(str(f))
    a = tt.ensemble(sc, runs=6, threads=1, first_passage="omega>1e11,omega<-1e11")
    b = tt.ensemble(sc, runs=6, threads=2, first_passage="omega>1e11,omega<-1e11")
    out = tmp_path / "e"
    subprocess.run(
        [str(cli_binary()), "ensemble", str(f), "--runs", "6", "--quiet", "--first-passage",
         "omega>1e11,omega<-1e11", "--out", str(out)],
        check=True,
    )
    rows = list(csv.reader(open(out / "ensemble.csv")))
    header, rows = rows[0], rows[1:]
    for j, name in enumerate(header):
        if name == "status":
            assert list(a["status"]) == [r[j] for r in rows]
            continue
        want = [float(r[j]) if r[j] != "" else math.nan for r in rows]
        for x, y, w in zip(a[name], b[name], want):
            assert (x == w or (math.isnan(x) and math.isnan(w))), (name, x, w)
            assert (x == y or (math.isnan(x) and math.isnan(y))), name
    assert a["summary"]["runs"] == 6
    # The step check (the CLI's default and tt.ensemble's): summary.json's
    # keys, the same figures.
    cli = json.loads((out / "summary.json").read_text())
    for key in ("dt_converged", "step_check"):
        assert a["summary"][key] == b["summary"][key] == cli[key], key
    assert "step_unchecked" not in a["summary"] and "step_unchecked" not in cli
    checks = a["summary"]["step_check"]
    assert a["summary"]["dt_converged"] is True
    assert {c["converged"] for c in checks.values()} == {True}
    theta = checks["theta_final"]
    assert theta["at_dt"]["estimate"] == a["summary"]["theta_final"]["mean"]
    assert theta["at_dt"]["dt"] == 1e-14 and theta["at_half_dt"]["dt"] == 5e-15
    assert theta["family"] == len(checks) >= 5
    # Run 2 replayed alone.
    tr = tt.run(sc.set("thermal.run", 2))
    stop = a["t_reached"][2]
    i = list(tr.t).index(stop)
    assert tr["omega"][i] == a["omega_final"][2]


def test_ensemble_step_check_false_and_one_run(tmp_path):
    """step_check=False: the statistics unchanged, the step unchecked with
    the reason (as the CLI's --no-step-check); one run has no interval to
    check, and says so as the CLI does."""
    f = tmp_path / "lang.toml"
    f.write_text(ENSEMBLE_TOML)
    sc = tt.Scenario.from_file(str(f))
    on = tt.ensemble(sc, runs=4)["summary"]
    off = tt.ensemble(sc, runs=4, step_check=False)["summary"]
    assert off["dt_converged"] is None and off["step_check"] is None
    assert off["step_unchecked"] == "step_check=False"
    assert on["dt_converged"] is not None and on["step_check"]
    for key in ("theta_final", "omega_final", "first_passage"):
        assert on[key] == off[key], key
    one = tt.ensemble(sc, runs=1)["summary"]
    out = tmp_path / "one"
    subprocess.run([str(cli_binary()), "ensemble", str(f), "--runs", "1", "--quiet", "--out",
                    str(out)], check=True)
    cli = json.loads((out / "summary.json").read_text())
    assert one["step_unchecked"] == cli["step_unchecked"] == (
        "one run: no statistic has a 95 % interval")
    assert one["dt_converged"] is None and cli["dt_converged"] is None
    # A run of 6e8 steps within a step limit of 1e9 needs 1.2e9 at dt/2:
    # refused before anything runs, naming the key and the switch.
    big = sc.set_many({"solver.t_end": 6e-6, "solver.max_steps": 1_000_000_000})
    with pytest.raises(ValueError, match="^solver.dt: .* at solver.dt/2 .*step_check=False skips"):
        tt.ensemble(big, runs=2)


def test_ensemble_bad_input():
    sc = tt.Scenario.preset("nano")
    with pytest.raises(ValueError, match="solver.method"):
        tt.ensemble(sc, runs=3)
    f = tt.Scenario.from_toml(ENSEMBLE_TOML)
    with pytest.raises(ValueError, match="--first-passage"):
        tt.ensemble(f, runs=3, first_passage="bogus>1")
    with pytest.raises(ValueError, match="--runs"):
        tt.ensemble(f, runs=-1)


def test_langevin_simulation_in_pieces_equals_run():
    """A Langevin run stepped with Simulation (pauses, a snapshot and a
    restore) gives the run's arrays bit for bit: the random stream's counter
    is the global step number."""
    sc = tt.Scenario.from_toml(ENSEMBLE_TOML)
    whole = tt.run(sc)
    sim = tt.Simulation(sc)
    sim.integrate_to(3.3e-12)
    snap = sim.snapshot()
    sim.integrate_to(8e-12)
    sim.restore(snap)
    sim.integrate_to(1e-11)
    tr = sim.into_trajectory()
    for c in tt.COLUMNS:
        assert np.array_equal(tr[c], whole[c]), c
    assert tr.summary["normal_intervals"]["intervals"] == 10
