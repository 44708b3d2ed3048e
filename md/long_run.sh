#!/usr/bin/env bash
# The long calibration (md/README.md): 300 K then 77 K to 300 ps each, then
# both on to 1000 ps. Resumable: re-run this script after a kill and each
# run continues from its last restart (md/runs/T*/state.json).
# One core, low priority: OMP_NUM_THREADS=1, nice -n 15, one run at a time.
set -euo pipefail
cd "$(dirname "$0")"
PY="${PY:-/work/venv-md/bin/python}"
ROOT="${ROOT:-runs}"
export OMP_NUM_THREADS=1
for stage in 300 1000; do
    for T in 300 77; do
        nice -n 15 "$PY" calibrate.py run "$ROOT" -T "$T" --ps "$stage"
    done
done
nice -n 15 "$PY" calibrate.py analyse "$ROOT"
