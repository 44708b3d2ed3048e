"""Issue #28's four speed cases, one binary against another, whole process.

Usage (from the repository root, after `cargo build --release`):

    python3 benches/compare/against.py OLD_BIN [NEW_BIN] [--reps 21] [--callgrind] [--case N] [--loops K]

OLD_BIN is e.g. 47b3e75's release binary (built from `git worktree add
--detach /tmp/old 47b3e75`); NEW_BIN defaults to target/release/tippetop.
The new binary runs with `--no-pose` (the 17 columns 47b3e75 writes,
docs/performance.md#pose) unless OLD_BIN knows that flag too.

For each case: the steps and right-hand-side evaluations of both runs
(summary.json; they must be equal, the same work), optionally their
instruction counts (`valgrind --tool=callgrind`), then `--reps` whole-process
runs of each, interleaved (old, new, new, old, old, new, ...), each timed by wall clock
and by the CPU time the kernel accounts to it (user + system, from
`os.wait4`). Prints a Markdown table of the medians and their ratios
(new / old: below 1 is faster). Not part of CI.
"""
import argparse
import json
import os
import platform
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

CASES = [
    (
        "classical (exact Coulomb), 200 s",
        "run --preset classical --set solver.t_end=200 --no-plot",
    ),
    (
        "classical regularised, 10 s (the MuJoCo case)",
        'run --preset classical --set surface.friction_law="regularized" '
        "--set surface.friction_eps=1e-3 --set solver.rtol=1e-8 --set solver.t_end=10 --no-plot",
    ),
    ("nano (vector), 1 ms", "run --preset nano --set solver.t_end=1e-3 --no-plot"),
    (
        "nano reduced, 1 ms",
        'run --preset nano --set solver.model="reduced" --set solver.t_end=1e-3 --no-plot',
    ),
]


def knows_no_pose(binary):
    out = subprocess.run([binary, "run", "--help"], capture_output=True, text=True).stdout
    return "--no-pose" in out


def argv(binary, args, out, no_pose):
    a = [binary, "-q"] + shlex.split(args) + ["--out", out]
    if no_pose:
        a.append("--no-pose")
    return a


def timed(cmd):
    """Wall [s], user + system CPU [s] of one run of `cmd` (exit 0 required)."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().decode()
    p.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"{' '.join(cmd)} failed: {err}")
    return wall, ru.ru_utime + ru.ru_stime


def work(out):
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return s.get("steps"), s.get("rhs_evaluations")


def instructions(cmd):
    env = dict(os.environ, TIPPETOP_CHECKPOINT_SECONDS="86400")
    r = subprocess.run(
        ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null"] + cmd,
        capture_output=True,
        text=True,
        env=env,
    )
    m = re.search(r"Collected : (\d+)", r.stderr)
    return int(m.group(1)) if m else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new", nargs="?", default="target/release/tippetop")
    ap.add_argument("--reps", type=int, default=21)
    ap.add_argument("--callgrind", action="store_true")
    ap.add_argument(
        "--loops",
        type=int,
        default=1,
        help="repeat the timed runs this many times and print each loop's wall ratio "
        "(the table shows the medians over all runs)",
    )
    ap.add_argument(
        "--case",
        type=int,
        action="append",
        help="run only this case (1-4, in the table's order; may be repeated)",
    )
    a = ap.parse_args()
    old, new = os.path.abspath(a.old), os.path.abspath(a.new)
    pose_old, pose_new = knows_no_pose(old), knows_no_pose(new)
    tmp = tempfile.mkdtemp()
    # Both programs run from fresh copies made the same way: the page cache
    # holds a file in folios whose sizes depend on how it was written (a
    # linker's output against a copy), and the same bytes then start with
    # different numbers of page faults (190 against 177 here).
    for k, src in enumerate((old, new)):
        dst = os.path.join(tmp, f"bin{k}")
        shutil.copy2(src, dst)
        if k == 0:
            old = dst
        else:
            new = dst
    rows = []
    for i, (name, args) in enumerate(CASES, 1):
        if a.case and i not in a.case:
            continue
        o, n = os.path.join(tmp, "old"), os.path.join(tmp, "new")
        co, cn = argv(old, args, o, pose_old), argv(new, args, n, pose_new)
        timed(co), timed(cn)  # warm the page cache; also checks the runs
        wo, wn = work(o), work(n)
        if wo != wn:
            sys.exit(f"{name}: not the same work (steps, rhs) {wo} against {wn}")
        ir = (instructions(co), instructions(cn)) if a.callgrind else (None, None)
        walls, cpus = ([], []), ([], [])
        per_loop = []
        for _ in range(a.loops):
            lw = ([], [])
            for r in range(a.reps):
                # ABBA order: each binary follows itself as often as the other
                # (a process right after one of the same binary starts faster,
                # its code still in the CPU's caches: 3-5 % here).
                for k in (0, 1) if r % 2 == 0 else (1, 0):
                    w, c = timed((co, cn)[k])
                    walls[k].append(w)
                    cpus[k].append(c)
                    lw[k].append(w)
            per_loop.append(statistics.median(lw[1]) / statistics.median(lw[0]))
        med = [statistics.median(x) for x in walls + cpus]
        rows.append((name, wn, ir, med, per_loop))
        print(f"{name}: done", file=sys.stderr)
    print(
        f"{platform.node()}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}, "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {a.reps} runs each, interleaved; "
        f"new {'with' if pose_new and not pose_old else 'without'} --no-pose\n"
    )
    print("| case | steps / RHS | Ir old | Ir new | ratio | wall old / new [ms] | ratio | CPU old / new [ms] | ratio |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (steps, rhs), (io, inn), (wo, wn, co, cn), _ in rows:
        irs = (
            f"{io / 1e6:.2f} M | {inn / 1e6:.2f} M | **{inn / io:.3f}**"
            if io and inn
            else "– | – | –"
        )
        print(
            f"| {name} | {steps} / {rhs} | {irs} | {wo * 1e3:.1f} / {wn * 1e3:.1f} | "
            f"**{wn / wo:.3f}** | {co * 1e3:.1f} / {cn * 1e3:.1f} | **{cn / co:.3f}** |"
        )
    if a.loops > 1:
        print(f"\nWall ratio (new / old) of each loop of {a.reps} runs of each:")
        for name, _, _, _, per_loop in rows:
            print(
                f"- {name}: {', '.join(f'{x:.3f}' for x in per_loop)} "
                f"(range {min(per_loop):.3f}-{max(per_loop):.3f})"
            )


if __name__ == "__main__":
    main()
