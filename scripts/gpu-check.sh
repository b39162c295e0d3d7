#!/usr/bin/env bash
# One check of the GPU-only code paths on a machine with a GPU and its EGL driver (Debian 12,
# NVIDIA or AMD): fragment shader interlock and 64-bit atomics in the k-buffer and depth peeling
# shaders, and the EGL device platform. Prints ONE summary table on stdout (progress on stderr):
# the GL renderer, which synchronisation path the k-buffer and depth peeling ran, the `gl` ctest
# label on the EGL device, the images of each path against the llvmpipe path of the same scene,
# and ms per frame of every registered technique on the 1M-segment tornado at 1920x1080, and the
# voxel model's build time on the CPU against the GPU (render.vrc.build).
#
#   scripts/gpu-check.sh [--quick] [--build DIR] [--device N] [--out DIR]
#
# --build DIR  the build tree (default build/); configured and built (Release) when DIR/cli/tubecast
#              is missing, otherwise reused as it is.
# --device N   EGL device N (`tubecast render -v` lists them) for the renders; default: the first
#              that works. The gl tests always take the first (their fixture has no device option).
# --quick      small images, few frames, a 26k-segment tornado, no `gl` ctest label: under a minute
#              on llvmpipe (the cli ctest gpu_check_quick runs it so the script keeps working).
# --out DIR    keep the renders here (default: a temporary directory, removed at the end).
#
# The paths. tubecast picks the synchronisation from the context's extensions
# (gl/transparent_renderer.cpp): the k-buffer uses ARB_fragment_shader_interlock when present,
# depth peeling ARB_shader_atomic_int64 (atomicMin) before interlock; on llvmpipe neither: it
# relies on llvmpipe shading one pixel's fragments in primitive order. No scene key or variable
# forces a path, so the script forces them with `--shader-dir`: copies of kbuffer_insert.frag and
# depth_peel.frag that #undef the path's define (the llvmpipe code run on the GPU, "unordered"), or
# for depth peeling swap atomicMin for interlock. Every image is compared (`tubecast compare`)
# with the same scene rendered by the llvmpipe path: the OSMesa backend (Mesa llvmpipe) on the
# same machine. On a machine without a GPU the EGL context is llvmpipe too: the table then says
# that no GPU path was exercised.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0 build=build device= out=
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --build) build=$2; shift ;;
    --device) device=$2; shift ;;
    --out) out=$2; shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu-check.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if [ -n "$device" ] && ! [[ $device =~ ^[0-9]+$ ]]; then
  echo "gpu-check.sh: --device: expected a device index 0, 1, ..., got '$device'" >&2
  exit 2
fi
if [ -z "$out" ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out"
log() { echo "gpu-check: $*" >&2; }
start=$(date +%s)

tc=$build/cli/tubecast
if [ ! -x "$tc" ]; then
  log "building $build (Release)"
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > "$out/configure.log" 2>&1
  cmake --build "$build" -j"$(nproc)" > "$out/build.log" 2>&1 || { tail -20 "$out/build.log" >&2; exit 1; }
fi
egl=(--backend egl)
[ -n "$device" ] && egl+=(--device "$device")

json() {  # FILE PYTHON-EXPRESSION on `j`, the parsed file
  python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($2)" "$1"
}
# Median `frame` ms over the frames after the first (the first compiles shaders).
median_frame() {
  awk -F, '$2 == "frame" && $1 > 0 { print $4 }' "$1" | sort -n |
    awk '{ v[++n] = $1 } END { if (n == 0) { print "-"; exit } printf "%.1f", (n % 2) ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }'
}
render() {  # OUTDIR SCENE render-arguments...
  local dir=$1 scene=$2; shift 2
  rm -rf "$dir"
  mkdir -p "$(dirname "$dir")"
  if ! "$tc" render "$scene" -o "$dir" -q --overwrite --set 'output.formats=["png"]' --set 'output.aovs=[]' \
    --set 'output.name=f.####' "$@" > "$dir.log" 2>&1; then
    log "render failed ($dir.log):"; tail -5 "$dir.log" >&2
    return 1
  fi
}

# --- The context: renderer, device, extensions ---------------------------------------------------
render "$out/probe" configs/demo.json "${egl[@]}" --set image.width=64 --set image.height=48 --frames 0
probe=$out/probe/run.json
renderer=$(json "$probe" 'j["gl"]["renderer"]')
backend=$(json "$probe" 'j["gl"]["backend"] + (" device " + j["gl"]["device"] if j["gl"]["device"] else "")')
extensions=$(json "$probe" '" ".join(j["gl"]["extensions"])')
gpu=1
case $renderer in *llvmpipe* | *softpipe* | *swrast*) gpu=0 ;; esac
has() { [[ " $extensions " == *" $1 "* ]]; }
log "context: $backend, $renderer"

# --- The gl ctest label on the EGL device ----------------------------------------------------------
if [ "$quick" = 1 ]; then
  gl_tests="not run (--quick)"
