"""The paper's Fig. 2 from Python: the nutation angle θ(t) of the C60 nano
tippe top for g = 0, 9.8 and 100 m/s², as `tippetop reproduce` draws it
(fig02.png): the same runs, the same numbers.

Needs matplotlib, which tippetop itself does not (from the repository's root,
in the environment tippetop is installed in):

    .venv/bin/pip install matplotlib
    .venv/bin/python examples/python/paper_fig2.py            # writes paper_fig2.png
    .venv/bin/python examples/python/paper_fig2.py --out f.png --tiny

--tiny runs 1 µs instead of 100 µs (a smoke test). The cells (`# %%`) run
one by one in VS Code or Jupyter; examples/python/tippetop.ipynb is the same
as a notebook.
"""

# %% Setup
import argparse
import pathlib
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
parser.add_argument("--out", default="paper_fig2.png", help="PNG to write")
parser.add_argument("--tiny", action="store_true", help="1 µs instead of 100 µs")
args = parser.parse_args()

# %% The scenario
# The paper's nano top (scenarios/nano.toml: a C60 shell on graphene, the
# retarding force H_x = H_y = 0.1 zN from t = 0, θ(0) = 0.1 rad, ω(0) =
# 100 rad/s, 100 µs) with the paper's own Euler-angle equations, as
# `tippetop reproduce` runs it. Outside the repository: the "nano" preset,
# the same top.
ROOT = pathlib.Path(__file__).resolve().parents[2]
path = ROOT / "scenarios" / "nano.toml"
base = tt.Scenario.from_file(path) if path.is_file() else tt.Scenario.preset("nano")
base = base.set("solver.model", "reduced")
if args.tiny:
    base = base.set("solver.t_end", 1e-6)

# The paper's literal contact law (its "paper contact"), and its method:
# classical RK4 on 500 steps (each `set` is checked at once, so the
# sample count comes first: RK4 needs steps to be a multiple of samples - 1).
paper = base.set("surface.friction_law", "coulomb_sliding").set("surface.contact", "paper")
paper_rk4 = paper.set("solver.samples", 501).set("solver.steps", 500).set("solver.method", "rk4")

# %% The runs (each a few seconds at most; the GIL is released meanwhile)
curves = [
    ("g=0 bilateral", base.set("surface.gravity", 0.0), "-"),
    ("g=9.8 bilateral", base, "-"),
    ("g=100 bilateral", base.set("surface.gravity", 100.0), "-"),
    ("g=9.8 paper contact", paper, "-"),
    ("g=9.8 paper contact RK4/500", paper_rk4, "--"),
]
results = [(name, tt.run(sc), style) for name, sc, style in curves]
for name, tr, _ in results:
    end = f"θ({tr.t[-1] * 1e6:.3g} µs) = {tr.theta[-1]:.4f} rad"
    failed = f"; failed: {tr.error['message'][:60]}..." if tr.error else ""
    print(f"{name:30s} {end}{failed}")

# %% The figure
fig, ax = plt.subplots(figsize=(9, 5.5))
for name, tr, style in results:
    ax.plot(tr.t * 1e6, tr.theta, style, lw=0.9, label=name)  # t [s] -> µs
for y, label in [(np.pi / 2, "π/2"), (np.pi, "π")]:
    ax.axhline(y, color="grey", lw=0.8, ls=":")
    ax.text(ax.get_xlim()[1], y, f" {label}", va="center", color="grey")
ax.set_xlabel("t [µs]")
ax.set_ylabel("θ [rad]")
ax.set_title("Fig. 2: nutation angle θ of the nano top for g = 0, 9.8 and 100 m/s²")
ax.legend(loc="lower right")
fig.tight_layout()
fig.savefig(args.out, dpi=120)
print(f"wrote {args.out}")
