"""Langevin dynamics of the vector model in numpy, vectorised over N independent runs, against
tippetop on the same machine in the same run. See README.md in this folder.

The equations are tippetop's (docs/physics.md#vector-model with mu = 0, §vertical-load-§adhesion the adhesion as a
vertical load at the contact, §wells the Gaussian wells, §langevin the Langevin scheme), written afresh:
state (16, N), component-major, in scaled units m = R = 1 and the time unit 1/max(gamma_t,
gamma_r); one step is O(h/2) RK4(h) O(h/2), O the exact Ornstein-Uhlenbeck step of the five
generalised velocities in the basis (X, Y | k, e, f) where mass and friction matrices are
diagonal. Normals: numpy's default generator (PCG64, ziggurat), 10 per run and step, one call.
Only the uncoupled O step (no contact damping) and a constant applied force.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/compare/langevin_numpy.py [--out docs/perf] [--quick]

1. checks: at T = 0 (damping on) the deterministic part against tippetop's trajectory.csv of
   the same scenario (theta, omega, x, y at 41 samples over 10 000 steps); at 300 K
   equipartition of the five modes (M_i p_i^2 = kT) over an ensemble;
2. timing: steps x runs per second for N = 1 ... 1e5 (nano-physical preset; and the preset
   without adhesion and well) against tippetop's single-core steps per second (in process,
   `wall_seconds` of summary.json, best of --repeats; the vector model and the rigid one,
   whose Langevin scheme in contact solves the same equations) and two tippetop processes at
   once; the N where numpy's rate reaches tippetop's.

Writes langevin_numpy.json and langevin_numpy.md into --out. Not part of CI.
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
import tomllib

import numpy as np

KB = 1.380649e-23
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# ---------------------------------------------------------------- the model

class Model:
    """The vector model's on-plane Langevin dynamics with mu = 0, scaled units (m = R = 1)."""

    def __init__(self, sc):
        top, th = sc["top"], sc["thermal"]
        R, m = top["radius"], top["mass"]
        self.R, self.m = R, m
        gt, gr = th["damping_translational"], th["damping_rotational"]
        self.tu = 1.0 / max(gt, gr)  # time unit [s]
        tu = self.tu
        self.a = top["offset"] / R
        self.A = top["inertia_transverse"] / (m * R * R)
        self.C = top["inertia_axial"] / (m * R * R)
        force = lambda f: f * tu * tu / (m * R)  # noqa: E731
        energy = lambda e: e * tu * tu / (m * R * R)  # noqa: E731
        self.g = force(sc["surface"]["gravity"] * m)
        adh = sc.get("adhesion", {})
        self.fa = force(adh.get("force", 0.0))
        forces = sc.get("force", [])
        assert len(forces) <= 1 and all(f.get("start", 0.0) == 0.0 for f in forces), \
            "one constant applied force only"
        self.hx = force(forces[0]["hx"]) if forces else 0.0
        self.hy = force(forces[0]["hy"]) if forces else 0.0
        self.wells = [(w["theta"], energy(w["depth"]), w["width"]) for w in sc.get("well", [])]
        assert sc["surface"]["friction"] == 0.0, "mu = 0 only"
        assert th.get("damping_contact", 0.0) == 0.0, "no contact damping"
        self.kt = energy(KB * th["temperature"])
        self.gt, self.gr = gt * tu, gr * tu
        self.h = sc["solver"]["dt"] / tu
        self.steps = math.ceil(sc["solver"]["t_end"] / sc["solver"]["dt"] - 1e-9)
        self.h = sc["solver"]["t_end"] / self.steps / tu
        self.gyro = (self.C - self.A) / self.A
        self.dinv = 1.0 / self.C - 1.0 / self.A
        i = sc["initial"]
        self.initial = (i["theta"], i["theta_dot"] * tu, i["precession"] * tu, i["spin"] * tu,
                        i["ux"] * tu / R, i["uy"] * tu / R)

    def initial_state(self, n):
        th, thd, om, w, ux, uy = self.initial
        s, c = math.sin(th), math.cos(th)
        y0 = [s, 0.0, c, (w - om * c) * s, thd, om * s * s + w * c, ux, uy, 0.0, 0.0,
              math.cos(0.5 * th), 0.0, math.sin(0.5 * th), 0.0, 0.0, 0.0]
        return np.tile(np.array(y0)[:, None], (1, n))

    def rhs(self, y):
        a, A = self.a, self.A
        k0, k1, k2, w0, w1, w2, vx, vy = y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7]
        kd0 = w1 * k2 - w2 * k1
        kd1 = w2 * k0 - w0 * k2
        kd2 = w0 * k1 - w1 * k0
        wk = w0 * k0 + w1 * k1 + w2 * k2
        r0, r1, r2 = a * k0, a * k1, a * k2 - 1.0
        wr0 = w1 * r2 - w2 * r1
        wr1 = w2 * r0 - w0 * r2
        # The applied force H in the world frame (x-hat along the axis's horizontal projection).
        kh2 = k0 * k0 + k1 * k1
        inv = 1.0 / np.sqrt(kh2)
        xh0, xh1 = k0 * inv, k1 * inv
        hw0 = self.hx * xh0 - self.hy * xh1
        hw1 = self.hx * xh1 + self.hy * xh0
        # w0 = -(C - A)/A (w.k) k-dot, plus the wells' torque over A.
        gk = -self.gyro * wk
        a0, a1, a2 = gk * kd0, gk * kd1, gk * kd2
        if self.wells:
            kh = np.hypot(k0, k1)
            th = np.arctan2(kh, k2)
            tq = 0.0
            for t0, d, wd in self.wells:
                x = (th - t0) / wd
                tq = tq - d * x / wd * np.exp(-0.5 * x * x)
            ty = tq / kh / A
            a0 = a0 - k1 * ty
            a1 = a1 + k0 * ty
        # e = k x Z = (k1, -k0, 0); u = (e x r)/A.
        u0, u1, u2 = -k0 * r2 / A, -k1 * r2 / A, (k1 * r1 + k0 * r0) / A
        wkdz = w0 * kd1 - w1 * kd0
        q = self.g + a * (hw0 * u0 + hw1 * u1 - (a0 * k1 - a1 * k0) - wkdz)
        d0 = 1.0 + a * u2
        if self.fa != 0.0:
            q = q + self.fa * d0
        normal = q / d0
        f0, f1, f2 = -hw0, -hw1, normal - self.fa
        # r x F, then I^-1 (r x F).
        t0 = r1 * f2 - r2 * f1
        t1 = r2 * f0 - r0 * f2
        t2 = r0 * f1 - r1 * f0
        tk = self.dinv * (t0 * k0 + t1 * k1 + t2 * k2)
        wd0 = a0 + t0 / A + tk * k0
        wd1 = a1 + t1 / A + tk * k1
        wd2 = a2 + t2 / A + tk * k2
        qw, qx, qy, qz = y[10], y[11], y[12], y[13]
        dy = np.empty_like(y)
        dy[0], dy[1], dy[2] = kd0, kd1, kd2
        dy[3], dy[4], dy[5] = wd0, wd1, wd2
        dy[6], dy[7] = f0, f1
        dy[8] = 0.0
        dy[9] = -hw0 * (vx + wr0) - hw1 * (vy + wr1)
        dy[10] = 0.5 * (-w0 * qx - w1 * qy - w2 * qz)
        dy[11] = 0.5 * (w0 * qw + w1 * qz - w2 * qy)
        dy[12] = 0.5 * (w1 * qw + w2 * qx - w0 * qz)
        dy[13] = 0.5 * (w2 * qw + w0 * qy - w1 * qx)
        dy[14], dy[15] = vx, vy
        return dy

    def kinetic(self, y):
        a, A, C = self.a, self.A, self.C
        k0, k1, k2, w0, w1, w2 = y[0], y[1], y[2], y[3], y[4], y[5]
        vz = -a * (w0 * k1 - w1 * k0)
        wk = w0 * k0 + w1 * k1 + w2 * k2
        wiw = A * (w0 * w0 + w1 * w1 + w2 * w2) + (C - A) * wk * wk
        return 0.5 * (y[6] * y[6] + y[7] * y[7] + vz * vz) + 0.5 * wiw

    def basis(self, y):
        """(k-hat, e-hat, f-hat) as arrays (3, N) and sin^2 theta."""
        k = y[0:3]
        kn = k / np.sqrt((k * k).sum(axis=0))
        e = np.stack([kn[1], -kn[0], np.zeros_like(kn[0])])
        s2 = e[0] * e[0] + e[1] * e[1]
        ok = s2 > 0.0
        eh = np.where(ok, e / np.sqrt(np.where(ok, s2, 1.0)), np.array([1.0, 0.0, 0.0])[:, None])
        fh = np.cross(kn, eh, axis=0)
        return kn, eh, fh, s2

    def ou(self, y, tau, xi):
        """The exact Ornstein-Uhlenbeck step over tau at fixed axis, in place; xi (5, N)."""
        if self.kt == 0.0 and self.gt == 0.0 and self.gr == 0.0:
            return
        e0 = self.kinetic(y)

        def factors(rate, mass):
            return np.exp(-rate * tau), np.sqrt(-(self.kt / mass) * np.expm1(-2.0 * rate * tau))

        dt_, at_ = factors(self.gt, 1.0)
        y[6:8] = dt_ * y[6:8] + at_ * xi[0:2]
        kn, eh, fh, s2 = self.basis(y)
        beta = self.a * self.a * s2
        rate_e = (self.gr * self.A + self.gt * beta) / (self.A + beta)
        w = y[3:6]
        for j, (d, (dec, amp)) in enumerate([
                (kn, factors(self.gr, self.C)),
                (eh, factors(rate_e, self.A + beta)),
                (fh, factors(self.gr, self.A))]):
            x = (w * d).sum(axis=0)
            dx = dec * x + amp * xi[2 + j] - x
            w += dx * d
        y[8] += self.kinetic(y) - e0

    def step(self, y, xi):
        h = self.h
        self.ou(y, 0.5 * h, xi[0:5])
        k1 = self.rhs(y)
        k2 = self.rhs(y + 0.5 * h * k1)
        k3 = self.rhs(y + 0.5 * h * k2)
        k4 = self.rhs(y + h * k3)
        y += h / 6.0 * (k1 + 2.0 * (k2 + k3) + k4)
        self.ou(y, 0.5 * h, xi[5:10])

    def run(self, n, steps, seed=1, every=None, observe=None):
        rng = np.random.default_rng(seed)
        y = self.initial_state(n)
        for s in range(steps):
            xi = rng.standard_normal((10, n))
            self.step(y, xi)
            if every and (s + 1) % every == 0 and observe:
                observe(s + 1, y)
        return y

    def modes(self, y):
        """M_i p_i^2 of the five modes (kT each in equilibrium), arrays (N,)."""
        kn, eh, fh, s2 = self.basis(y)
        w = y[3:6]
        beta = self.a * self.a * s2
        pk, pe, pf = ((w * d).sum(axis=0) for d in (kn, eh, fh))
        return [y[6] ** 2, y[7] ** 2, self.C * pk ** 2, (self.A + beta) * pe ** 2, self.A * pf ** 2]