elif [ ! -f "$build/CTestTestfile.cmake" ]; then
  gl_tests="not run: $build has no tests (configure it with the default options)"
else
  log "ctest -L gl on $backend"
  # The tests make their context with `auto` unless told; egl keeps them off OSMesa.
  (cd "$build" && TUBECAST_TEST_BACKEND=egl ctest -L gl -j"$(nproc)" --timeout 300 > "$out/ctest_gl.log" 2>&1) || true
  gl_tests=$(awk '/tests passed, .* tests failed out of/ { print }' "$out/ctest_gl.log")
  [ -z "$gl_tests" ] && gl_tests="ctest gave no summary ($out/ctest_gl.log)"
  failed=$(awk '/^[[:space:]]*[0-9]+ - .* \((Failed|Timeout|Exception|SEGFAULT|Subprocess)/ { print $3 }' "$out/ctest_gl.log" |
    head -5 | paste -sd' ')
  [ -n "$failed" ] && gl_tests="$gl_tests; first failures: $failed"
fi

# --- The synchronisation paths against llvmpipe ------------------------------------------------------
# Shader overrides that force a path (see the header): the defines come before the file's text.
mkdir -p "$out/shaders_unordered" "$out/shaders_interlock"
{ echo '#undef USE_INTERLOCK'; cat shaders/kbuffer_insert.frag; } > "$out/shaders_unordered/kbuffer_insert.frag"
{ printf '#undef USE_INTERLOCK\n#undef USE_ATOMIC64\n'; cat shaders/depth_peel.frag; } > "$out/shaders_unordered/depth_peel.frag"
{ printf '#undef USE_ATOMIC64\n#ifndef USE_INTERLOCK\n#define USE_INTERLOCK\n#endif\n'; cat shaders/depth_peel.frag; } \
  > "$out/shaders_interlock/depth_peel.frag"

if [ "$quick" = 1 ]; then
  scenes=(tornado)
  size=(--set image.width=192 --set image.height=108)
else
  scenes=(tornado demo)
  size=(--set image.width=480 --set image.height=270)
fi
scene_args() {  # NAME: the scene file and its settings
  case $1 in
    tornado) echo configs/tornado_1m.json --set dataset.lines="$([ "$quick" = 1 ] && echo 60 || echo 200)" ;;
    demo) echo configs/demo.json ;;
  esac
}
compare() {  # A B: "PSNR x dB, max error y"
  "$tc" compare "$1" "$2" | awk '$1 == "psnr" { p = $2 } $1 == "max_error" { m = $2 }
    END { printf "PSNR %s dB, max error %s", (p == "inf" ? "inf (identical)" : sprintf("%.1f", p)), m }'
}
path_rows=()
for scene in "${scenes[@]}"; do
  read -r -a sargs <<<"$(scene_args "$scene")"
  for mode in kbuffer depth_peeling; do
    margs=("${sargs[@]}" "${size[@]}" --set style.opacity=0.3 --set render.technique=rasterized
           --set render.transparency=$mode --frames 0)
    [ "$mode" = kbuffer ] && margs+=(--set render.kbuffer.k=4)  # few entries: many ordered evictions
    label="$mode, $scene"
    [ "$mode" = kbuffer ] && label="kbuffer k=4, $scene"
    log "paths: $label"
    ref=$out/paths/${scene}_${mode}_llvmpipe
    render "$ref" "${margs[@]}" --backend osmesa || { path_rows+=("| $label: llvmpipe (OSMesa) | render failed: $ref.log |"); continue; }
    auto=$out/paths/${scene}_${mode}_auto
    render "$auto" "${margs[@]}" "${egl[@]}" || { path_rows+=("| $label: this context | render failed: $auto.log |"); continue; }
    sync=$(json "$auto/run.json" 'j["technique"].get("synchronisation", "-")')
    [ "$mode" = kbuffer ] && kbuffer_path=$sync || peel_path=$sync
    path_rows+=("| $label: $sync vs llvmpipe | $(compare "$auto/f.0000.png" "$ref/f.0000.png") |")
    [ "$gpu" = 1 ] || continue
    variants=(unordered)
    [ "$mode" = depth_peeling ] && has GL_ARB_shader_atomic_int64 && has GL_ARB_fragment_shader_interlock &&
      variants+=(interlock)
    for v in "${variants[@]}"; do
      dir=$out/paths/${scene}_${mode}_$v
      what=$([ "$v" = unordered ] && echo "forced unordered (the llvmpipe code on the GPU; may race)" ||
        echo "forced ARB_fragment_shader_interlock")
      if render "$dir" "${margs[@]}" "${egl[@]}" --shader-dir "$out/shaders_$v"; then
        path_rows+=("| $label: $what vs llvmpipe | $(compare "$dir/f.0000.png" "$ref/f.0000.png") |")
      else
        path_rows+=("| $label: $what | render failed: $dir.log |")
      fi
    done
  done
