"""Time the classical tippe top in MuJoCo, in scipy (the same reduced equations
as tippetop) and in tippetop, on the same machine in the same run, and draw a
work-precision figure for scipy vs tippetop. See README.md in this folder.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/compare/compare.py [--repeats 5] [--out docs/perf] [--quick]

Writes into --out: compare.json (every figure), compare.md (the table),
work_precision.csv, work_precision.png and mujoco_theta.csv. Not part of CI.
"""
import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from reduced_scipy import make_rhs, preset  # noqa: E402

# Classical preset (scenarios: preset = "classical").
CL = preset("classical")
R, A_OFF, M, I_T, I_A, MU, G = (CL[k] for k in ("R", "a", "m", "A", "C", "mu", "g"))
TH0, W0 = 0.1, 100.0
EPS = 1e-3
# tippetop's unit of time for this preset is 1/100 s (rate = max(|w0|, sqrt(g/R), 1/t_end)).
RATE = 100.0


def best_of(n, f):
    """Smallest wall time of n calls of f (the least disturbed by other load); f returns (wall, value)."""
    best, val = math.inf, None
    for _ in range(n):
        w, v = f()
        if w < best:
            best, val = w, v
    return best, val


# ---------------------------------------------------------------- MuJoCo

def mujoco_xml(dt):
    # Sphere of radius R centred at the body origin; centre of mass a below it
    # along the body z axis (the symmetry axis, pointing from the centre of
    # mass to the centre: theta = 0 is standing on the ball, theta = pi inverted).
    return f"""<mujoco model="tippetop_classical">
  <option timestep="{dt}" integrator="RK4" gravity="0 0 -{G}"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" friction="{MU} 0 0" condim="3"/>
    <body name="top" pos="0 0 {R}">
      <freejoint/>
      <inertial pos="0 0 {-A_OFF}" mass="{M}" diaginertia="{I_T} {I_T} {I_A}"/>
      <geom name="ball" type="sphere" size="{R}" friction="{MU} 0 0" condim="3"/>
    </body>
  </worldbody>
</mujoco>"""


def mujoco_init(mujoco, model, data):
    mujoco.mj_resetData(model, data)
    data.qpos[0:3] = [0.0, 0.0, R]
    data.qpos[3:7] = [math.cos(TH0 / 2), math.sin(TH0 / 2), 0.0, 0.0]
    # Free joint: linear velocity of the body origin (world), angular velocity
    # in the body frame. Spin w0 about the symmetry axis; the centre (the body
    # origin) then moves with w x (a k) = 0, as the centre of mass does (u = 0).
    data.qvel[:] = [0.0, 0.0, 0.0, 0.0, 0.0, W0]
    mujoco.mj_forward(model, data)


def theta_of(q):
    # k = R(q) e_z; cos(theta) = k_z = 1 - 2 (qx^2 + qy^2).
    kz = 1.0 - 2.0 * (q[1] ** 2 + q[2] ** 2)
    return math.acos(max(-1.0, min(1.0, kz)))


