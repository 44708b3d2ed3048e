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

The notebook tippetop.ipynb imports this file (`import inversion_map`): the
sweep, the criterion of "inverted", the counts and the figure are these
functions, so the notebook and the script print the same lines.
"""

import argparse
import sys

import numpy as np

import tippetop as tt

# A top ends "inverted" when it ends standing on its stem, within this angle
# of θ = π [rad]. A top outside the window may rise past π/2 to a tilted
# state without inverting, so θ > π/2 would overcount.
INVERTED_WITHIN = 0.3


def inverted(theta):
    """Whether each final θ [rad] is inverted: within INVERTED_WITHIN of π."""
    return np.asarray(theta) > np.pi - INVERTED_WITHIN


def sweep_maps(tiny=False, threads=None):
    """θ after t_end over the (A/C, a/R) grid for each friction law.

    Returns (t_end [s], {law: (A_C, a_R, theta, failed)}): A_C and a_R the
    grid's axes, theta[i, j] the final θ [rad] of the top (A_C[i], a_R[j])
    (NaN for a failed run), failed the number of failed runs."""
    base = tt.Scenario.preset("classical")
    C = base.get("top.inertia_axial")  # [kg m²]
    R = base.get("top.radius")  # [m]
    nx, ny = (5, 4) if tiny else (21, 20)
    t_end = 1.0 if tiny else 10.0  # [s]
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
        sw = tt.sweep(sc, vary=vary, threads=threads)  # one row per top, A slowest
        theta = np.where(sw["status"] == "ok", sw["theta_final"], np.nan)
        A_C = sw["top.inertia_transverse"].reshape(nx, ny)[:, 0] / C
        a_R = sw["top.offset"].reshape(nx, ny)[0, :] / R
        failed = int(np.sum(sw["status"] != "ok"))
        maps[law] = (A_C, a_R, theta.reshape(nx, ny), failed)
    return t_end, maps


def census(A_C, a_R, theta):
    """The counts of one map: tops inside and outside the window, inverted
    ones and ones past π/2 but not inverted (tilted), each inside and
    outside."""
    x, y = np.meshgrid(A_C, a_R, indexing="ij")
    inside = (1 - y < x) & (x < 1 + y)
    inv = inverted(theta)
    tilted = (theta > np.pi / 2) & ~inv
    return {
        "inside": int(np.sum(inside)),
        "outside": int(np.sum(~inside)),
        "inverted_inside": int(np.sum(inv & inside)),
        "inverted_outside": int(np.sum(inv & ~inside)),
        "tilted_inside": int(np.sum(tilted & inside)),
        "tilted_outside": int(np.sum(tilted & ~inside)),
    }


def summary_line(law, t_end, A_C, a_R, theta, failed):
    """One map's counts as the line the script and the notebook print."""
    c = census(A_C, a_R, theta)
    return (
        f"{law}: {theta.size} tops, {failed} failed; "
        f"inverted (θ within {INVERTED_WITHIN:g} rad of π) after {t_end:g} s: "
        f"{c['inverted_inside']} of {c['inside']} inside the window, "
        f"{c['inverted_outside']} of {c['outside']} outside; past π/2 but not inverted: "
        f"{c['tilted_inside']} inside, {c['tilted_outside']} outside"
    )


def draw(t_end, maps):
    """The maps side by side, the window's edges in white; a Figure."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True, constrained_layout=True)
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("grey")  # a failed case
    for ax, (law, (A_C, a_R, z, _)) in zip(axes, maps.items()):
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
    return fig


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="inversion_map.png", help="PNG to write")
    parser.add_argument("--tiny", action="store_true", help="5 x 4 tops over 1 s")
    parser.add_argument("--threads", type=int, default=None, help="default: one per core")
    args = parser.parse_args()
    try:
        import matplotlib
    except ImportError:
        sys.exit("this example plots with matplotlib: pip install matplotlib")
    matplotlib.use("Agg")  # write a file, no window

    t_end, maps = sweep_maps(tiny=args.tiny, threads=args.threads)
    for law, m in maps.items():
        print(summary_line(law, t_end, *m))

    draw(t_end, maps).savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
