#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: installs what is missing, builds, then lets the
# simulated robot explore the default world by itself (explore.launch) and leave a hybrid map: the
# topological map, the places (local maps), a summary and the evaluation against the world's ground
# truth in the output folder. Exits 0 when the exploration ended complete.
# Usage: bash scripts/run_main.sh [world] [out_dir] [max_sim_time_s]   (defaults: institute, ./out, 4000)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${HYBRID_SLAM_WS:-$ROOT/.ws}"
WORLD="${1:-institute}"
OUT="$(mkdir -p "${2:-$ROOT/out}" && cd "${2:-$ROOT/out}" && pwd)"
MAX_TIME="${3:-4000}"
export PATH="/usr/bin:$PATH"

bash "$ROOT/scripts/setup.sh"
# shellcheck disable=SC1091
set +u  # ROS setup scripts read unset variables
source "$WS/devel/setup.bash"
set -u
NAME="$(basename "$WORLD" .yaml)"
MAP="$OUT/$NAME.topo"
rm -f "$MAP" "$MAP.places" "$OUT/$NAME.summary.json" "$OUT/$NAME.evaluation.json"
echo "[main] exploring '$WORLD' in lockstep: deterministic, as fast as the stack goes (at most $MAX_TIME s of sim time); the map goes to $MAP"
roslaunch hybrid_slam explore.launch world:="$WORLD" rate:=0 seed:=1 rviz:=false map_file:="$MAP" \
  summary:="$OUT/$NAME.summary.json" evaluate:="$OUT/$NAME.evaluation.json" max_time:="$MAX_TIME"
sleep 2
echo "[main] summary:    $(cat "$OUT/$NAME.summary.json" 2>/dev/null || echo none)"
echo "[main] evaluation: $(tr -d '\n ' < "$OUT/$NAME.evaluation.json" 2>/dev/null || echo none)"
echo "[main] look at the map: roslaunch hybrid_slam view_map.launch map_file:=$MAP"
/usr/bin/python3 - "$OUT/$NAME.summary.json" <<'PY'
import json, sys
try:
    complete = json.load(open(sys.argv[1]))['complete']
except Exception:
    complete = False
print('[main] exploration complete' if complete else '[main] exploration NOT complete')
sys.exit(0 if complete else 1)
PY