def run_mujoco(dt, t_end, repeats):
    import mujoco

    model = mujoco.MjModel.from_xml_string(mujoco_xml(dt))
    data = mujoco.MjData(model)
    nstep = int(round(t_end / dt))

    def once():
        mujoco_init(mujoco, model, data)
        t0 = time.perf_counter()
        mujoco.mj_step(model, data, nstep)
        return time.perf_counter() - t0, (data.time, theta_of(data.qpos[3:7]))

    wall, (t_fin, th_fin) = best_of(repeats, once)
    # theta(t): the same run in chunks of 10 ms (identical steps), not timed.
    mujoco_init(mujoco, model, data)
    chunk = max(1, int(round(0.01 / dt)))
    ts, ths = [0.0], [theta_of(data.qpos[3:7])]
    for _ in range(nstep // chunk):
        mujoco.mj_step(model, data, chunk)
        ts.append(data.time)
        ths.append(theta_of(data.qpos[3:7]))
    assert abs(ths[-1] - th_fin) < 1e-9 * max(1.0, th_fin), (ths[-1], th_fin)
    return dict(
        dt=dt, steps=nstep, wall=wall, t_end=t_fin, theta_final=th_fin,
        theta_max=max(ths), theta_min=min(ths), inverts=bool(max(ths) > math.pi / 2),
        version=mujoco.__version__, t=ts, theta=ths,
    )


# ---------------------------------------------------------------- scipy

def atol_vector(rtol):
    # tippetop's scaled tolerance (atol = rtol in units of R and 1/RATE) in SI.
    return rtol * np.array([1.0, RATE, RATE, RATE, R * RATE, R * RATE])


def run_scipy(rtol, t_end, t_eval=None, max_step=np.inf, law="regularized"):
    rhs = make_rhs(CL, law, EPS, "bilateral")
    y0 = [TH0, 0.0, 0.0, W0, 0.0, 0.0]
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=atol_vector(rtol),
                    t_eval=t_eval, max_step=max_step)
    wall = time.perf_counter() - t0
    assert sol.status == 0, sol.message
    return wall, dict(y_end=sol.y[:, -1].tolist(), nfev=int(sol.nfev), theta_final=float(sol.y[0, -1]))


# ---------------------------------------------------------------- tippetop

MODELS = ("reduced", "vector")


def tippetop_cmd(binary, out, rtol, t_end=None, law="regularized", samples=None, model="reduced"):
    cmd = [binary, "run", "--preset", "classical", "--set", f'solver.model="{model}"']
    if law == "regularized":
        cmd += ["--set", 'surface.friction_law="regularized"', "--set", f"surface.friction_eps={EPS}"]
    else:
        cmd += ["--set", f'surface.friction_law="{law}"']
    cmd += ["--set", f"solver.rtol={rtol}"]
    if t_end is not None:
        cmd += ["--set", f"solver.t_end={t_end}"]
    if samples is not None:
        cmd += ["--set", f"solver.samples={samples}"]
    return cmd + ["--no-plot", "--quiet", "--out", out]


def run_tippetop(binary, rtol, t_end=None, law="regularized", samples=None, plots=False, model="reduced"):
    """Whole-process wall time, the in-process simulate() time (summary.json
    wall_seconds) and the final state (last row of trajectory.csv, SI)."""
    with tempfile.TemporaryDirectory() as out:
        cmd = tippetop_cmd(binary, out, rtol, t_end, law, samples, model)
        if plots:
            cmd.remove("--no-plot")
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True)
        wall = time.perf_counter() - t0
        with open(os.path.join(out, "summary.json")) as f:
            summ = json.load(f)
        with open(os.path.join(out, "trajectory.csv")) as f:
            header = f.readline().strip().split(",")
            last = None
            for line in f:
                last = line
        row = dict(zip(header, map(float, last.split(","))))
        y_end = [row[k] for k in ("theta", "theta_dot", "Omega", "omega", "ux", "uy")]
    return wall, dict(in_process=summ["wall_seconds"], y_end=y_end, steps=summ.get("steps"),
                      rhs_evaluations=summ.get("rhs_evaluations"), theta_final=row["theta"],
                      cmd=" ".join(cmd[:-1] + ["/tmp/x"]))


def scaled_error(y, ref):
    """Max-norm of the Euler-angle state error in tippetop's scaled units
    (rad, 1/RATE s, R). Near the pole it is dominated by Ω, whose error is the
    physical state's error amplified by 1/sin²θ (the classical top runs at
    θ = 0.015-0.05 rad here)."""
    scale = np.array([1.0, RATE, RATE, RATE, R * RATE, R * RATE])
    return float(np.max(np.abs((np.array(y) - np.array(ref)) / scale)))


