"""tt.rare: the CLI's `tippetop rare` from Python (issue 27): the exact
one-dimensional answer against symmetry and the direct ensemble, the same
figures as the CLI's rare.json with and without the step check (issue
42), and bad input."""

import json
import math
import subprocess

import pytest

import tippetop as tt
from _helpers import cli_binary

# The eccentric nano top (a = R/2) in the Brownian mode at 300 K, a 2 kT
# well at pi/2 (width 0.3), started at its bottom (as the CLI test).
SCENARIO = """preset = "nano"
[top]
offset = 1.775e-10
[surface]
gravity = 0.0
friction = 0.0
[[well]]
theta = 1.5707963267948966
depth = 8.283e-21
width = 0.3
[initial]
theta = 1.5707963267948966
spin = 0.0
[solver]
method = "brownian"
dt = 2e-15
t_end = 1e-12
samples = 2
[thermal]
temperature = 300.0
damping_translational = 2.2e12
damping_rotational = 2.2e12
seed = 5
"""

UP, DOWN = "theta>1.75", "theta<1.3"


@pytest.fixture(scope="module")
def sc():
    return tt.Scenario.from_toml(SCENARIO)


def test_exact_is_one_half_in_a_symmetric_window(sc):
    # sin(theta), s(theta), D(theta) and the well are even about pi/2.
    r = tt.rare(
        sc,
        target="theta>1.7507963267948966",
        reset="theta<1.3907963267948966",
        method="exact",
    )
    assert r["quantity"] == "probability"
    assert r["method"] == "exact"
    assert abs(r["estimate"] - 0.5) < 1e-9
    assert r["ci95"] == [r["estimate"], r["estimate"]]
    assert r["trajectories"] == 0 and r["steps"] == 0
    assert r["exact"]["lower"] == {"theta": 1.3907963267948966, "role": "reset"}


def test_direct_covers_the_exact_value(sc):
    # One fixed-seed draw: a correct estimator's Wilson interval covers the
    # exact value 95 % of the time; 1 - p (target and reset swapped) is
    # outside it.
    r = tt.rare(sc, target=UP, reset=DOWN, method="direct", replicas=300, threads=2,
                step_check=False)
    exact = r["exact"]["watched"]
    lo, hi = r["ci95"]
    assert lo <= exact <= hi
    assert not lo <= 1 - exact <= hi
    t = r["tally"]
    assert t["target"] + t["reset"] == r["trajectories"] == r["replicas"] == 300
    assert r["estimate"] == t["target"] / 300


def test_mean_time_and_its_log(sc):
    r = tt.rare(sc, target="theta>1.75,theta<1.39", method="exact")
    assert r["quantity"] == "mean_first_passage_time" and r["unit"] == "s"
    assert math.isclose(math.log(r["estimate"]), r["ln_estimate"], rel_tol=1e-14)
    # Past f64: at 0.05 K the well is 12 000 kT deep and the window's edge
    # ~2 000 kT up: the value is None, its log finite.
    cold = sc.set("thermal.temperature", 0.05)
    r = tt.rare(cold, target="theta>1.75,theta<1.39", method="exact")
    assert r["estimate"] is None
    assert r["ln_estimate"] > 709


def run_cli(tmp_path, args, name="o"):
    """rare.json of `tippetop rare` on SCENARIO with `args`, without its
    wall_seconds (the test skips without a binary)."""
    exe = cli_binary()
    if exe is None:
        pytest.skip("no tippetop binary (cargo build first, or set TIPPETOP_BIN)")
    (tmp_path / "b.toml").write_text(SCENARIO)
    subprocess.run(
        [str(exe), "rare", str(tmp_path / "b.toml"), *args, "--quiet", "--out",
         str(tmp_path / name)],
        check=True,
    )
    cli = json.loads((tmp_path / name / "rare.json").read_text())
    cli.pop("wall_seconds")
    return cli


