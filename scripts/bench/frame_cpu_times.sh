#!/usr/bin/env bash
# Renders SCENE as a short orbit and prints the process CPU time (user + system, all threads) of
# the setup (up to the first frame's PNG: data, voxelization, AO cache, first frame with shader
# JIT) and of every later frame (from one PNG to the next), plus the run's run.json AO summary.
# CPU time, unlike wall time, is barely inflated when other processes share the cores, so
# ratios of two such runs back to back stay meaningful on a loaded machine.
#   scripts/bench/frame_cpu_times.sh SCENE [FRAMES] [--set key=value ...]
# Example: scripts/bench/frame_cpu_times.sh configs/tornado_1m.json 3 --set render.ao.enabled=true
set -euo pipefail
cd "$(dirname "$0")/../.."
scene=$1; shift
frames=${1:-3}; [ $# -gt 0 ] && shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
tick=$(getconf CLK_TCK)
"${TUBECAST:-build/cli/tubecast}" render "$scene" -o "$out" -q --overwrite \
  --set "animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":30}" \
  --set "output.name=bench.####" --set 'output.formats=["png"]' --set 'output.aovs=[]' "$@" &
pid=$!
cpu() { awk -v t="$tick" '{ printf "%.0f", ($14 + $15) * 1000 / t }' "/proc/$pid/stat" 2>/dev/null || true; }
start=$(date +%s.%N)
last=0
seen=0
while kill -0 "$pid" 2>/dev/null; do
  n=$(find "$out" -maxdepth 1 -name 'bench.*.png' | wc -l)
  if [ "$n" -gt "$seen" ]; then
    now=$(cpu)
    [ -n "$now" ] || break
    if [ "$seen" -eq 0 ]; then
      echo "setup + frame 0: cpu $now ms, wall $(echo "$(date +%s.%N) - $start" | bc) s"
    else
      echo "frame $seen: cpu $((now - last)) ms"
    fi
    last=$now
    seen=$n
  fi
  sleep 0.1
done
wait "$pid"
python3 - "$out/run.json" <<'EOF'
import json, sys
run = json.load(open(sys.argv[1]))
ao = run.get("technique", {}).get("ambient_occlusion")
if ao:
    cache = ao.get("cache")
    print("ao: voxelize_ms %.0f, upload_and_mips_ms %.0f, cache %s" % (ao.get("voxelize_ms", 0), ao.get("upload_and_mips_ms", 0), json.dumps(cache)))
EOF
