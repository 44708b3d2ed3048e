#!/usr/bin/env python3
"""The Python package's sweep against the CLI's (issue #17): the same sweep
(the classical top with regularised friction, N cases over top.offset, 2
threads) run by `tt.sweep` and by `tippetop sweep`, alternately, K times
each; prints the medians and their ratio, and checks the two give the same
numbers (bit for bit). Usage:

    python3 -m venv .venv && .venv/bin/pip install ./crates/tippetop-py
    cargo build --release
    .venv/bin/python benches/compare/py_sweep_bench.py [--cases N] [--repeats K]
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import tippetop as tt

ap = argparse.ArgumentParser()
ap.add_argument("--cases", type=int, default=2000)
ap.add_argument("--repeats", type=int, default=5)
ap.add_argument("--threads", type=int, default=2)
ap.add_argument("--bin", default=os.path.join(os.path.dirname(__file__), "../../target/release/tippetop"))
a = ap.parse_args()

sets = ["surface.friction_law=regularized", "surface.friction_eps=1e-3"]
sc = tt.Scenario.preset("classical").set_many({"surface.friction_law": "regularized", "surface.friction_eps": 1e-3})
lo, hi = 3e-4, 6e-3
py_times, cli_times = [], []
out = tempfile.mkdtemp(prefix="tippetop-pysweep-")
for r in range(a.repeats):
    t0 = time.perf_counter()
    sw = tt.sweep(sc, vary={"top.offset": (lo, hi, a.cases)}, threads=a.threads)
    py_times.append(time.perf_counter() - t0)
    cmd = [a.bin, "sweep", "--preset", "classical", "--quiet", "--threads", str(a.threads),
           "--vary", f"top.offset={lo}:{hi}:{a.cases}", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    cli_times.append(time.perf_counter() - t0)
    print(f"repeat {r}: python {py_times[-1]:.3f} s, cli {cli_times[-1]:.3f} s", flush=True)

rows = list(csv.DictReader(open(os.path.join(out, "sweep.csv"))))
same = all(
    float(row["theta_final"]) == x for row, x in zip(rows, sw["theta_final"])
) and len(rows) == len(sw["theta_final"])
mp, mc = statistics.median(py_times), statistics.median(cli_times)
print(f"cases {a.cases}, threads {a.threads}: median python {mp:.3f} s, cli {mc:.3f} s, "
      f"python/cli = {mp / mc:.3f}; same theta_final bit for bit: {same}")
sys.exit(0 if same else 1)