def without_step_check(cli):
    """rare.json of `--no-step-check` as `tt.rare(..., step_check=False)`
    says it: the same keys and figures, the reason naming Python's switch."""
    assert cli["dt_converged"] is None and cli["step_check"] is None
    assert cli["step_unchecked"] == "--no-step-check"
    return {**cli, "step_unchecked": "step_check=False"}


def test_same_figures_as_the_cli(sc, tmp_path):
    args = ["--target", UP, "--reset", DOWN, "--replicas", "40"]
    cli = run_cli(tmp_path, [*args, "--no-step-check"])
    py = tt.rare(sc, target=UP, reset=DOWN, replicas=40, step_check=False)
    py.pop("wall_seconds")
    assert py == without_step_check(cli)
    assert py["dt_converged"] is None and py["step_check"] is None


# The CLI's default (the step check at dt/2) against tt.rare's default:
# the same dict, the check's figures included. A probability by direct
# runs and by the splitting (linear scale), the splitting's mean time
# (log scale) and the exact answer (no step: unchecked, with the reason).
WITH_CHECK = {
    "direct": (["--target", UP, "--reset", DOWN, "--replicas", "40"],
               dict(target=UP, reset=DOWN, replicas=40)),
    "ams": (["--target", UP, "--reset", DOWN, "--method", "ams", "--replicas", "5",
             "--particles", "20"],
            dict(target=UP, reset=DOWN, method="ams", replicas=5, particles=20)),
    "ams_mean_time": (["--target", "theta>1.75,theta<1.39", "--method", "ams", "--replicas", "3",
                       "--particles", "10", "--pilot-steps", "2000", "--crossings", "5"],
                      dict(target="theta>1.75,theta<1.39", method="ams", replicas=3,
                           particles=10, pilot_steps=2000, crossings=5)),
    "exact": (["--target", UP, "--reset", DOWN, "--method", "exact"],
              dict(target=UP, reset=DOWN, method="exact")),
}


@pytest.mark.parametrize("case", sorted(WITH_CHECK))
def test_the_step_check_has_the_cli_figures(sc, tmp_path, case):
    args, kwargs = WITH_CHECK[case]
    cli = run_cli(tmp_path, args)
    py = tt.rare(sc, **kwargs)
    py.pop("wall_seconds")
    assert py == cli
    if case == "exact":
        assert py["dt_converged"] is None and py["step_check"] is None
        assert py["step_unchecked"].startswith("the exact answer has no step")
        return
    c = py["step_check"]
    assert "step_unchecked" not in py
    assert py["dt_converged"] is c["converged"] is True
    assert c["scale"] == ("log" if case == "ams_mean_time" else "linear")
    # The answer returned is the one at dt, the check's second answer at
    # dt/2; the change and its half-width are those of the two intervals.
    assert c["at_dt"] == {"dt": 2e-15, "estimate": py["estimate"], "ci95": py["ci95"]}
    assert c["at_half_dt"]["dt"] == 1e-15
    assert c["refined_seed_offset"] == 0x9E3779B97F4A7C15
    assert c["refined_trajectories"] > 0 and c["refined_steps"] > py["steps"]
    lo, hi = c["at_dt"]["ci95"], c["at_half_dt"]["ci95"]
    if c["scale"] == "linear":
        change = abs(c["at_half_dt"]["estimate"] - py["estimate"])
        width = math.hypot((lo[1] - lo[0]) / 2, (hi[1] - hi[0]) / 2)
    else:
        change = abs(math.log(c["at_half_dt"]["estimate"] / py["estimate"]))
        width = math.hypot(math.log(lo[1] / lo[0]) / 2, math.log(hi[1] / hi[0]) / 2)
    assert math.isclose(c["step_error"], change, rel_tol=1e-12)
    assert math.isclose(c["statistical"], width, rel_tol=1e-12)
    assert change < width


