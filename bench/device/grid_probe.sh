#!/usr/bin/env bash
# One lease's measurements for the training-quality question (issues 46 and 49), run through
#
#   bench/device/run.sh --exec BUNDLE bench/device/grid_probe.sh OUT_DIR
#
# with a bundle of `bench/device/pack.sh --paper`: the main job (2 minutes of ISNR on the bundled Cornell box, its
# MAPE), then Wooden Staircase at the paper's scale (batch 16384, N = 4, width 512, Adam 5e-3, the L2 residual, NEE)
# trained STEPS steps (default 12000, the learning rate annealed over them) with ISNR-IKL twice, once per hash grid:
# `paper` (the preset's, after Müller et al.: 16 levels x 2 features, 2^19 entries, resolution 16 to 2048) and `nr`
# (the Neural Radiosity authors' code: 12 levels x 8 features, 2^18 entries, resolution 2 doubling to 4096). Each is
# evaluated against TungstenRender.exr every STEPS/3 steps at 4 spp, then rendered in each of MODES (default lhs;
# render --mode) at each of RENDER_SPP (default 32), timed. GRIDS (default "paper nr") picks the grids. Logs and the figures
# go to OUT_DIR; the last lines printed are the figures. A rehearsal on a CPU: SKIP_MAIN=1 STEPS=2 EVAL_EVERY=2
# RENDER_SPP=1 BUILD_DIR=build/ci CLR_SHARED_SCENES=../shared/scenes bench/device/grid_probe.sh OUT_DIR.
set -u
out=${1:?usage: grid_probe.sh OUT_DIR}
mkdir -p "$out"
out=$(cd "$out" && pwd)
clr=$BUILD_DIR/clradiosity
scene_dir=${CLR_SHARED_SCENES:?run through bench/device/run.sh --exec with a --paper bundle}/staircase
ref=$scene_dir/TungstenRender.exr
steps=${STEPS:-12000}
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT
figures=()

if [ -z "${SKIP_MAIN:-}" ]; then  # SKIP_MAIN=1: a rehearsal on a CPU
  (cd "$out" && timeout 220 "$clr" >"$out/main.txt" 2>&1)
  figures+=("main job: exit $? $(grep -o 'MAPE [0-9.eE+-]*' "$out/main.txt" | tail -n 1)")
fi

common='"batch": 16384, "samples": 4, "residual": "l2", "guide": {"adam": {"learning_rate": 0.005}}'
for grid in ${GRIDS:-paper nr}; do
  case $grid in
    paper) g='"levels": 16, "features": 2, "log2_table": 19, "base_resolution": 16, "growth": 1.38191' ;;
    nr) g='"levels": 12, "features": 8, "log2_table": 18, "base_resolution": 2, "growth": 2.0' ;;
  esac
  echo "{$common, \"network\": {\"width\": 512, \"adam\": {\"learning_rate\": 0.005}, \"encoder\": {\"grid\": {$g}}}}" \
    >"$runs/$grid.json"
  timeout -k 10 "${TRAIN_LIMIT_S:-180}" "$clr" train "$scene_dir/scene.xml" --config "$runs/$grid.json" --method isnr \
    --is-loss ikl --steps "$steps" --reference "$ref" --eval-every "${EVAL_EVERY:-$((steps / 3))}" --eval-spp 4 -o "$runs/$grid" \
    >"$out/staircase-$grid.txt" 2>&1
  status=$?
  cp "$runs/$grid/log.csv" "$out/staircase-$grid-log.csv" 2>/dev/null
  last=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } END { print $c["step"], $c["seconds"], $c["mape"] }' \
    "$out/staircase-$grid-log.csv" 2>/dev/null)
  figures+=("staircase $grid: exit $status, last row (step seconds mape) $last")
  # The trained model rendered in each image mode (render --mode) at each spp, timed.
  for mode in ${MODES:-lhs}; do
    for spp in ${RENDER_SPP:-32}; do
      start=$SECONDS
      timeout "${RENDER_LIMIT_S:-90}" "$clr" render "$scene_dir/scene.xml" --model "$runs/$grid" --mode "$mode" --spp "$spp" --reference "$ref" \
        --error-map "$out/staircase-$grid-$mode-$spp-error.png" -o "$runs/$grid/r.exr" >"$runs/render.txt" 2>&1
      cat "$runs/render.txt" >>"$out/staircase-$grid.txt"
      figures+=("  render --mode $mode --spp $spp: $((SECONDS - start)) s, $(grep -o 'MAPE.*relMSE [0-9.eE+-]*' "$runs/render.txt")")
    done
  done
done
printf '%s\n' "${figures[@]}" | tee "$out/figures.txt"
