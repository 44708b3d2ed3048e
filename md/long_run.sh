#!/usr/bin/env bash
# The long calibration (md/README.md): the static scan, 300 K to 300 ps, the
# 300 K spin-down runs, 77 K to 300 ps, then both temperatures on to 1000 ps.
# Resumable: re-run this script after a kill and each run continues from
# its last restart (md/runs/T*/state.json); finished stages are skipped.
# One core, low priority: OMP_NUM_THREADS=1, nice -n 15, one run at a time.
set -euo pipefail
cd "$(dirname "$0")"
PY="${PY:-/work/venv-md/bin/python}"
ROOT="${ROOT:-runs}"
export OMP_NUM_THREADS=1
run() { nice -n 15 "$PY" calibrate.py "$@"; }
[ -f "$ROOT/static.json" ] || run static "$ROOT"
run run "$ROOT" -T 300 --ps 300
run spindown "$ROOT" -T 300 || echo "spin-down at 300 K failed" >&2
run run "$ROOT" -T 77 --ps 300
run analyse "$ROOT"
run run "$ROOT" -T 300 --ps 1000
run analyse "$ROOT"
run run "$ROOT" -T 77 --ps 1000
run spindown "$ROOT" -T 77 || echo "spin-down at 77 K failed" >&2
run analyse "$ROOT"
run run "$ROOT" -T 300 --ps 2000
run run "$ROOT" -T 77 --ps 2000
run analyse "$ROOT"
