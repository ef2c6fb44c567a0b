#!/usr/bin/env bash
# Runs explore.launch on a world and reports, next to its summary and evaluation, the peak resident
# memory of every node (sampled every second from /proc) and the wall time.
# Usage: bash scripts/measure_exploration.sh WORLD OUT_DIR [rate] [max_sim_time_s]   (rate 0: lockstep, the default)
# (needs a built workspace: source .ws/devel/setup.bash first)
set -uo pipefail
WORLD="$1"
# A world file given by a relative path: roslaunch's nodes run in ~/.ros, so make it absolute.
[ -f "$WORLD" ] && WORLD="$(cd "$(dirname "$WORLD")" && pwd)/$(basename "$WORLD")"
OUT="$(mkdir -p "$2" && cd "$2" && pwd)"
RATE="${3:-0}"
MAX_TIME="${4:-4000}"
NAME="$(basename "$WORLD" .yaml)"
rm -f "$OUT/$NAME".{topo,topo.places,summary.json,evaluation.json,memory.json}
START=$(date +%s.%N)
roslaunch hybrid_slam explore.launch world:="$WORLD" rate:="$RATE" map_file:="$OUT/$NAME.topo" \
  summary:="$OUT/$NAME.summary.json" evaluate:="$OUT/$NAME.evaluation.json" max_time:="$MAX_TIME" \
  > "$OUT/$NAME.log" 2>&1 &
LAUNCH=$!
declare -A PEAK
while kill -0 "$LAUNCH" 2>/dev/null; do
  for node in bullet_sim_node laser_features_node pomdp_topo_node ekf_local_map_node exploration_node; do
    for pid in $(pgrep -f "/$node( |$)"); do
      kb=$(awk '/VmRSS/ {print $2}' "/proc/$pid/status" 2>/dev/null)
      [ -n "$kb" ] && [ "$kb" -gt "${PEAK[$node]:-0}" ] && PEAK[$node]=$kb
    done
  done
  sleep 1
done
END=$(date +%s.%N)
{
  echo -n "{\"wall_time_s\": $(awk -v a="$START" -v b="$END" 'BEGIN { printf "%.1f", b - a }')"
  for node in "${!PEAK[@]}"; do echo -n ", \"${node}_peak_rss_kb\": ${PEAK[$node]}"; done
  echo "}"
} > "$OUT/$NAME.memory.json"
echo "summary:    $(cat "$OUT/$NAME.summary.json" 2>/dev/null)"
echo "evaluation: $(tr -d '\n ' < "$OUT/$NAME.evaluation.json" 2>/dev/null)"
echo "memory:     $(cat "$OUT/$NAME.memory.json")"