def physical(y):
    """The azimuth-free physical state of (θ, θ̇, Ω, ω, u_x, u_y) in scaled
    units: the axis k = (sin θ, 0, cos θ), the angular velocity
    w = ((ω − Ω cos θ) sin θ, θ̇, Ω sin²θ + ω cos θ)/RATE and the centre-of-mass
    velocity (u_x, u_y)/(R RATE), all in the precessing frame
    (docs/physics.md#vector-model). Well conditioned at every θ."""
    th, thd, om, w, ux, uy = y
    s, c = math.sin(th), math.cos(th)
    return np.array([s, c, (w - om * c) * s / RATE, thd / RATE, (om * s * s + w * c) / RATE,
                     ux / (R * RATE), uy / (R * RATE)])


def physical_error(y, ref):
    """Max-norm of the physical state error (see `physical`)."""
    return float(np.max(np.abs(physical(y) - physical(ref))))


# ---------------------------------------------------------------- main

def machine():
    model = ""
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return dict(nproc=os.cpu_count(), cpu=model, load=os.getloadavg(),
                date=time.strftime("%Y-%m-%d %H:%M:%S %Z"), python=platform.python_version())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tippetop", default="target/release/tippetop")
    ap.add_argument("--repeats", type=int, default=5, help="best-of repeats for the fast runs")
    ap.add_argument("--out", default="docs/perf")
    ap.add_argument("--quick", action="store_true", help="fewer tolerances and repeats (smoke test)")
    o = ap.parse_args()
    os.makedirs(o.out, exist_ok=True)
    rep = 1 if o.quick else o.repeats
    res = dict(machine=machine())
    print(f"machine: {res['machine']}", flush=True)

    # (c) tippetop, whole process and in process, 10 s at rtol 1e-8, both
    # on-plane models (reduced = Euler angles, vector = no Euler angles).
    tt = {}
    for model in MODELS:
        for law in ("regularized", "coulomb"):
            run = lambda: run_tippetop(o.tippetop, 1e-8, law=law, model=model)
            w, info = best_of(rep, run)
            info["wall"] = w
            info["in_process"] = min(run()[1]["in_process"] for _ in range(rep))
            tt[f"{model}/{law}"] = info
            print(f"tippetop {model} {law}: process {w*1e3:.2f} ms, simulate() {info['in_process']*1e3:.2f} ms, "
                  f"steps {info['steps']}, evaluations {info['rhs_evaluations']}, "
                  f"theta(10 s) {info['theta_final']:.6f}", flush=True)
    w, _ = best_of(max(1, rep // 2), lambda: run_tippetop(o.tippetop, 1e-8, plots=True))
    tt["reduced/regularized"]["wall_with_plots"] = w
    print(f"tippetop reduced regularized with plots: {w*1e3:.1f} ms", flush=True)
    res["tippetop"] = tt

    # (a) MuJoCo.
    mj = {}
    for dt in (1e-3, 1e-4):
        r = run_mujoco(dt, 10.0, rep if dt == 1e-3 else max(1, rep // 2))
        mj[str(dt)] = r
        print(f"MuJoCo {r['version']} RK4 dt={dt}: {r['wall']*1e3:.1f} ms for {r['steps']} steps, "
              f"theta(10 s) {r['theta_final']:.4f}, max {r['theta_max']:.4f}, inverts {r['inverts']}",
              flush=True)
    with open(os.path.join(o.out, "mujoco_theta.csv"), "w") as f:
        f.write("t,theta_dt1e-3,theta_dt1e-4\n")
        a, b = mj["0.001"], mj["0.0001"]
        for i in range(min(len(a["t"]), len(b["t"]))):
            f.write(f"{a['t'][i]:.6g},{a['theta'][i]!r},{b['theta'][i]!r}\n")
    for r in mj.values():
        del r["t"], r["theta"]
    res["mujoco"] = mj

    # (b) scipy DOP853, same equations, rtol 1e-8, 10 s, 1001 output points and
    # tippetop's largest step (t_end / 1000) so both do the same work.
    t_eval = np.linspace(0.0, 10.0, 1001)
    w, info = best_of(1 if o.quick else 2, lambda: run_scipy(1e-8, 10.0, t_eval=t_eval, max_step=0.01))
    info["wall"] = w
    res["scipy"] = info
    print(f"scipy DOP853 rtol 1e-8: {w:.2f} s, nfev {info['nfev']}, theta(10 s) {info['theta_final']:.4f}",
          flush=True)

    # Work-precision: error of the state at t = 1 s against a tight reference.
    # tippetop with 11 samples (largest step 0.1 s), scipy without a step limit.
    ref_wall, ref = run_tippetop(o.tippetop, 1e-13, t_end=1.0, samples=11)
    ref_sw, sref = run_scipy(1e-13, 1.0)
    ref_check = scaled_error(sref["y_end"], ref["y_end"])
    _, vref = run_tippetop(o.tippetop, 1e-13, t_end=1.0, samples=11, model="vector")
    vref_check = scaled_error(vref["y_end"], ref["y_end"])
    print(f"reference: tippetop rtol 1e-13 vs scipy rtol 1e-13 differ by {ref_check:.2e}, "
          f"vs tippetop vector rtol 1e-13 by {vref_check:.2e} (scaled)", flush=True)
    rtols = [1e-4, 1e-6, 1e-8, 1e-10] if o.quick else [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11]
    wp = []
    for rt in rtols:
        row = dict(rtol=rt)
        for model in MODELS:
            run = lambda: run_tippetop(o.tippetop, rt, t_end=1.0, samples=11, model=model)
            _, ti = run()
            t_in = min([ti["in_process"]] + [run()[1]["in_process"] for _ in range(rep - 1)])
            row[f"{model}_s"] = t_in
            row[f"{model}_err"] = scaled_error(ti["y_end"], ref["y_end"])
            row[f"{model}_perr"] = physical_error(ti["y_end"], ref["y_end"])
            row[f"{model}_rhs"] = ti["rhs_evaluations"]
        sw, si = best_of(1 if (o.quick or rt < 1e-9) else 2, lambda: run_scipy(rt, 1.0))
        row.update(scipy_s=sw, scipy_err=scaled_error(si["y_end"], ref["y_end"]),
                   scipy_perr=physical_error(si["y_end"], ref["y_end"]), scipy_nfev=si["nfev"])
        wp.append(row)
        print(f"rtol {rt:.0e}: " + " | ".join(
            f"{m} {row[m + '_s']*1e3:.3f} ms err {row[m + '_err']:.2e} phys {row[m + '_perr']:.2e}" for m in MODELS)
            + f" | scipy {sw*1e3:.1f} ms err {row['scipy_err']:.2e} phys {row['scipy_perr']:.2e}", flush=True)
    res["reference"] = dict(check_vs_scipy_1e13=ref_check, check_vector_1e13=vref_check,
                            scipy_1e13_wall=ref_sw, tippetop_1e13_process_wall=ref_wall)
    res["work_precision"] = wp
    with open(os.path.join(o.out, "work_precision.csv"), "w") as f:
        f.write("rtol," + ",".join(f"{m}_seconds,{m}_error,{m}_physical_error,{m}_rhs_evals" for m in MODELS)
                + ",scipy_seconds,scipy_error,scipy_physical_error,scipy_nfev\n")
        for r in wp:
            f.write(f"{r['rtol']:.0e},"
                    + ",".join(f"{r[m + '_s']!r},{r[m + '_err']!r},{r[m + '_perr']!r},{r[m + '_rhs']}" for m in MODELS)
                    + f",{r['scipy_s']!r},{r['scipy_err']!r},{r['scipy_perr']!r},{r['scipy_nfev']}\n")
    # Equal-error speed ratio: scipy time interpolated (log-log) at tippetop's
    # error, for both error measures.
    ratios = {}
    for kind in ("err", "perr"):
        se = np.log10([max(r["scipy_" + kind], 1e-300) for r in wp])
        st = np.log10([r["scipy_s"] for r in wp])
        order = np.argsort(se)
        for m in MODELS:
            out = ratios.setdefault(f"{m}/{kind}", [])
            for r in wp:
                e = math.log10(max(r[f"{m}_{kind}"], 1e-300))
                if se.min() <= e <= se.max():
                    out.append(dict(rtol=r["rtol"], error=r[f"{m}_{kind}"],
                                    ratio=10 ** float(np.interp(e, se[order], st[order])) / r[m + "_s"]))
    res["equal_error_ratios"] = ratios

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.6), dpi=120)
        for ax, kind, what in zip(axes, ("err", "perr"),
                                  ("Euler-angle state error (max-norm, scaled)",
                                   "physical state error (k, w, v; max-norm, scaled)")):
            for m, mark in zip(MODELS, "o^"):
                ax.loglog([r[m + "_s"] for r in wp], [r[f"{m}_{kind}"] for r in wp], mark + "-",
                          label=f"tippetop {m} (DOP853, Rust)")
            ax.loglog([r["scipy_s"] for r in wp], [r["scipy_" + kind] for r in wp], "s-",
                      label="scipy solve_ivp DOP853 (Euler angles)")
            for r in wp:
                for m in MODELS + ("scipy",):
                    ax.annotate(f"{r['rtol']:.0e}", (r[m + "_s"], r[f"{m}_{kind}"]), fontsize=6,
                                textcoords="offset points", xytext=(4, 2))
            ax.set_xlabel("wall time of the run [s] (in process)")
            ax.set_ylabel(what + " at t = 1 s")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
        fig.suptitle("Classical top, regularised friction (eps = 1e-3 m/s), 1 s")
        fig.tight_layout()
        fig.savefig(os.path.join(o.out, "work_precision.png"))
    except ImportError:
        print("matplotlib missing: no PNG", flush=True)

    # The table: every tippetop run with its speed-up over MuJoCo RK4 at
    # dt = 1e-3 and (regularised law only: scipy has the same equations) over
    # scipy DOP853 at rtol 1e-8, whole process and in process.
    mj3 = mj["0.001"]["wall"]
    sp = res["scipy"]["wall"]
    lines = ["| tippetop run (classical, 10 s, rtol 1e-8) | whole process | in process | "
             "MuJoCo dt=1e-3 / whole | MuJoCo / in process | scipy / whole | scipy / in process |",
             "|---|---|---|---|---|---|---|"]
    for key, info in tt.items():
        model, law = key.split("/")
        sc_w = f"{sp / info['wall']:.0f}x" if law == "regularized" else "-"
        sc_i = f"{sp / info['in_process']:.0f}x" if law == "regularized" else "-"
        lines.append(f"| {model}, {law} ({info['rhs_evaluations']} evaluations) | {info['wall']*1e3:.2f} ms | "
                     f"{info['in_process']*1e3:.2f} ms | {mj3 / info['wall']:.1f}x | {mj3 / info['in_process']:.1f}x | "
                     f"{sc_w} | {sc_i} |")
    lines.append("")
    lines.append("| other run | wall time |")
    lines.append("|---|---|")
    lines.append(f"| tippetop reduced, regularised, whole process with plots | "
                 f"{tt['reduced/regularized']['wall_with_plots']*1e3:.1f} ms |")
    for dt, r in mj.items():
        lines.append(f"| MuJoCo {r['version']} RK4 dt = {float(dt):g} ({r['steps']} steps, in process) | {r['wall']*1e3:.1f} ms |")
    lines.append(f"| scipy DOP853 rtol 1e-8 (regularised, in process) | {sp*1e3:.0f} ms |")
    lines.append("")
    lines.append("Equal-error ratios (scipy time interpolated at tippetop's error, in process, work-precision runs of 1 s):")
    lines.append("")
    for key, rs in ratios.items():
        m, kind = key.split("/")
        what = "Euler-angle state error" if kind == "err" else "physical state error"
        lines.append(f"- {m}, {what}: " + ", ".join(f"{r['ratio']:.0f}x at rtol {r['rtol']:.0e}" for r in rs))
    table = "\n".join(lines)
    with open(os.path.join(o.out, "compare.md"), "w") as f:
        f.write(f"Machine: {res['machine']}\n\n{table}\n")
    with open(os.path.join(o.out, "compare.json"), "w") as f:
        json.dump(res, f, indent=1)
    print(table)


if __name__ == "__main__":
    main()