# ---------------------------------------------------------------- tippetop

def tippetop(binary, args, out):
    subprocess.run([binary, "run", *args, "--no-plot", "--quiet", "--out", out], check=True)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "scenario.toml"), "rb") as f:
        scenario = tomllib.load(f)
    return summary, scenario


def trajectory(out):
    data = np.genfromtxt(os.path.join(out, "trajectory.csv"), delimiter=",", names=True)
    return data


def simple_toml(tmp, binary):
    """The nano-physical preset's scenario.toml without [adhesion] and [[well]]."""
    out = os.path.join(tmp, "preset")
    tippetop(binary, ["--preset", "nano-physical"], out)
    text = open(os.path.join(out, "scenario.toml")).read()
    keep, skip = [], False
    for line in text.splitlines():
        if line.startswith("["):
            skip = line.strip() in ("[adhesion]", "[[well]]")
        if not skip:
            keep.append(line)
    path = os.path.join(tmp, "simple.toml")
    with open(path, "w") as f:
        f.write("\n".join(keep) + "\n")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tippetop", default=os.path.join(ROOT, "target", "release", "tippetop"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "perf"))
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="fewer N, shorter runs (smoke test)")
    ap.add_argument("--equipartition-runs", type=int, default=4000)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    res = {
        "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "cpus": os.cpu_count(), "python": sys.version.split()[0],
                    "numpy": np.__version__},
        "load_before": os.getloadavg(),
    }
    try:
        res["machine"]["cpu_model"] = next(
            ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo") if ln.startswith("model name"))
    except (OSError, StopIteration):
        pass
    with tempfile.TemporaryDirectory() as tmp:
        simple = simple_toml(tmp, args.tippetop)
        case_args = {"nano_physical": ["--preset", "nano-physical"], "simple": [simple]}

        # 1a. T = 0 (damping on): the deterministic part and the damping, against tippetop.
        checks = {}
        for name, cargs in case_args.items():
            out = os.path.join(tmp, f"t0_{name}")
            _, sc = tippetop(args.tippetop, [*cargs, "--set", "thermal.temperature=0",
                                             "--set", "solver.t_end=4e-11",
                                             "--set", "solver.samples=41"], out)
            tr = trajectory(out)
            m = Model(sc)
            every = m.steps // 40
            rows = []

            def obs(s, y, rows=rows, m=m):
                k = y[0:3, 0]
                rows.append([math.atan2(math.hypot(k[0], k[1]), k[2]),
                             (y[3:6, 0] @ k) / m.tu, y[14, 0] * m.R, y[15, 0] * m.R])
            m.run(1, m.steps, every=every, observe=obs)
            got = np.array(rows)
            ref = np.stack([tr["theta"][1:], tr["omega"][1:], tr["x"][1:], tr["y"][1:]], axis=1)
            scale = np.maximum(np.abs(ref).max(axis=0), 1e-300)
            err = (np.abs(got - ref) / scale).max(axis=0)
            checks[name] = {"steps": m.steps, "max_rel_error": dict(zip(["theta", "omega", "x", "y"],
                                                                        err.tolist())),
                            "ranges": dict(zip(["theta", "omega", "x", "y"], scale.tolist()))}
            print(f"T = 0 check {name}: max error / range {dict(zip(['theta', 'omega', 'x', 'y'], err))}")
        res["deterministic_check"] = checks

        # 1b. Equipartition at 300 K: each mode's M_i p_i^2 over the ensemble at the last step.
        # From the preset's initial state (theta = 0.1): without the well the velocities are in
        # equilibrium after ~10/gamma (3 000 steps are 26/gamma); with it the top first falls
        # into the well at pi/2 (its theta_dot is not yet thermal after 4 ps: it takes ~40 ps),
        # so that case runs 15 000 steps (60 ps).
        eqs = {}
        for name, cargs in case_args.items():
            out = os.path.join(tmp, f"eq_{name}")
            _, sc = tippetop(args.tippetop, [*cargs, "--set", "solver.t_end=4e-15",
                                             "--set", "solver.samples=2"], out)
            m = Model(sc)
            n_eq = 500 if args.quick else args.equipartition_runs
            steps_eq = {"nano_physical": 15000, "simple": 3000}[name] // (3 if args.quick else 1)
            y = m.run(n_eq, steps_eq, seed=7)
            eq = []
            for label, v in zip(["m ux^2", "m uy^2", "C omega^2", "(A + m a^2 s^2) theta_dot^2",
                                 "A (Omega sin theta)^2"], m.modes(y)):
                mean, se = v.mean() / m.kt, v.std(ddof=1) / math.sqrt(n_eq) / m.kt
                eq.append({"mode": label, "mean_over_kT": mean, "stderr": se, "z": (mean - 1.0) / se})
                print(f"equipartition {name} {label}: <.>/kT = {mean:.4f} +- {se:.4f} (z = {(mean - 1) / se:+.2f})")
            eqs[name] = {"runs": n_eq, "steps": steps_eq, "modes": eq}
        res["equipartition"] = eqs

        # 2. Timing.
        ns = [1, 10, 100, 1000, 10000] if args.quick else [1, 10, 100, 1000, 10000, 100000]
        timing = {}
        for name, cargs in case_args.items():
            # tippetop, one process (in process: wall_seconds), best of --repeats; the vector
            # model, then the rigid one (its Langevin scheme in bilateral contact).
            def best_rate(extra, label):
                best, steps, sc = math.inf, None, None
                for r in range(args.repeats):
                    s, sc = tippetop(args.tippetop, [*cargs, *extra], os.path.join(tmp, f"tt_{label}"))
                    best = min(best, s["wall_seconds"])
                    steps = s["steps"]
                return steps / best, steps, sc
            tt_rigid, _, _ = best_rate(["--set", 'solver.model="rigid"'], f"{name}_rigid")
            tt1, steps, sc = best_rate([], name)
            # Two processes at once (2 cores): their summed rate, best of --repeats.
            best2 = 0.0
            for r in range(args.repeats):
                procs = [subprocess.Popen([args.tippetop, "run", *cargs, "--no-plot", "--quiet", "--out",
                                           os.path.join(tmp, f"tt2_{name}_{j}")]) for j in range(2)]
                for p in procs:
                    assert p.wait() == 0
                rate = sum(steps / json.load(open(os.path.join(tmp, f"tt2_{name}_{j}", "summary.json")))
                           ["wall_seconds"] for j in range(2))
                best2 = max(best2, rate)
            m = Model(sc)
            rows = []
            for n in ns:
                steps_n = max(10, min(5000, int((2e5 if args.quick else 1e6) / n)))
                m.run(n, 2)  # warm-up
                best_np = math.inf
                for r in range(1 if args.quick or n >= 10000 else 3):
                    t0 = time.perf_counter()
                    m.run(n, steps_n)
                    best_np = min(best_np, time.perf_counter() - t0)
                rate = n * steps_n / best_np
                rows.append({"n": n, "steps": steps_n, "seconds": best_np, "steps_runs_per_s": rate,
                             "tippetop_1_over_numpy": tt1 / rate})
                print(f"{name} numpy N = {n}: {rate:.3e} steps*runs/s (tippetop 1 core {tt1:.3e}: x{tt1 / rate:.1f})")
            catch = next((r["n"] for r in rows if r["steps_runs_per_s"] >= tt1), None)
            catch_rigid = next((r["n"] for r in rows if r["steps_runs_per_s"] >= tt_rigid), None)
            timing[name] = {"tippetop_steps": steps, "tippetop_1_core_steps_per_s": tt1,
                            "tippetop_rigid_1_core_steps_per_s": tt_rigid,
                            "numpy_catches_up_with_rigid_at_n": catch_rigid,
                            "tippetop_2_processes_steps_per_s": best2,
                            "two_process_speedup": best2 / tt1, "numpy": rows,
                            "numpy_catches_up_at_n": catch}
            print(f"{name}: tippetop 1 process {tt1:.3e} steps/s, 2 processes {best2:.3e} (x{best2 / tt1:.2f});"
                  f" numpy catches up at N = {catch}")
        res["timing"] = timing
    res["load_after"] = os.getloadavg()
    with open(os.path.join(args.out, "langevin_numpy.json"), "w") as f:
        json.dump(res, f, indent=2)
    md = [f"# Langevin: tippetop vs numpy ({res['date']})", "",
          f"Machine: {res['machine'].get('cpu_model', '?')}, {res['machine']['cpus']} CPUs; numpy "
          f"{np.__version__}; load before {res['load_before'][0]:.2f}, after {res['load_after'][0]:.2f}.", ""]
    md += ["## Checks", "", "T = 0 (damping on), 10 000 steps, numpy against tippetop's trajectory.csv "
           "(max |difference| / max |value| over 40 samples):", "",
           "| case | theta | omega | x | y |", "|---|---|---|---|---|"]
    md += [f"| {n} | " + " | ".join(f"{c['max_rel_error'][q]:.1e}" for q in ("theta", "omega", "x", "y")) + " |"
           for n, c in res["deterministic_check"].items()]
    md += ["", "Equipartition at 300 K, <M_i p_i^2>/kT over the ensemble at the last step (1 is exact):", "",
           "| case | runs | steps | " + " | ".join(q["mode"] for q in next(iter(res["equipartition"].values()))["modes"])
           + " |", "|---|---|---|---|---|---|---|---|"]
    md += [f"| {n} | {e['runs']} | {e['steps']} | "
           + " | ".join(f"{q['mean_over_kT']:.3f} +- {q['stderr']:.3f}" for q in e["modes"]) + " |"
           for n, e in res["equipartition"].items()]
    md.append("")
    for name, t in timing.items():
        md += [f"## {name}", "",
               f"tippetop: {t['tippetop_1_core_steps_per_s']:.3e} steps/s (1 process), "
               f"{t['tippetop_2_processes_steps_per_s']:.3e} (2 processes, x{t['two_process_speedup']:.2f}); "
               f"numpy catches up at N = {t['numpy_catches_up_at_n']}; rigid model "
               f"{t['tippetop_rigid_1_core_steps_per_s']:.3e} steps/s (1 process), numpy catches up at "
               f"N = {t['numpy_catches_up_with_rigid_at_n']}", "",
               "| N | numpy steps x runs / s | tippetop (1 core) / numpy |", "|---|---|---|"]
        md += [f"| {r['n']} | {r['steps_runs_per_s']:.3e} | {r['tippetop_1_over_numpy']:.2f} |" for r in t["numpy"]]
        md.append("")
    with open(os.path.join(args.out, "langevin_numpy.md"), "w") as f:
        f.write("\n".join(md))


if __name__ == "__main__":
    main()
