#!/usr/bin/env bash
# The relaxation runs at 300 K (md/README.md, (b') and (c')): slide-down,
# 5 runs of 100 ps after a push of 3 sqrt(kT/m) along x, then spin-down,
# 4 runs of 450 ps after omega_z += 5 sqrt(kT/I); then `analyse`.
# Each run has its own directory and is written at its end, so re-running
# this script after a kill redoes only the run that was in progress.
# One core, low priority: OMP_NUM_THREADS=1, nice -n 15, one run at a time.
set -euo pipefail
cd "$(dirname "$0")"
PY="${PY:-/work/venv-md/bin/python}"
ROOT="${ROOT:-runs}"
export OMP_NUM_THREADS=1
run() { nice -n 15 "$PY" calibrate.py "$@"; }
run spindown "$ROOT" -T 300 --mode slide --factor 3 --runs 5 --ps 100
run spindown "$ROOT" -T 300 --mode spin --factor 5 --runs 4 --ps 450
run analyse "$ROOT"
