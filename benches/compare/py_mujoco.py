#!/usr/bin/env python3
"""tippetop's Python package against MuJoCo in ONE Python process (issue #28):
`tt.run` of the classical top (10 s, regularised friction eps = 1e-3 m/s,
rtol 1e-8, the default model) against MuJoCo's `mj_step` (RK4, dt = 1e-3 s,
10 000 steps in one call) on the same top (compare.py's `mujoco_xml`: a free
body carrying a sphere, its centre of mass a below the centre).

The two are timed alternately, `--repeats` times each, in the same process
(so the same interpreter, the same load), and the ratio of the medians and
of the best times is reported. MuJoCo's contact is soft and its top does not
invert at dt = 1e-3 (compare.py, docs/performance.md): the two compare as
costs of "10 s of this top", not as trajectories. Usage (repository root):

    python3 -m venv .venv && .venv/bin/pip install ./crates/tippetop-py mujoco==4.0.0 scipy matplotlib
    .venv/bin/python benches/compare/py_mujoco.py [--repeats 21] [--out docs/perf]

Writes py_mujoco.json and py_mujoco.png into --out. Not part of CI.
"""
import argparse
import json
import math
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mujoco  # noqa: E402
import tippetop as tt  # noqa: E402
from compare import machine, mujoco_init, mujoco_xml, theta_of  # noqa: E402

T_END, DT = 10.0, 1e-3


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=21)
    ap.add_argument("--out", default="docs/perf")
    a = ap.parse_args()

    model = mujoco.MjModel.from_xml_string(mujoco_xml(DT))
    data = mujoco.MjData(model)
    nstep = int(round(T_END / DT))
    sc = tt.Scenario.preset("classical").set_many(
        {
            "surface.friction_law": "regularized",
            "surface.friction_eps": 1e-3,
            "solver.rtol": 1e-8,
            "solver.t_end": T_END,
        }
    )

    def mj():
        mujoco_init(mujoco, model, data)
        t0 = time.perf_counter()
        mujoco.mj_step(model, data, nstep)
        return time.perf_counter() - t0

    def ttrun():
        t0 = time.perf_counter()
        tr = tt.run(sc)
        wall = time.perf_counter() - t0
        assert tr.error is None, tr.error
        return wall, tr

    mj()  # warm both up (page faults, first-call costs) before timing
    _, tr = ttrun()
    mj_t, tt_t = [], []
    for _ in range(a.repeats):
        mj_t.append(mj())
        tt_t.append(ttrun()[0])
    theta = tr.to_dict()["theta"]
    res = dict(
        machine=machine(),
        mujoco=dict(version=mujoco.__version__, integrator="RK4", dt=DT, steps=nstep,
                    median_s=statistics.median(mj_t), best_s=min(mj_t), times_s=mj_t,
                    theta_final=theta_of(data.qpos[3:7])),
        tippetop=dict(version=getattr(tt, "__version__", "?"), law="regularized", eps=1e-3,
                      rtol=1e-8, t_end=T_END, median_s=statistics.median(tt_t),
                      best_s=min(tt_t), times_s=tt_t, theta_final=float(theta[-1]),
                      inverts=bool(max(theta) > math.pi / 2),
                      steps=tr.summary["steps"], rhs_evaluations=tr.summary["rhs_evaluations"]),
    )
    res["ratio_median"] = res["mujoco"]["median_s"] / res["tippetop"]["median_s"]
    res["ratio_best"] = res["mujoco"]["best_s"] / res["tippetop"]["best_s"]
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "py_mujoco.json"), "w") as f:
        json.dump(res, f, indent=1)
    m, t = res["mujoco"], res["tippetop"]
    print(f"MuJoCo {m['version']} mj_step RK4 dt = 1 ms, 10 s: median {m['median_s'] * 1e3:.4g} ms "
          f"(best {m['best_s'] * 1e3:.4g} ms), {a.repeats} runs")
    print(f"tt.run classical, regularised eps = 1e-3 m/s, rtol 1e-8, 10 s: median "
          f"{t['median_s'] * 1e3:.4g} ms (best {t['best_s'] * 1e3:.4g} ms); inverts: {t['inverts']}")
    print(f"tt.run is {res['ratio_median']:.3g}x faster (medians), {res['ratio_best']:.3g}x (best times)")
    plot(res, mj_t, tt_t, os.path.join(a.out, "py_mujoco.png"))


def plot(res, mj_t, tt_t, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 3.2), constrained_layout=True)
    rows = [("MuJoCo mj_step\nRK4, dt = 1 ms", mj_t), ("tippetop tt.run\nDOP853, rtol 1e-8", tt_t)]
    for i, (name, ts) in enumerate(rows):
        ax.scatter([x * 1e3 for x in ts], [i] * len(ts), s=12, alpha=0.6, color=f"C{i}")
        med = statistics.median(ts) * 1e3
        ax.plot([med, med], [i - 0.25, i + 0.25], color="k", lw=2)
        ax.annotate(f"median {med:.3g} ms", (med, i + 0.3), ha="center", fontsize=9)
    ax.set_yticks([0, 1], [r[0] for r in rows])
    ax.set_ylim(-0.6, 1.8)
    ax.set_xscale("log")
    lo, hi = min(mj_t + tt_t) * 1e3, max(mj_t + tt_t) * 1e3
    ax.set_xlim(lo / 2, hi * 2.5)
    ax.set_xlabel("wall time for 10 s of the classical top, one Python process [ms]")
    ax.set_title(f"tt.run {res['ratio_median']:.3g}x faster than MuJoCo {res['mujoco']['version']} "
                 f"(medians of {len(mj_t)})", fontsize=10)
    fig.savefig(path, dpi=130)


if __name__ == "__main__":
    main()
