#!/usr/bin/env bash
# The paper's ablation (ISNR Table 4) at CPU scale on one shared scene: w/o I-Module (`--method nr`), w/o IKL
# (`--is-loss kl`) and the full method (IKL), each trained for every step count and seed, rendered at 16 spp and
# compared with the scene's TungstenRender.exr. One Markdown row per run: steps, training seconds (for equal-time
# reading), MAPE, relMSE, non-finite pixels, and the mean I-Module loss and guided share of the last log rows.
# Each step count is its own run because the learning rate anneals over the budget.
#
# Usage: bench/ablation.sh SCENE_DIR WIDTH HEIGHT "STEPS..." "SEEDS..." [-- EXTRA TRAIN FLAGS]
#   e.g. bench/ablation.sh ../shared/scenes/veach-bidir 128 128 "250 500 1000 2000" "1 2"
# Environment: CLRADIOSITY (binary, default build/release/clradiosity), SWEEP_DIR (runs, default a temporary
# folder), VARIANTS (default "nr kl ikl"), CLRADIOSITY_DEVICE as for every command.
set -euo pipefail
[ $# -ge 5 ] || {
  sed -n '8,9p' "$0" >&2
  exit 2
}
scene_dir=$1 width=$2 height=$3 steps_list=$4 seeds=$5
shift 5
[ "${1:-}" = "--" ] && shift
bin=${CLRADIOSITY:-build/release/clradiosity}
out=${SWEEP_DIR:-$(mktemp -d)}
mkdir -p "$out"
scene=$scene_dir/scene.xml
ref=$scene_dir/TungstenRender.exr
json() { python3 -c "import json,sys; d=json.load(sys.stdin); print(d['$1'])"; }

echo "scene: $scene (${width}x${height}, 16 spp), runs in $out"
echo "| variant | steps | seed | seconds | MAPE | relMSE | non-finite px |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"
for variant in ${VARIANTS:-nr kl ikl}; do
  case $variant in
    nr) flags=(--method nr) ;;
    kl) flags=(--method isnr --is-loss kl) ;;
    ikl) flags=(--method isnr --is-loss ikl) ;;
    *) echo "unknown variant $variant" >&2 && exit 2 ;;
  esac
  for steps in $steps_list; do
    for seed in $seeds; do
      run=$out/$variant-$steps-s$seed
      rm -rf "$run"
      "$bin" train "$scene" --steps "$steps" --seed "$seed" "${flags[@]}" -o "$run" "$@" >"$run.train.log" 2>&1
      seconds=$(tail -n 1 "$run/log.csv" | cut -d, -f2)
      "$bin" render "$scene" --model "$run" --width "$width" --height "$height" --spp 16 -o "$run.exr" \
        --png "$run.png" >/dev/null
      metrics=$("$bin" compare "$run.exr" "$ref" --json)
      printf "| %s | %s | %s | %.1f | %.4f | %.4f | %s |\n" "$variant" "$steps" "$seed" "$seconds" \
        "$(json mape <<<"$metrics")" "$(json relmse <<<"$metrics")" "$(json non_finite <<<"$metrics")"
    done
  done
done