def test_step_check_false_says_unchecked(sc):
    on = tt.rare(sc, target=UP, reset=DOWN, replicas=40)
    off = tt.rare(sc, target=UP, reset=DOWN, replicas=40, step_check=False)
    assert off["dt_converged"] is None and off["step_check"] is None
    assert off["step_unchecked"] == "step_check=False"
    # The answer at dt is the same with or without the check.
    for key in ("estimate", "ci95", "trajectories", "steps", "tally"):
        assert on[key] == off[key], key
    assert on["dt_converged"] is True and on["step_check"]["converged"] is True
    with pytest.raises(TypeError, match="step_check"):
        tt.rare(sc, target=UP, reset=DOWN, replicas=40, step_check=None)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(target="theta>1.5"), "--target: theta>1.5 already holds at the start"),
        (dict(target=UP, reset="theta<1.6"), "--reset: theta<1.6 already holds"),
        (
            dict(target=UP, reset=DOWN, method="ams", coordinate="thetaa"),
            '--coordinate: "thetaa" is not a trajectory.csv column',
        ),
        (dict(target=UP, coordinate="theta"), "--coordinate: given with --method direct"),
        (dict(target=UP, reset=DOWN, method="ams", replicas=1), "--replicas: 1 replicas"),
        (dict(target=UP, reset=DOWN, method="ams", max_trajectories=5), "--max-trajectories: 5"),
        (dict(target=UP, reset=DOWN, method="ams", max_steps=0), "--max-steps: 0"),
        (dict(target="theta>1.5", reset=DOWN, method="ams"), "--target: theta>1.5 already holds"),
        (
            dict(target=UP, reset=DOWN, method="ams", kill=20, particles=20),
            "--kill: 20 of 20 particles",
        ),
        (dict(target=UP, method="fast"), '--method: "fast" is not a method'),
        (dict(target=UP, replicas=0), "--replicas: 0"),
        (dict(target=UP, max_steps=-3), "--max-steps: -3"),
        (dict(target="omega>1", method="exact"), "--target: no exact 1D answer"),
    ],
)
def test_bad_input(sc, kwargs, message):
    with pytest.raises(ValueError, match="^" + message.replace("(", r"\(")):
        tt.rare(sc, **kwargs)


def test_ams_agrees_with_exact(sc):
    # P(theta > 2.5 before theta < 1.565) ~ 2e-3 by 20 replicas of 20
    # particles: the exact value for the path watched at every step lies
    # within 3 of the estimate's standard errors, and 3 SE is below the
    # estimate (the test can fail).
    r = tt.rare(
        sc, target="theta>2.5", reset="theta<1.565", method="ams",
        replicas=20, particles=20, threads=2, step_check=False,
    )
    assert r["method"] == "ams" and r["quantity"] == "probability"
    assert r["replicas"] == 20 and r["trajectories"] >= 400
    se = r["ams"]["standard_error"]
    exact = r["exact"]["watched"]
    assert abs(r["estimate"] - exact) < 3 * se
    assert 3 * se < r["estimate"]
    assert r["ams"]["coordinate"] == "theta"
    assert math.isclose(sum(r["ams"]["replica_estimates"]) / 20, r["estimate"], rel_tol=1e-12)


def test_ams_extinction_is_zero_with_a_bound(sc):
    # 5 steps cannot climb 0.18 rad: no particle meets the target; the
    # estimate is 0 and the upper end the rule of three for n M roots.
    r = tt.rare(sc, target=UP, reset="theta<1.39", method="ams", horizon=1e-14,
                replicas=3, particles=20)
    assert r["estimate"] == 0.0
    assert r["ci95"][0] == 0.0
    assert math.isclose(r["ci95"][1], 1 - 0.05 ** (1 / 60), rel_tol=1e-12)
    assert r["ams"]["extinct"] is True


def test_ams_same_figures_as_the_cli(sc, tmp_path):
    args = ["--target", UP, "--reset", DOWN, "--method", "ams", "--replicas", "5",
            "--particles", "20"]
    cli = run_cli(tmp_path, [*args, "--no-step-check"])
    py = tt.rare(sc, target=UP, reset=DOWN, method="ams", replicas=5, particles=20,
                 step_check=False)
    py.pop("wall_seconds")
    assert py == without_step_check(cli)
