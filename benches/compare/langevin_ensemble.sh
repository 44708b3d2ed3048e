#!/usr/bin/env bash
# Langevin ensembles: steps per second on 1 and 2 threads and the peak memory against the
# number of runs N (`tippetop ensemble`, whole process, GNU time's %e and %M), the
# nano-physical preset cut to 10 000 steps (40 ps, 41 samples) per run, both models.
# Also checks that 1 and 2 threads write the same ensemble.csv and histograms.csv.
# Usage (from the repository root, after `cargo build --release`):
#     benches/compare/langevin_ensemble.sh [RUNS...]        (default: 50 200 800)
# Prints a Markdown table. Not part of CI.
set -euo pipefail
B=${TIPPETOP:-target/release/tippetop}
RUNS=("${@:-50 200 800}")
read -r -a RUNS <<<"${RUNS[*]}"
STEPS=10000
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
echo
echo "| model | runs N | threads | wall [s] | steps/s | peak RSS [kB] | 2 threads / 1 | same bytes |"
echo "|---|---|---|---|---|---|---|---|"
for model in vector rigid; do
  for n in "${RUNS[@]}"; do
    declare -A wall=()
    for th in 1 2; do
      /usr/bin/time -f "%e %M" -o "$OUT/time" "$B" ensemble --preset nano-physical \
        --set solver.model="\"$model\"" --set solver.t_end=4e-11 --set solver.samples=41 \
        --runs "$n" --threads "$th" --quiet --out "$OUT/e$th"
      read -r w rss <"$OUT/time"
      wall[$th]=$w
      rate=$(python3 -c "print(f'{$n * $STEPS / $w:.3e}')")
      if [ "$th" = 2 ]; then
        ratio=$(python3 -c "print(f'{${wall[1]} / $w:.2f}')")
        same=no
        cmp -s "$OUT/e1/ensemble.csv" "$OUT/e2/ensemble.csv" &&
          cmp -s "$OUT/e1/histograms.csv" "$OUT/e2/histograms.csv" && same=yes
        echo "| $model | $n | 2 | $w | $rate | $rss | $ratio | $same |"
      else
        echo "| $model | $n | 1 | $w | $rate | $rss | | |"
      fi
    done
  done
done
echo
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
