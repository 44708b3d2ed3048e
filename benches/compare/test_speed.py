#!/usr/bin/env python3
"""The same tests, before and after: CPU seconds of the tests two checkouts share.

Issue #28 asks that "the same tests run no slower after the move than before
it". This runs the tests both checkouts have (matched by package and the test's
leaf name, unique in its package, since tests moved between files and
binaries), with `--exact`, in both checkouts, interleaved package by
package (old, new; new, old with --repeats), and counts the user + system CPU seconds of each run and of the processes it
starts (the CLI tests run the `tippetop` binary of their own checkout). CPU
seconds, not wall seconds: a shared machine's load changes the wall time far
more than the CPU time. Ignored tests are not run.

Usage (both checkouts' tests built first, `cargo test --workspace --no-run`):
    python3 benches/compare/test_speed.py OLD_CHECKOUT NEW_CHECKOUT [--repeats N]

It prints one line per package and the totals: the CPU seconds of each side
(the median of the repeats) and their ratio new/old.
"""

import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
from pathlib import Path


def binaries(root: Path) -> dict:
    """Test executables of a checkout by (package, target kind, target
    name), with the package's directory (cargo runs its tests from there),
    as `cargo test --no-run --message-format=json` names them."""
    r = subprocess.run(
        ["cargo", "test", "--workspace", "--locked", "--no-run", "--message-format=json"],
        capture_output=True,
        text=True,
        cwd=root,
    )
    if r.returncode != 0:
        sys.exit(f"cargo test --no-run failed in {root}:\n{r.stderr[-2000:]}")
    out = {}
    for line in r.stdout.splitlines():
        msg = json.loads(line)
        if msg.get("reason") != "compiler-artifact" or not msg.get("executable"):
            continue
        if not msg.get("profile", {}).get("test"):
            continue
        t = msg["target"]
        key = (msg["package_id"].split("#")[0].split("/")[-1], t["kind"][0], t["name"])
        out[key] = (Path(msg["executable"]), Path(t["src_path"]).parents[0])
    return out


def tests_of(exe: Path) -> set:
    r = subprocess.run(
        [str(exe), "--list", "--format", "terse"],
        capture_output=True,
        text=True,
        
    )
    if r.returncode != 0:
        return set()
    return {
        line[: -len(": test")]
        for line in r.stdout.splitlines()
        if line.endswith(": test")
    }


def cpu_of(exe: Path, names: list, cwd: Path) -> float:
    """User + system CPU seconds of running `names` (and their children)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(
        [str(exe), "--exact", "--test-threads=2", "-q", *names],
        capture_output=True,
        text=True,
        cwd=cwd,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"{exe} failed:\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def leaves(bins: dict) -> dict:
    """(package, the test's last path segment) -> (executable, full name),
    for the names that are unique in their package: tests moved between
    files or binaries (tests/rigid.rs into tests/physics/rigid.rs) keep
    their leaf name."""
    seen, dup = {}, set()
    for (package, _kind, _name), (exe, _) in bins.items():
        for full in tests_of(exe):
            key = (package, full.split("::")[-1])
            if key in seen:
                dup.add(key)
            seen[key] = (exe, full)
    return {k: v for k, v in seen.items() if k not in dup}


def run_side(chosen: list, root: Path, package: str) -> float:
    """CPU seconds of running the chosen (executable, full name) pairs,
    each executable once with its names."""
    by_exe = {}
    for exe, full in chosen:
        by_exe.setdefault(exe, []).append(full)
    return sum(cpu_of(exe, sorted(names), package_dir(root, package)) for exe, names in by_exe.items())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("--repeats", type=int, default=1)
    a = ap.parse_args()
    old, new = leaves(binaries(a.old)), leaves(binaries(a.new))
    common = sorted(set(old) & set(new))
    print(f"{len(old)} tests before, {len(new)} after (unique leaf names), {len(common)} in both")
    tot_old = tot_new = 0.0
    for package in sorted({k[0] for k in common}):
        keys = [k for k in common if k[0] == package]
        c_old, c_new = [], []
        for k in range(a.repeats):
            order = [(old, a.old, c_old), (new, a.new, c_new)]
            if k % 2:
                order.reverse()
            for side, root, acc in order:
                acc.append(run_side([side[key] for key in keys], root, package))
        mo, mn = statistics.median(c_old), statistics.median(c_new)
        tot_old += mo
        tot_new += mn
        ratio = mn / mo if mo else float("nan")
        print(f"{package:20} {len(keys):5} tests  {mo:8.2f} s -> {mn:8.2f} s  ({ratio:.3f}x)", flush=True)
    print(f"{'total':20} {len(common):5} tests  {tot_old:8.2f} s -> {tot_new:8.2f} s  ({tot_new / tot_old:.3f}x)")


def package_dir(root: Path, package: str) -> Path:
    """The package's directory (cargo runs a package's tests from there)."""
    for crate in (root / "crates").iterdir():
        if crate.name == package.split("@")[0]:
            return crate
    return root


if __name__ == "__main__":
    main()
