#!/usr/bin/env bash
# The speed/accuracy trade of vanilla NR on one shared scene: trains a fresh run for each budget (minutes), renders it
# and prints one Markdown table row per budget — steps, steps/s, MAPE and relMSE against the scene's
# TungstenRender.exr (box-downsampled to the render size), non-finite pixels, and the residual metric.
# Each budget is its own run because the learning rate anneals over the budget (docs/method.md, "Annealing").
#
# Usage: bench/accuracy_sweep.sh SCENE_DIR WIDTH HEIGHT MINUTES... [-- EXTRA TRAIN FLAGS]
#   e.g. bench/accuracy_sweep.sh ../shared/scenes/cornell-box 128 128 1 2 5 10
# Environment: CLRADIOSITY (binary, default build/release/clradiosity), SWEEP_DIR (runs and images, default a
# temporary folder), CLRADIOSITY_DEVICE as for every command. Budgets run one after another, never in parallel,
# so each has the whole device.
set -euo pipefail
[ $# -ge 4 ] || {
  sed -n '7,8p' "$0" >&2
  exit 2
}
scene_dir=$1 width=$2 height=$3
shift 3
budgets=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  budgets+=("$1")
  shift
done
[ "${1:-}" = "--" ] && shift
bin=${CLRADIOSITY:-build/release/clradiosity}
out=${SWEEP_DIR:-$(mktemp -d)}
mkdir -p "$out"
scene=$scene_dir/scene.xml
ref=$scene_dir/TungstenRender.exr
json() { python3 -c "import json,sys; d=json.load(sys.stdin); print(d['$1'])"; }

echo "scene: $scene (${width}x${height}, 16 spp), runs in $out"
echo "| budget | steps | steps/s | MAPE | relMSE | non-finite px | residual (P=8192, S=64) |"
echo "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for minutes in "${budgets[@]}"; do
  run=$out/run-${minutes}min
  rm -rf "$run"
  "$bin" train "$scene" --minutes "$minutes" -o "$run" "$@" >"$run.train.log" 2>&1
  steps=$(sed -n 's/^model: .* (\([0-9]*\) steps)$/\1/p' "$run.train.log")
  "$bin" render "$scene" --model "$run" --width "$width" --height "$height" --spp 16 -o "$run.exr" \
    --png "$run.png" >/dev/null
  metrics=$("$bin" compare "$run.exr" "$ref" --json)
  residual=$("$bin" residual "$scene" --model "$run" --points 8192 --samples 64 --json)
  printf "| %s min | %s | %.2f | %.4f | %.4f | %s | %.4g ± %.2g |\n" "$minutes" "$steps" \
    "$(python3 -c "print($steps / ($minutes * 60))")" "$(json mape <<<"$metrics")" "$(json relmse <<<"$metrics")" \
    "$(json non_finite <<<"$metrics")" "$(json residual <<<"$residual")" "$(json standard_error <<<"$residual")"
done
