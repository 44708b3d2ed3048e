#!/bin/bash
# Cost of Coulomb–Contensou friction (docs/physics.md#contensou) against the point law, measured as
# simulate()'s own wall time (summary.json `wall_seconds`), interleaved, ROUNDS rounds, medians.
# usage: benches/compare/contensou.sh [ROUNDS]   (from the repository root, after
#        cargo build --release -p tippetop-cli)
set -e
ROUNDS=${1:-7}
B=$(pwd)/target/release/tippetop
D=$(mktemp -d)
cd "$D"
printf 'preset = "classical"\n' > point.toml
printf 'preset = "classical"\n[surface]\nfriction_law = "regularized"\nfriction_eps = 1e-2\n' > reg.toml
printf 'preset = "classical"\n[surface]\nfriction_law = "contensou"\ncontact_radius = 3e-4\n' > contensou.toml
printf 'preset = "classical"\n[surface]\nfriction_law = "contensou_pade"\ncontact_radius = 3e-4\n' > pade.toml
# The eccentric top of tests/physics/contensou.rs that sticks and slips five times in 2 s.
stick='preset = "classical"\n[surface]\nfriction = 0.03\nfriction_law = "%s"\ncontact_radius = 3e-4\n[initial]\ntheta = 0.5\nprecession = 5.0\nspin = -1.3095568271708822\nuy = 0.03737699519875277\n[solver]\nt_end = 2.0\n'
printf "$stick" contensou > stick.toml
printf "$stick" contensou_pade > stick_pade.toml
for r in $(seq "$ROUNDS"); do
  for s in point reg contensou pade stick stick_pade; do
    for m in vector rigid; do
      "$B" run $s.toml --out out --no-plot --set solver.model=\"$m\" > /dev/null
      python3 -c "import json; d=json.load(open('out/summary.json')); print('$s $m', d['wall_seconds'], d['steps'], d['rhs_evaluations'])"
    done
  done
done > times.txt
python3 - <<'PY'
import statistics, collections
d = collections.defaultdict(list); n = {}
for l in open('times.txt'):
    s, m, w, st, rhs = l.split()
    d[(s, m)].append(float(w)); n[(s, m)] = (int(st), int(rhs))
print("| model | run | simulate() median [ms] | min–max | steps | rhs | per rhs [µs] | / point law |")
print("|---|---|---|---|---|---|---|---|")
for m in ["vector", "rigid"]:
    base = statistics.median(d[("point", m)])
    for s in ["point", "reg", "contensou", "pade", "stick", "stick_pade"]:
        v = d[(s, m)]; med = statistics.median(v); st, rhs = n[(s, m)]
        print(f"| {m} | {s} | {1e3*med:.2f} | {1e3*min(v):.2f}–{1e3*max(v):.2f} | {st} | {rhs} | {1e6*med/rhs:.3f} | {med/base:.1f} |")
PY
rm -rf "$D"
