#!/usr/bin/env bash
# Throughput against fleet size (issue 10, BENCHMARKS.md): runs a scaling scenario with the
# fleets scaled together to 4, 8, 16, 32 and 64 robots (the same task requests), and prints
# one table row per size: tasks completed, failed, unfinished, and the run's wall time.
#   scripts/scaling.sh fixtures/bench/hotel_20_robots.scenario.yaml [--until 4h]
# The fleets keep the proportions of the scenario's `count`s.
set -euo pipefail
scenario=$1; shift
# The release build.
mapc=${MAPC:-target/release/mapc}
dir=$(cd "$(dirname "$scenario")" && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mapfile -t counts < <(grep -o 'count: [0-9]*' "$scenario" | grep -o '[0-9]*')
total=0; for c in "${counts[@]}"; do total=$((total + c)); done
echo "| robots | counts | completed | failed | unfinished | wall s |"
echo "|---|---|---|---|---|---|"
for n in 4 8 16 32 64; do
  # Scale every count, largest remainders last, so that they add up to n.
  scaled=(); sum=0
  for c in "${counts[@]}"; do s=$(( c * n / total )); [[ $s -lt 1 ]] && s=1; scaled+=("$s"); sum=$((sum + s)); done
  i=0; while [[ $sum -lt $n ]]; do scaled[$i]=$(( scaled[i] + 1 )); sum=$((sum + 1)); i=$(( (i + 1) % ${#scaled[@]} )); done
  out="$dir/.scaling_$(basename "$scenario" .scenario.yaml)_$n.scenario.yaml"
  awk -v list="${scaled[*]}" 'BEGIN{split(list, s, " "); k=0} /count: [0-9]+/{k++; sub(/count: [0-9]+/, "count: " s[k])} {print}' "$scenario" > "$out"
  start=$(date +%s.%N)
  "$mapc" sim "$out" --report "$tmp/r.json" "$@" > /dev/null 2>&1 || true
  end=$(date +%s.%N)
  rm -f "$out"
  python3 - "$tmp/r.json" "$n" "${scaled[*]}" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
res = [t["result"] for t in r["tasks"]]
print(f"| {sys.argv[2]} | {sys.argv[3].replace(' ', '/')} | {res.count('completed')} | {res.count('failed')} | {res.count('unfinished')} | {float(sys.argv[5]) - float(sys.argv[4]):.1f} |")
PY
done
