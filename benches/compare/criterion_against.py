"""Issue #28's four speed cases in process: criterion, one tree's `simulate`
bench executable against another's, bench by bench.

Usage (from the repository root):

    cargo bench --locked -p tippetop --bench simulate --no-run      # prints the executable
    python3 benches/compare/criterion_against.py OLD_EXE NEW_EXE [--rounds 2] [--seconds 4] [--case N]

OLD_EXE is e.g. 47b3e75's (`git worktree add --detach /tmp/old 47b3e75`, then the
same `cargo bench ... --no-run` there). NEW_EXE runs the `_nopose` variants
(`simulate_with_pose(.., false, ..)`: the motion alone, as 47b3e75 integrated
it), unless OLD_EXE has them too.

For each bench: `--rounds` times old, new, new, old (the machine's speed drifts
by several per cent over minutes, so each bench's runs are kept together and
in that order; more, shorter rounds hold the drift better), each a criterion
run (1 s warm-up, `--seconds` of measurement) whose point estimate is kept. Prints a Markdown table of the medians and their ratio
(new / old: below 1 is faster). Not part of CI.
"""
import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time

BENCHES = [
    ("classical exact Coulomb, 10 s", "classical_10s_coulomb_rtol1e-8_vector"),
    ("the MuJoCo case (regularised, 10 s)", "classical_10s_regularized_rtol1e-8_vector"),
    ("nano (vector), 100 µs", "nano_100us_rtol1e-10_vector"),
    ("nano reduced, 100 µs", "nano_100us_rtol1e-10"),
]
UNIT = {"ns": 1e-6, "µs": 1e-3, "us": 1e-3, "ms": 1.0, "s": 1e3}


def names(exe):
    out = subprocess.run([exe, "--bench", "--list"], capture_output=True, text=True).stdout
    return {line.split(":")[0] for line in out.splitlines() if line.endswith(": benchmark")}


def estimate(exe, bench, cwd, seconds):
    """Criterion's point estimate [ms] of one bench."""
    out = subprocess.run(
        [exe, "--bench", f"^simulate/{re.escape(bench)}$", "--noplot",
         "--warm-up-time", "1", "--measurement-time", str(seconds)],
        capture_output=True, text=True, cwd=cwd,
    ).stdout
    m = re.search(r"time:\s+\[\S+ \S+ (\S+) (\S+) \S+ \S+\]", out)
    if not m:
        sys.exit(f"{exe}: no time for {bench}:\n{out}")
    return float(m.group(1)) * UNIT[m.group(2)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument(
        "--seconds", type=float, default=4.0, help="criterion's measurement time per run"
    )
    ap.add_argument(
        "--case", type=int, action="append", help="only this case (1-4; may be repeated)"
    )
    a = ap.parse_args()
    old, new = os.path.abspath(a.old), os.path.abspath(a.new)
    have_old, have_new = names(old), names(new)
    cwd = tempfile.mkdtemp()  # criterion's target/criterion goes here
    rows = []
    for i, (label, bench) in enumerate(BENCHES, 1):
        if a.case and i not in a.case:
            continue
        ob = bench + "_nopose" if f"simulate/{bench}_nopose" in have_old else bench
        nb = bench + "_nopose" if f"simulate/{bench}_nopose" in have_new else bench
        for exe, b, have in ((old, ob, have_old), (new, nb, have_new)):
            if f"simulate/{b}" not in have:
                sys.exit(f"{exe} has no bench simulate/{b}")
        t = ([], [])
        for _ in range(a.rounds):
            for k in (0, 1, 1, 0):
                t[k].append(estimate((old, new)[k], (ob, nb)[k], cwd, a.seconds))
        o, n = statistics.median(t[0]), statistics.median(t[1])
        rows.append((label, ob, nb, o, n))
        print(
            f"{label}: old {', '.join(f'{x:.3f}' for x in t[0])}; "
            f"new {', '.join(f'{x:.3f}' for x in t[1])} ms",
            file=sys.stderr,
        )
    print(
        f"{platform.node()}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}, "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
        f"{2 * a.rounds} criterion runs ({a.seconds:g} s each) of each bench and side, "
        "old-new-new-old\n"
    )
    print("| case | old bench | new bench | old [ms] | new [ms] | ratio |")
    print("|---|---|---|---|---|---|")
    for label, ob, nb, o, n in rows:
        print(f"| {label} | `{ob}` | `{nb}` | {o:.3f} | {n:.3f} | **{n / o:.3f}** |")


if __name__ == "__main__":
    main()
