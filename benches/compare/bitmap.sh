#!/usr/bin/env bash
# Bit design maps (issue #16 item 4): the cost of a grid point of the nano bit with 20 us
# phases (scenarios/bit/nano.toml, hold 5 us, 81 rows: the least the hold check takes),
# whole process (GNU time: wall %e, CPU %U + %S, peak RSS %M), against the trajectories alone:
# `tippetop sweep` of the same runs (the bit's scenario.toml, the write window as force.0)
# on the same grid and threads. Also one bit run's simulate() time (summary.json's
# wall_seconds of `tippetop run`) against the output rows (which cap the step size).
# Usage (from the repository root, after `cargo build --release`):
#     benches/compare/bitmap.sh [N...]     (N x N grids; default: 100)
# Prints Markdown tables. Not part of CI.
set -euo pipefail
B=${TIPPETOP:-target/release/tippetop}
NS=("${@:-100}")
read -r -a NS <<<"${NS[*]}"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
BIT=(scenarios/bit/nano.toml --set bit.phase=2e-5 --set bit.hold=5e-6 --set write.0.stop=2e-5
  --set erase.0.stop=2e-5 --set solver.samples=81)
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
echo
"$B" bit "${BIT[@]}" --quiet --out "$OUT/one"
echo "| rows (solver.samples) | simulate() [ms] | accepted steps | rhs evaluations |"
echo "|---|---|---|---|"
for s in 2001 401 81; do
  "$B" run "$OUT/one/scenario.toml" --set solver.samples=$s --no-plot --quiet --out "$OUT/r$s"
  python3 - "$OUT/r$s/summary.json" "$s" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {d['wall_seconds'] * 1e3:.3f} | {d['steps']} | {d['rhs_evaluations']} |")
PY
done
echo
echo "| grid | what | points | wall [s] | CPU [s] | CPU per point [ms] | peak RSS [kB] | map CPU / sweep CPU | mean steps |"
echo "|---|---|---|---|---|---|---|---|---|"
for n in "${NS[@]}"; do
  for grid in "hy,stop" "hy,hx"; do
    if [ "$grid" = "hy,stop" ]; then
      MV=(--vary write.0.hy=0:2e-22:$n --vary write.0.stop=2e-6:2e-5:$n)
      SV=(--vary force.0.hy=0:2e-22:$n --vary force.0.stop=2e-6:2e-5:$n)
    else
      MV=(--vary write.0.hy=0:1e-21:$n --vary write.0.hx=-5e-22:5e-22:$n)
      SV=(--vary force.0.hy=0:1e-21:$n --vary force.0.hx=-5e-22:5e-22:$n)
    fi
    /usr/bin/time -f "%e %U %S %M" -o "$OUT/tm" "$B" bit "${BIT[@]}" "${MV[@]}" --threads 2 \
      --quiet --out "$OUT/map"
    /usr/bin/time -f "%e %U %S %M" -o "$OUT/ts" "$B" sweep "$OUT/one/scenario.toml" "${SV[@]}" \
      --threads 2 --quiet --out "$OUT/sweep"
    python3 - "$OUT" "$grid" "$n" <<'PY'
import csv, sys
out, grid, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
pts = n * n
def t(f):
    w, u, s, m = open(f"{out}/{f}").read().split()
    return float(w), float(u) + float(s), int(m)
mw, mc, mm = t("tm")
sw, sc, sm = t("ts")
rows = list(csv.DictReader(open(f"{out}/sweep/sweep.csv")))
steps = sum(int(r["steps"]) for r in rows) / len(rows)
print(f"| {grid} {n}x{n} | bit --vary | {pts} | {mw:.2f} | {mc:.2f} | {mc / pts * 1e3:.3f} | {mm} | {mc / sc:.3f} | |")
print(f"| {grid} {n}x{n} | sweep (trajectories) | {pts} | {sw:.2f} | {sc:.2f} | {sc / pts * 1e3:.3f} | {sm} | | {steps:.0f} |")
PY
  done
done
echo
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