done

# --- Every technique on the 1M tornado ------------------------------------------------------------------
if [ "$quick" = 1 ]; then
  frames=2 width=256 height=144 lines=(--set dataset.lines=60) particles=(--set dataset.particles=20000)
else
  frames=5 width=1920 height=1080 lines=() particles=(--set dataset.particles=1000000)
fi
"$tc" techniques --json > "$out/techniques.json"
technique_rows=()
while IFS=' ' read -r name data; do
  if [[ " $data " == *" lines "* ]]; then
    what=tornado_1m
    [ "$quick" = 1 ] && what="tornado_1m (60 lines)"
    targs=(configs/tornado_1m.json "${lines[@]}")
  else
    what="droplets $([ "$quick" = 1 ] && echo 20k || echo 1M) particles"
    targs=(configs/droplets.json "${particles[@]}" --set render.ao.enabled=false)
  fi
  for t in opaque transparent; do
    dir=$out/techniques/${name}_$t
    topts=(--set render.technique="$name" --set image.width=$width --set image.height=$height
           --set "animation={\"type\":\"orbit\",\"frames\":$frames,\"degrees\":10}")
    if [ "$t" = opaque ]; then
      topts+=(--set style.opacity=1 --set render.transparency=opaque)
    else
      topts+=(--set style.opacity=0.3 --set render.transparency=auto)
    fi
    log "technique $name, $t"
    if render "$dir" "${targs[@]}" "${egl[@]}" "${topts[@]}"; then
      mode=$(json "$dir/run.json" 'j["technique"].get("transparency", "-")')
      technique_rows+=("| $name $t ($mode), $what, ${width}x$height | $(median_frame "$dir/timings.csv") ms/frame |")
    else
      technique_rows+=("| $name $t, $what | render failed: $dir.log |")
    fi
  done
done < <(json "$out/techniques.json" '"\n".join(t["name"] + " " + " ".join(t["data"]) for t in j)')

# --- The voxel model build: CPU against GPU (render.vrc.build) ----------------------------------------------
# `auto` takes the GPU build on a hardware GL without a measurement from such a machine
# (docs/scene-spec.md, vrc.build); this row is that measurement: run.json's build_ms of the
# tornado's model, built twice each way in the order cpu gpu gpu cpu, and what `auto` took.
log "vrc.build cpu / gpu"
vrc_what=tornado_1m
[ "$quick" = 1 ] && vrc_what="tornado_1m (60 lines)"
vrc_args=(configs/tornado_1m.json "${lines[@]}" "${egl[@]}" --set render.technique=voxel_raycast
          --set image.width=64 --set image.height=48 --frames 0)
declare -A build_ms=([cpu]=0 [gpu]=0)
vrc_row=
for b in cpu gpu gpu cpu; do
  dir=$out/vrc_build/$b
  if ! render "$dir" "${vrc_args[@]}" --set render.vrc.build=$b; then
    vrc_row="| vrc.build, $vrc_what | render failed: $dir.log |"
    break
  fi
  ms=$(json "$dir/run.json" 'j["technique"].get("build_ms", "")')
  if [ -z "$ms" ]; then
    vrc_row="| vrc.build, $vrc_what | no build_ms in $dir/run.json |"
    break
  fi
  build_ms[$b]=$(awk -v sum="${build_ms[$b]}" -v ms="$ms" 'BEGIN { print sum + ms / 2 }')
done
if [ -z "$vrc_row" ]; then
  dir=$out/vrc_build/auto
  if render "$dir" "${vrc_args[@]}" --set render.vrc.build=auto; then
    vrc_row=$(printf '| vrc.build, %s | cpu %.0f ms, gpu %.0f ms (means of two builds); auto takes %s |' "$vrc_what" \
      "${build_ms[cpu]}" "${build_ms[gpu]}" "$(json "$dir/run.json" 'j["technique"].get("build", "-")')")
  else
    vrc_row="| vrc.build, $vrc_what | render failed: $dir.log |"
  fi
fi

# --- The table ----------------------------------------------------------------------------------------------
if [ "$gpu" = 1 ]; then
  exercised="yes: $renderer"
else
  exercised="no GPU path exercised: the EGL context is a software renderer ($renderer); the llvmpipe path was compared with itself"
fi
echo "| check | result |"
echo "|---|---|"
echo "| GL renderer | $renderer ($backend) |"
echo "| GPU | $exercised |"
echo "| k-buffer path | ${kbuffer_path:--} |"
echo "| depth peeling path | ${peel_path:--} |"
echo "| gl tests (ctest -L gl, EGL) | $gl_tests |"
printf '%s\n' "${path_rows[@]}" "${technique_rows[@]}" "$vrc_row"
echo "| machine time | $(($(date +%s) - start)) s, load average $(cut -d' ' -f1-3 /proc/loadavg) |"
