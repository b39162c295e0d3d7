#!/usr/bin/env bash
# A particle time series with the `spheres` technique (Staib, Grottel & Gumhold 2015): every data
# frame is uploaded, voxelized into the AO volume and sorted again when the animation reaches it
# (core/particle_series.h), the per-frame work of the paper's Table 3. Writes a LAMMPS dump of
# FRAMES data frames of N particles (two droplets approaching each other, generated here with a
# fixed seed), renders FRAMES animation frames at 1024x768 with AO at RES^3, and prints per
# animation frame the stages upload, voxelize, sort and frame (cpu ms; llvmpipe runs the GPU work
# on the CPU) from timings.csv, then the same with dataset.frame=0 pinned (one upload and
# voxelization for the whole animation) for comparison.
#   scripts/bench/particle_series.sh [N] [FRAMES] [RES]     default: 500000 6 128
# EXTRA: more --set arguments for every run; SHADER_DIR: passed as --shader-dir (A/B of shaders).
set -euo pipefail
cd "$(dirname "$0")/../.."
n=${1:-500000}; frames=${2:-6}; res=${3:-128}
read -r -a extra <<<"${EXTRA:-}"
shader=(); [ -n "${SHADER_DIR:-}" ] && shader=(--shader-dir "$SHADER_DIR")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$n" "$frames" "$work/series.lammpstrj" <<'PY'
import math, random, sys
n, frames, path = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
rng = random.Random(1)
# Two balls of radius 0.25 in the unit box, their centres approaching by 0.03 per frame.
base = []
for i in range(n):
    while True:
        p = [rng.uniform(-1, 1) for _ in range(3)]
        if sum(c * c for c in p) <= 1: break
    side = 1 if i % 2 else -1
    base.append((side, [0.25 * c for c in p]))
with open(path, "w") as f:
    for t in range(frames):
        gap = 0.28 - 0.03 * t
        f.write(f"ITEM: TIMESTEP\n{t}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n")
        f.write("ITEM: ATOMS id type x y z\n")
        for i, (side, p) in enumerate(base):
            f.write(f"{i + 1} {1 if side < 0 else 2} {0.5 + side * gap + p[0]:.5f} {0.5 + p[1]:.5f} {0.5 + p[2]:.5f}\n")
PY
cat >"$work/scene.json" <<JSON
{
  "dataset": {"path": "$work/series.lammpstrj"},
  "style": {"radius": 0.004, "color": {"attribute": "type", "colormap": "viridis", "range": [1, 2]}, "opacity": 0.4},
  "camera": {"eye": [0.5, -1.2, 1.4], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 35, "fit": true},
  "image": {"width": 1024, "height": 768, "background": [0.08, 0.08, 0.1, 1]},
  "render": {"technique": "spheres", "transparency": "object_order",
             "spheres": {"chunks": 20}, "ao": {"enabled": true, "resolution": $res}},
  "animation": {"type": "orbit", "frames": $frames, "degrees": 10},
  "output": {"dir": "$work/out", "name": "s.####", "formats": ["png"], "aovs": []}
}
JSON
uptime
stages() {  # timings.csv -> one row per frame: upload, voxelize, sort, frame (cpu ms)
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
           { f = $col["frame"]; s = $col["stage"]; v[f, s] = $col["cpu_ms"]; if (f > last) last = f }
           END { for (f = 0; f <= last; ++f)
                   printf "| %d | %s | %s | %s | %s |\n", f, (f, "upload") in v ? v[f, "upload"] : "-",
                          (f, "voxelize") in v ? v[f, "voxelize"] : "-", v[f, "sort"], v[f, "frame"] }' "$1"
}
for mode in series pinned; do
  pin=(); [ "$mode" = pinned ] && pin=(--set dataset.frame=0)
  rm -rf "$work/out"
  "${TUBECAST:-build/cli/tubecast}" render "$work/scene.json" -q --overwrite "${shader[@]}" "${pin[@]}" "${extra[@]}"
  echo "### $n particles, $frames frames, AO ${res}^3: $mode"
  echo "| frame | upload ms | voxelize ms | sort ms | frame ms |"
  echo "|---:|---:|---:|---:|---:|"
  stages "$work/out/timings.csv"
done
uptime
