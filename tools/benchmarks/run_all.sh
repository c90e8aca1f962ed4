#!/usr/bin/env bash
# Runs the benchmarks behind docs/benchmarks.md, one after another on one core each, and
# leaves each one's --json (and its time) in OUT (default bench-results/): the tables of
# docs/benchmarks.md are these files' figures. Run it on a machine doing nothing else.
#   tools/benchmarks/run_all.sh [OUT] [NAME ...]    (NAME: only those, e.g. cloth paper)
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-bench-results}
shift || true
CATWALK=${CATWALK:-.venv/bin/catwalk}
mkdir -p "$OUT"
{ date -u +%FT%TZ; git rev-parse --short HEAD; nproc; grep -m1 "model name" /proc/cpuinfo;
  grep -qw avx512f /proc/cpuinfo && echo "avx512f: yes" || echo "avx512f: no";
  cat /proc/loadavg; echo "benchmarks: ${*:-all}"; } >> "$OUT/machine.txt"

declare -A BENCH=(
  [bodies]="bodies build --out-dir $OUT/bodies"
  [scan]="bench scan --json"
  [gait]="bench gait --speed 0.8 1.2 1.6 --json"
  [skinning]="bench skinning --repeats 60 --json"
  [render]="bench render --json"
  [cloth]="bench cloth --json"
  [drape]="bench drape --h 0.015 --json"
  [cantilever]="bench cantilever --json"
  [collide]="bench collide --json"
  [dress]="bench dress --json"
  [paper]="bench paper --quiet --json"
  [implicit]="bench paper --quiet --json --modes hybrid --integrator implicit"
  [service]="bench service --json"
  [player]="bench player --json"
  [stress]="bench stress --quiet --json"
  [pareto]="bench pareto --quiet --json"
  [chaos]="loadtest --chaos --users 20 --seconds 180 --json"
)
ORDER=(bodies scan gait skinning render cloth drape cantilever collide dress paper implicit
       service player stress pareto chaos)
[ $# -gt 0 ] && ORDER=("$@")
for name in "${ORDER[@]}"; do   # every name checked before anything runs
  [ -n "${BENCH[$name]:-}" ] || { echo "run_all: no benchmark $name (${!BENCH[*]})" >&2; exit 2; }
done
failed=()
for name in "${ORDER[@]}"; do
  echo "run_all: $name: catwalk ${BENCH[$name]}" >&2
  start=$EPOCHREALTIME
  # one that fails is told and the rest still run (its log: $OUT/$name.log)
  # shellcheck disable=SC2086
  if $CATWALK ${BENCH[$name]} > "$OUT/$name.json" 2> "$OUT/$name.log"; then
    python3 -c "print('$name', round($EPOCHREALTIME - $start, 1))" >> "$OUT/seconds.txt"
  else
    echo "run_all: $name failed (exit $?): $OUT/$name.log" >&2
    failed+=("$name")
  fi
done
[ ${#failed[@]} -eq 0 ] || { echo "run_all: failed: ${failed[*]}" >&2; exit 1; }
