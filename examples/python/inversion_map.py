"""The classical tippe top's inversion map from Python: θ after 10 s over
(A/C, a/R), for regularised and exact Coulomb friction, as `tippetop
reproduce` draws it (inversion_map_regularized.png, inversion_map_exact.png):
the same sweep (tt.sweep, the CLI's `tippetop sweep`), the same numbers.

The paper's classical top (R = 15 mm, m = 15 g, C = 2/5 m R², μ = 0.1) from
its initial state (θ = 0.1 rad, ω = 100 rad/s), C fixed, A = (A/C)·C and
a = (a/R)·R varied; the white lines are the literature's inversion window
1 − a/R < A/C < 1 + a/R.

Needs matplotlib, which tippetop itself does not (from the repository's root,
in the environment tippetop is installed in):

    .venv/bin/pip install matplotlib
    .venv/bin/python examples/python/inversion_map.py         # writes inversion_map.png
    .venv/bin/python examples/python/inversion_map.py --out m.png --tiny

--tiny: a 5 x 4 grid over 1 s (as reproduce --quick's grid); the full map is
21 x 20 tops over 10 s, 840 runs, a few seconds on two cores.
"""

# %% Setup
import argparse
import sys

import numpy as np

import tippetop as tt

try:
    import matplotlib
except ImportError:
    sys.exit("this example plots with matplotlib: pip install matplotlib")
matplotlib.use("Agg")  # write a file, no window
import matplotlib.pyplot as plt  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--out", default="inversion_map.png", help="PNG to write")
parser.add_argument("--tiny", action="store_true", help="5 x 4 tops over 1 s")
parser.add_argument("--threads", type=int, default=None, help="default: one per core")
args = parser.parse_args()

# %% The sweep
base = tt.Scenario.preset("classical")
C = base.get("top.inertia_axial")  # [kg m²]
R = base.get("top.radius")  # [m]
nx, ny = (5, 4) if args.tiny else (21, 20)
t_end = 1.0 if args.tiny else 10.0  # [s]
base = base.set("solver.t_end", t_end).set("solver.samples", 201)
vary = {
    "top.inertia_transverse": (0.55 * C, 1.5 * C, nx),  # A [kg m²]: A/C from 0.55 to 1.5
    "top.offset": (0.02 * R, 0.4 * R, ny),  # a [m]: a/R from 0.02 to 0.4
}
laws = {
    # Two keys that need each other: set together (ε in m/s).
    "regularized": base.set_many(
        {"surface.friction_law": "regularized", "surface.friction_eps": 1e-2}
    ),
    "exact Coulomb": base,
}
maps = {}
for law, sc in laws.items():
    sw = tt.sweep(sc, vary=vary, threads=args.threads)  # one row per top, A slowest
    theta = np.where(sw["status"] == "ok", sw["theta_final"], np.nan)
    A_C = sw["top.inertia_transverse"].reshape(nx, ny)[:, 0] / C
    a_R = sw["top.offset"].reshape(nx, ny)[0, :] / R
    maps[law] = (A_C, a_R, theta.reshape(nx, ny))
    # Inside the window, how many tops end inverted? "Inverted" is the
    # window's criterion: the top ends standing on its stem, within 0.3 rad
    # of θ = π (a top outside the window may rise past π/2 to a tilted
    # state without inverting, so θ > π/2 would overcount).
    x, y = np.meshgrid(A_C, a_R, indexing="ij")
    inside = (1 - y < x) & (x < 1 + y)
    inv = maps[law][2] > np.pi - 0.3
    tilted = (maps[law][2] > np.pi / 2) & ~inv
    print(
        f"{law}: {len(theta)} tops, {np.sum(sw['status'] != 'ok')} failed; "
        f"inverted (θ within 0.3 rad of π) after {t_end:g} s: {np.sum(inv & inside)} of "
        f"{np.sum(inside)} inside the window, {np.sum(inv & ~inside)} of {np.sum(~inside)} "
        f"outside; past π/2 but not inverted: {np.sum(tilted & inside)} inside, "
        f"{np.sum(tilted & ~inside)} outside"
    )

# %% The maps
fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True, constrained_layout=True)
cmap = plt.get_cmap("viridis").copy()
cmap.set_bad("grey")  # a failed case
for ax, (law, (A_C, a_R, z)) in zip(axes, maps.items()):
    mesh = ax.pcolormesh(
        A_C, a_R, np.ma.masked_invalid(z.T), cmap=cmap, vmin=0, vmax=np.pi, shading="nearest"
    )
    for sign in (-1, 1):
        ax.plot(1 + sign * a_R, a_R, color="white", lw=1.5)
    ax.set_xlabel("A/C")
    ax.set_title(f"θ after {t_end:g} s, {law} friction")
axes[0].set_ylabel("a/R")
fig.colorbar(mesh, ax=axes, label="θ final [rad]")
fig.suptitle("Classical tippe top; white: the inversion window 1 ∓ a/R")
fig.savefig(args.out, dpi=120)
print(f"wrote {args.out}")
