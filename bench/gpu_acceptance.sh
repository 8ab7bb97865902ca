#!/usr/bin/env bash
# Acceptance run for a GPU (or any device), about 5 minutes on an H100, no network (docs/nvidia.md):
#
#   bench/gpu_acceptance.sh [DEVICE] OUT_DIR
#
# DEVICE is a --device SPEC (default: CLRADIOSITY_DEVICE, else the default rule). Steps, each with its own time
# limit: list the devices; run the kernel and engine tests on DEVICE (the gtest suites of the `kernel` and `engine`
# groups in tests/runtimes/lanes.cmake, in one process); bench_nn --acceptance; train the bundled Cornell box with ISNR
# for 2 minutes (the main job: its MAPE against a path-traced reference); render the run at 512² and time it;
# bench_guide and bench_pipeline (the I-Module's share of a step, the pipelined step, host stages beside the device's
# busy time); bench_nn's table of every GEMM candidate; then every GPU-pace figure beside its target (issue:
# docs/nvidia.md). Writes OUT_DIR/summary.json and OUT_DIR/log.txt; the last line printed is PASS, or FAIL with the
# reasons. Binaries come from BUILD_DIR (default build/ci, as the test command builds it). MAPE_MAX (default 0.5) bounds the 2-minute MAPE: a CPU
# reaches about 0.2 there (docs/results/nr-training.md), so a larger one means training is broken, not slow.
# SKIP_STEPS (step names, space-separated; default none, gemm_table with PAPER=1) leaves steps out: leaving out the
# tests, bench_nn, the main job or its render is itself a reason to FAIL, since the verdict would then judge less.
#
# PAPER=1 (what `bench/device/run.sh --paper` sets): one lease does it all (issue 49). After the acceptance figures it
# trains the paper's scenes with `train --preset paper`, NR and ISNR (IKL), at the paper's step counts, evaluated
# against Tungsten's render, within one wall budget for the whole run: Wooden Staircase, then Veach Ajar if time is
# left ("The paper's runs" below: what they measure and the PAPER_* variables that shrink them for a rehearsal).
# Their MAPE, minutes and steps go into summary.json beside the paper's own (bench/paper/paper.json) and each run's
# log.csv into OUT_DIR/paper-SCENE-METHOD-log.csv. They are measurements: the verdict stays the acceptance's, and a
# paper run adds a reason only when its training exits with an error (not when the budget stops it).
set -uo pipefail

if [ $# -ge 2 ]; then
  device=$1 out=$2
elif [ $# -eq 1 ]; then
  device=${CLRADIOSITY_DEVICE:-} out=$1
else
  echo "usage: bench/gpu_acceptance.sh [DEVICE] OUT_DIR" >&2
  exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build/ci}
clr=$build/clradiosity
bench=$build/bench/bench_nn
tests=$build/tests/clr_tests
mape_max=${MAPE_MAX:-0.5}
mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)
log=$out/log.txt
: >"$log"
[ -n "$device" ] && export CLRADIOSITY_DEVICE=$device
reasons=()
json_steps=""
paper=${PAPER:-0}
# The paper mode's wall budget counts from PAPER_START (epoch seconds: run.sh sets it before it unpacks the bundle),
# else from now; PAPER_RESERVE_S of it is kept for the summary at the end.
budget_s=${PAPER_BUDGET_S:-540}
budget_start=${PAPER_START:-$(date +%s)}
reserve_s=${PAPER_RESERVE_S:-15}
time_left() { echo $((budget_start + budget_s - $(date +%s))); }
# gemm_table (51 s on an H100) is tuning information only, judged by nothing but its own checks: the paper mode
# leaves it out by default to give its seconds to the paper's runs. SKIP_STEPS= (set, empty) runs it there too.
if [ "$paper" = 1 ]; then
  skip_steps=" ${SKIP_STEPS-gemm_table} "
else
  skip_steps=" ${SKIP_STEPS-} "
fi
skipped() { [[ "$skip_steps" == *" $1 "* ]]; }

note() { echo "$*" | tee -a "$log"; }
# step NAME LIMIT_S COMMAND...: runs COMMAND with its output in OUT_DIR/NAME.txt and the log; records its status and
# seconds. A step in SKIP_STEPS, or one with no time left in the paper mode's budget, returns 1 without running; the
# paper mode also shortens LIMIT_S to the time left, so that the whole run stops within its budget.
step() {
  local name=$1 limit=$2
  shift 2
  if skipped "$name"; then
    rm -f "$out/$name.txt"  # an earlier call's output in OUT_DIR is not this call's figure
    note "== $name: skipped (SKIP_STEPS)"
    json_steps+="${json_steps:+,}\"$name\": {\"skipped\": true}"
    case $name in tests | bench_nn | train_cornell | render_512) reasons+=("$name skipped (SKIP_STEPS)") ;; esac
    return 1
  fi
  if [ "$paper" = 1 ]; then
    local left=$(($(time_left) - reserve_s))
    if [ "$left" -le 0 ]; then
      rm -f "$out/$name.txt"
      note "== $name: not run, the budget (PAPER_BUDGET_S=$budget_s) is spent"
      json_steps+="${json_steps:+,}\"$name\": {\"skipped\": true}"
      reasons+=("$name not run: the budget is spent")
      return 1
    fi
    [ "$left" -lt "$limit" ] && limit=$left
  fi
  note "== $name (limit ${limit}s): $*"
  local start=$SECONDS
  timeout "$limit" "$@" >"$out/$name.txt" 2>&1
  local status=$?
  cat "$out/$name.txt" >>"$log"
  local took=$((SECONDS - start))
  note "== $name: exit $status after ${took}s"
  json_steps+="${json_steps:+,}\"$name\": {\"exit\": $status, \"seconds\": $took}"
  [ $status -eq 124 ] && reasons+=("$name ran past ${limit}s")
  [ $status -ne 0 ] && [ $status -ne 124 ] && reasons+=("$name exited $status")
  return $status
}

# The binaries of the steps that run (a skipped step needs none).
needed=("$clr")
skipped tests || needed+=("$tests")
{ skipped bench_nn && skipped gemm_table; } || needed+=("$bench")
skipped bench_guide || needed+=("$build/bench/bench_guide")
skipped bench_pipeline || needed+=("$build/bench/bench_pipeline")
for f in "${needed[@]}"; do
  [ -x "$f" ] || { note "FAIL: $f is missing (cmake --workflow --preset ci builds it)"; exit 1; }
done

step devices 30 "$clr" devices ${device:+--device "$device"}
device_line=$("$clr" devices ${device:+--device "$device"} 2>/dev/null | grep '^\*' | head -n 1)
note "device: ${device_line:-none}"

# The kernel and engine groups' suites, read from the lane list ("*Suite.*": parameterised suites carry a prefix);
# CLRADIOSITY_DEVICE points the tests at DEVICE.
suites=$(awk '/^set\(CLR_(KERNEL|ENGINE)_SUITES/ {on = 1} on {print; if (/\)/) on = 0}' "$root/tests/runtimes/lanes.cmake" |
  sed 's/set(CLR_[A-Z]*_SUITES//; s/)//')
filter=$(printf '*%s.*:' $suites)
step tests 240 "$tests" --gtest_filter="${filter%:}" --gtest_brief=1

# The GPU-pace figures (bench_nn --acceptance): the engine's GEMM and N-Module steps, as one JSON line.
step bench_nn 150 "$bench" --acceptance --json ${device:+--device "$device"}

# The main job in OUT_DIR: 2 minutes of ISNR on the bundled Cornell box, its reference and MAPE.
mape=""
cd "$out" || exit 2
if step train_cornell 240 "$clr"; then
  mape=$(grep -o 'MAPE [0-9.eE+-]*' "$log" | tail -n 1 | cut -d' ' -f2)
fi
cd "$root" || exit 2
if skipped train_cornell; then
  :
elif [ -z "$mape" ]; then
  reasons+=("no MAPE from the Cornell training")
elif ! awk -v m="$mape" -v max="$mape_max" 'BEGIN { exit !(m == m + 0 && m <= max) }'; then
  reasons+=("Cornell MAPE $mape above $mape_max")
fi

render_s=""
run_dir=$out/clradiosity-out/cornell-box-run
if skipped train_cornell; then
  :  # no run of this call to render (an earlier call's may be there): the skip is the reason already
elif [ -d "$run_dir" ]; then
  start=$SECONDS
  if step render_512 120 "$clr" render "$root/scenes/cornell-box.xml" --model "$run_dir" --width 512 --height 512 \
    -o "$out/cornell-box-512.exr"; then
    render_s=$((SECONDS - start))
  fi
else
  reasons+=("no run directory to render")
fi

# Where a step's time goes on the device: its own figures, in the log (not judged).
step bench_guide 150 "$build/bench/bench_guide" "$root/scenes/cornell-box.xml" 3
step bench_pipeline 90 "$build/bench/bench_pipeline" "$root/scenes/cornell-box.xml" 3 20
# Every GEMM variant the device is offered (the probe's pick, each tiled block, CLBlast) at B = 4096 / 16384 / 65536:
# which block wins where, for the next round of tuning (not judged beyond its own checks against OpenBLAS).
step gemm_table 120 "$bench" ${device:+--device "$device"}

# The figures of the GPU-pace targets (docs/nvidia.md), each printed beside its target; JSON null where a step
# produced none. On a CPU they are far from the targets, which are for an H100 or H200: only a GPU run is judged by them.
jnum() { # KEY FILE: a number from bench_nn's one-line JSON
  sed -n "s/.*\"$1\":\([-0-9.eE+]*\).*/\1/p" "$2" 2>/dev/null | head -n 1
}
jstr() { # KEY FILE: a string from the same line
  sed -n "s/.*\"$1\":\"\([^\"]*\)\".*/\1/p" "$2" 2>/dev/null | head -n 1
}
nn_json=$out/bench_nn.txt
gemm_4096=$(jnum gemm_tflops_4096 "$nn_json") gemm_16384=$(jnum gemm_tflops_16384 "$nn_json")
gemm_dw=$(jnum gemm_tflops_dw "$nn_json")
step_4096=$(jnum nmodule_step_ms_4096 "$nn_json") step_16384=$(jnum nmodule_step_ms_16384 "$nn_json")
driver=$(jstr driver "$nn_json")
# bench_guide: "NR step A ms, ISNR step B ms: the I-Module's share of a step C %" (the default, the lagged guide;
# the same for "ISNR lag 0", the unlagged one).
guide_figure() { # LABEL FIELD(2: step ms, 3: share %)
  sed -n "s/^NR step [0-9.]* ms, $1 step \([0-9.]*\) ms: the I-Module's share of a step \(-\{0,1\}[0-9.]*\) %.*/\1 \2/p" \
    "$out/bench_guide.txt" 2>/dev/null | head -n 1 | cut -d' ' -f"$2"
}
isnr_ms=$(guide_figure ISNR 1) isnr_share=$(guide_figure ISNR 2)
lag_ms=$(guide_figure "ISNR lag 0" 1) lag_share=$(guide_figure "ISNR lag 0" 2)
share_fraction() { [ -n "$1" ] && awk -v s="$1" 'BEGIN { printf "%.4f", s / 100 }'; }
steps_per_s=""
if ! skipped train_cornell && [ -f "$run_dir/log.csv" ]; then
  steps_per_s=$(tail -n 1 "$run_dir/log.csv" | awk -F, '$2 > 0 { printf "%.2f", $1 / $2 }')
fi
# target FIGURE VALUE OP LIMIT: one line of the table in the log.
target() {
  local met=unmeasured
  [ -n "$2" ] && met=$(awk -v v="$2" -v t="$4" -v op="$3" 'BEGIN { print ((op == ">=" ? v >= t : v <= t) ? "met" : "not met") }')
  note "$(printf '%-24s %10s   target %s %s   %s' "$1" "${2:-—}" "$3" "$4" "$met")"
}
note "== the GPU-pace figures against their targets (an H100 or H200; docs/nvidia.md)"
target gemm_tflops_16384 "$gemm_16384" ">=" 40
target gemm_tflops_4096 "$gemm_4096" ">=" 30
target gemm_tflops_dw "$gemm_dw" ">=" 30
target nmodule_step_ms_16384 "$step_16384" "<=" 4.5
target nmodule_step_ms_4096 "$step_4096" "<=" 1.5
target isnr_step_ms "$isnr_ms" "<=" 6
target imodule_share "$(share_fraction "$isnr_share")" "<=" 0.10
target isnr_lag0_step_ms "$lag_ms" "<=" 6
target imodule_share_lag0 "$(share_fraction "$lag_share")" "<=" 0.10
target main_job_steps_per_s "$steps_per_s" ">=" 150

# The paper's runs (PAPER=1). The scenes of the shared set that the paper also shows (CLR_SHARED_SCENES, default
# ../shared/scenes beside the checkout; run.sh --paper points it at the bundle's copy, since that folder does not
# travel to a bare machine) are each trained twice from scratch with `train --preset paper`: ISNR with IKL, then NR
# (Table 1's columns, N = 4), at the paper's step count for the scene (paper.json), evaluated every PAPER_EVAL_EVERY
# steps against the scene's TungstenRender.exr. `train --reference` evaluates at the reference's own size, and
# Tungsten's render exists at the film's size only (720 × 1280, 1280 × 720), so the figures are at that size, not at
# the paper's 512 pixels on the longer side: a 512-pixel reference is path-traced at 32768 spp by
# bench/paper_tables.sh, far beyond this budget. The time: a scene's two runs share what is left, ISNR first with
# three fifths of it (the paper's method, whose step costs about 1.5 NR steps on a GPU) and NR with the rest, each
# under `timeout`, whose SIGTERM makes `train` stop at the end of its step with a checkpoint. A run stopped between evaluations is rendered once more at
# its last step by `render --reference`, the same figure as train's evaluation (docs/cli.md), within the PAPER_STOP_S
# kept of its share. Wooden Staircase first; Veach Ajar only where PAPER_AJAR_MIN_S are left after it. The learning
# rate follows the whole step budget: a stopped run is measured mid-schedule, unannealed, above what a run budgeted
# to the steps it reached would give.
#
# Environment (defaults in brackets): PAPER_BUDGET_S [540: the whole call, the acceptance included, so that it fits
# one 10-minute device call]; PAPER_STEPS [paper.json's: 25000 staircase, 30000 Veach Ajar]; PAPER_EVAL_EVERY [5000];
# PAPER_EVAL_SPP [4, as `render`]; PAPER_EVAL_LONG_SIDE [empty: TungstenRender.exr at the film's size; N: a reference
# path-traced by `clradiosity reference` at PAPER_REF_SPP [64] spp with the film's longer side scaled to N, for a
# rehearsal on a CPU]; PAPER_PRESET [paper; empty: the device's defaults, the CPU's scale]; PAPER_TRAIN_FLAGS (more
# `train` flags, e.g. "--batch 256"); PAPER_STOP_S [20]; PAPER_AJAR_MIN_S [240]; PAPER_RESERVE_S [15: kept for the
# summary]; PAPER_RUNS [a temporary folder, removed at the end: the run directories, whose checkpoints are too large
# to bring back].
paper_labels=""  # the runs' labels in order (staircase-nr, ...), for the table and the summary
declare -A p_status p_mape p_mape_step p_steps p_minutes p_wall p_exit p_paper_mape p_paper_minutes p_paper_steps
declare -A p_evaluation
if [ "$paper" = 1 ]; then
  paper_json=$root/bench/paper/paper.json
  scenes_dir=${CLR_SHARED_SCENES:-$root/../shared/scenes}
  [ -d "$scenes_dir" ] && scenes_dir=$(cd "$scenes_dir" && pwd)
  preset=${PAPER_PRESET-paper}
  eval_every=${PAPER_EVAL_EVERY:-5000}
  eval_spp=${PAPER_EVAL_SPP:-4}
  long_side=${PAPER_EVAL_LONG_SIDE:-}
  ref_spp=${PAPER_REF_SPP:-64}
  stop_s=${PAPER_STOP_S:-20}
  ajar_min_s=${PAPER_AJAR_MIN_S:-240}
  read -r -a train_flags <<<"${PAPER_TRAIN_FLAGS:-}"
  if [ -n "${PAPER_RUNS:-}" ]; then
    runs=$PAPER_RUNS
    mkdir -p "$runs" || exit 2
  else
    runs=$(mktemp -d) || exit 2
    trap 'rm -rf "$runs"' EXIT
  fi
fi

# paper_figure ROW METHOD KEY: a number of paper.json's Table 1 (ROW its scene, METHOD nr or isnr), read with sed since
# a bare machine may lack python3: Table 1 comes before Table 2, a row on one line.
paper_figure() {
  awk '/"table1"/ { on = 1 } /"table2"/ { on = 0 } on' "$paper_json" | grep "\"$1\":" | head -n 1 |
    sed -n "s/.*\"$2\": {\([^}]*\)}.*/\1/p" | sed -n "s/.*\"$3\": \([-0-9.eE+]*\).*/\1/p"
}
# csv_figures LOG: "STEP SECONDS MAPE MAPE_STEP" of a run's log.csv: its last row (where the training ended) and its
# last evaluation ("-" where none).
csv_figures() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { step = $col["step"]; seconds = $col["seconds"] }
    col["mape"] && $col["mape"] != "" { mape = $col["mape"]; at = $col["step"] }
    END { if (step != "") print step, seconds, (mape == "" ? "-" : mape), (at == "" ? "-" : at) }' "$1"
}

# paper_run LABEL METHOD SHARE_S: one training of `scene` from scratch, evaluated against `ref`, within SHARE_S
# seconds of wall time; its figures go into the p_* tables under LABEL-METHOD.
paper_run() {
  local run=$1-$2 method=$2 share=$3
  local dir=$runs/$run name=paper-$1-$2 limit=$(($3 - stop_s))
  local steps=${PAPER_STEPS:-${p_paper_steps[$run]}}
  p_status[$run]="not run"
  if [ "$limit" -lt 10 ]; then
    note "== $name: not run, ${share}s left of the budget"
    return
  fi
  local flags=(--method "$method" --reference "$ref" --eval-every "$eval_every" --eval-spp "$eval_spp")
  [ -n "$steps" ] && flags+=(--steps "$steps")
  [ "$method" = isnr ] && flags+=(--is-loss ikl)
  note "== $name (limit ${limit}s): train $scene ${preset:+--preset $preset} ${flags[*]} ${train_flags[*]}"
  local start=$SECONDS
  rm -rf "$dir"
  # -k: a `train` that does not stop within 15 s of the SIGTERM is killed (exit 137, a reason).
  timeout -k 15 "$limit" "$clr" train "$scene" ${preset:+--preset "$preset"} "${flags[@]}" "${train_flags[@]}" \
    -o "$dir" >"$out/$name.txt" 2>&1
  local status=$?
  p_exit[$run]=$status
  case $status in
    0) p_status[$run]="finished" ;;
    124 | 143) p_status[$run]="stopped by the budget" ;;
    *)
      p_status[$run]="train exited $status"
      reasons+=("$name: train exited $status (OUT_DIR/$name.txt)")
      ;;
  esac
  local step="" seconds="" mape="" at=""
  [ -f "$dir/log.csv" ] && read -r step seconds mape at < <(csv_figures "$dir/log.csv")
  [ "$mape" = - ] && mape=""
  [ "$at" = - ] && at=""
  # Stopped after its last evaluation: the checkpoint at its last step rendered as train's evaluation renders it.
  local render_limit=$((share - (SECONDS - start)))
  if [ "$status" != 0 ] && [ -n "$step" ] && [ "$step" != "${at:-}" ] && [ -f "$dir/model.clr" ] &&
    [ "$render_limit" -ge 5 ]; then
    echo "== render of the last checkpoint (step $step, limit ${render_limit}s)" >>"$out/$name.txt"
    local last
    last=$(timeout "$render_limit" "$clr" render "$scene" --model "$dir" --width "$ref_w" --height "$ref_h" \
      --spp "$eval_spp" --reference "$ref" -o "$dir/last.exr" 2>>"$out/$name.txt" | tee -a "$out/$name.txt" |
      grep -o 'MAPE [0-9.eE+-]*' | tail -n 1 | cut -d' ' -f2)
    [ -n "$last" ] && mape=$last at=$step
  fi
  cat "$out/$name.txt" >>"$log"
  [ -f "$dir/log.csv" ] && cp "$dir/log.csv" "$out/$name-log.csv"
  p_steps[$run]=$step
  p_mape[$run]=$mape
  p_mape_step[$run]=$at
  [ -n "$seconds" ] && p_minutes[$run]=$(awk -v s="$seconds" 'BEGIN { printf "%.2f", s / 60 }')
  p_wall[$run]=$((SECONDS - start))
  note "== $name: ${p_status[$run]} after ${p_wall[$run]}s, ${step:-no} steps, MAPE ${mape:-none}${at:+ at step $at}"
}

# paper_rows LABEL FOLDER: the scene's two rows, not run yet, with the paper's own figures beside them (Table 1).
paper_rows() {
  local label=$1 method
  row=$(sed -n "s/.*\"$2\": \"\([^\"]*\)\".*/\1/p" "$paper_json" | head -n 1)
  for method in nr isnr; do
    paper_labels+=" $label-$method"
    p_status[$label-$method]="not run"
    p_paper_mape[$label-$method]=$(paper_figure "$row" $method mape)
    p_paper_minutes[$label-$method]=$(paper_figure "$row" $method minutes)
    p_paper_steps[$label-$method]=$(paper_figure "$row" $method step)
  done
}

# paper_scene LABEL FOLDER: the scene's NR and ISNR runs in the time left.
paper_scene() {
  local label=$1 folder=$2
  paper_rows "$label" "$folder"
  scene=$scenes_dir/$folder/scene.xml
  local tungsten=$scenes_dir/$folder/TungstenRender.exr
  if [ ! -f "$scene" ] || [ ! -f "$tungsten" ]; then
    note "== paper $label: $scene or its TungstenRender.exr is missing"
    reasons+=("paper $label: no $scenes_dir/$folder (CLR_SHARED_SCENES; bench/device/pack.sh --paper packs it)")
    return
  fi
  # The film's size is Tungsten's (compare reads the EXR with the project's own reader).
  local size film_w film_h
  size=$("$clr" compare "$tungsten" "$tungsten" --json 2>/dev/null)
  film_w=$(sed -n 's/.*"width": *\([0-9]*\).*/\1/p' <<<"$size")
  film_h=$(sed -n 's/.*"height": *\([0-9]*\).*/\1/p' <<<"$size")
  ref=$tungsten ref_w=$film_w ref_h=$film_h
  p_evaluation[$label]="TungstenRender.exr ${film_w}x${film_h}"
  if [ -n "$long_side" ] && [ -n "$film_w" ] && [ -n "$film_h" ]; then
    # As bench/paper_tables.sh picks it: the longer side at N, where the aspect ratio stays exact in whole pixels.
    local w=$film_w h=$film_h
    if [ "$film_w" -ge "$film_h" ]; then
      w=$long_side h=$((film_h * long_side / film_w))
    else
      h=$long_side w=$((film_w * long_side / film_h))
    fi
    if [ $((w * film_h)) -eq $((h * film_w)) ]; then
      ref=$runs/$label-${w}x${h}-${ref_spp}spp.exr ref_w=$w ref_h=$h
      local limit=$(($(time_left) - reserve_s))
      note "== paper $label: reference ${w}x${h} at $ref_spp spp (limit ${limit}s)"
      [ "$limit" -gt 0 ] && timeout "$limit" "$clr" reference "$scene" --max-depth -1 --spp "$ref_spp" --width "$w" --height "$h" \
        -o "$ref" >>"$log" 2>&1
      [ -f "$ref" ] || { note "== paper $label: no reference"; return; }
      p_evaluation[$label]="path traced ${w}x${h} at $ref_spp spp"
    fi
  fi
  p_evaluation[$label]+=", $eval_spp spp, every $eval_every steps"
  note "== paper $label ($row): evaluations against ${p_evaluation[$label]}"
  paper_run "$label" isnr $((($(time_left) - reserve_s) * 3 / 5))
  paper_run "$label" nr $(($(time_left) - reserve_s))
}

if [ "$paper" = 1 ]; then
  rm -f "$out"/paper-*  # an earlier call's, in the same OUT_DIR
  note "== the paper's runs: $(time_left)s left of PAPER_BUDGET_S=$budget_s"
  paper_scene staircase staircase
  left=$(($(time_left) - reserve_s))
  if [ "$left" -ge "$ajar_min_s" ]; then
    paper_scene ajar veach-ajar
  else
    note "== paper ajar: not run, ${left}s left (PAPER_AJAR_MIN_S=$ajar_min_s)"
    paper_rows ajar veach-ajar
  fi
  note "== the paper's runs beside its Table 1 (its minutes: on an RTX 4090; ours: training time, evaluations excluded)"
  for run in $paper_labels; do
    shown=${p_mape[$run]:-}
    [ -n "$shown" ] && shown=$(awk -v m="$shown" 'BEGIN { printf "%.4g", m }')
    note "$(printf '%-14s MAPE %-7s %-15s (paper %s)   %6s min (paper %3s)   steps %6s of %s   %s' "$run" \
      "${shown:-—}" "${p_mape_step[$run]:+at step ${p_mape_step[$run]}}" "${p_paper_mape[$run]:-—}" \
      "${p_minutes[$run]:-—}" "${p_paper_minutes[$run]:-—}" "${p_steps[$run]:-—}" \
      "${PAPER_STEPS:-${p_paper_steps[$run]}}" "${p_status[$run]}")"
  done
fi

verdict=PASS
[ ${#reasons[@]} -gt 0 ] && verdict=FAIL
# json_number VALUE: VALUE where it is a JSON number, else null (empty, "nan").
json_number() { [[ $1 =~ ^-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$ ]] && echo "$1" || echo null; }
{
  printf '{\n  "device": "%s",\n  "driver": "%s",\n  "verdict": "%s",\n' "$(echo "$device_line" | sed 's/"/\\"/g')" \
    "$(echo "$driver" | sed 's/"/\\"/g')" "$verdict"
  for pair in "gemm_tflops_16384 $gemm_16384" "gemm_tflops_4096 $gemm_4096" "gemm_tflops_dw $gemm_dw" \
    "nmodule_step_ms_16384 $step_16384" "nmodule_step_ms_4096 $step_4096" "isnr_step_ms $isnr_ms" \
    "imodule_share $(share_fraction "$isnr_share")" "isnr_lag0_step_ms $lag_ms" \
    "imodule_share_lag0 $(share_fraction "$lag_share")" "main_job_steps_per_s $steps_per_s" "main_job_mape $mape"; do
    set -- $pair
    printf '  "%s": %s,\n' "$1" "${2:-null}"
  done
  printf '  "cornell_isnr_2min_mape": %s,\n' "${mape:-null}"
  printf '  "render_512_seconds": %s,\n' "${render_s:-null}"
  if [ "$paper" = 1 ]; then
    # Each paper run: MAPE (its last evaluation, at mape_step), minutes of training, steps reached, wall seconds,
    # train's exit status and what it means; then the paper's own Table 1 figures (_paper). null where not run.
    printf '  "paper_budget_s": %s,\n  "paper_preset": "%s",\n' "$budget_s" "$preset"
    for label in staircase ajar; do
      printf '  "paper_%s_evaluation": %s,\n' "$label" \
        "$([ -n "${p_evaluation[$label]:-}" ] && echo "\"${p_evaluation[$label]}\"" || echo null)"
    done
    for run in $paper_labels; do
      key=paper_${run//-/_}
      for pair in "mape ${p_mape[$run]:-}" "mape_step ${p_mape_step[$run]:-}" "minutes ${p_minutes[$run]:-}" \
        "steps ${p_steps[$run]:-}" "wall_seconds ${p_wall[$run]:-}" "exit ${p_exit[$run]:-}" \
        "mape_paper ${p_paper_mape[$run]:-}" "minutes_paper ${p_paper_minutes[$run]:-}" \
        "steps_paper ${p_paper_steps[$run]:-}"; do
        set -- $pair
        printf '  "%s_%s": %s,\n' "$key" "$1" "$(json_number "${2:-}")"
      done
      printf '  "%s_status": "%s",\n' "$key" "${p_status[$run]}"
    done
  fi
  printf '  "steps": {%s},\n' "$json_steps"
  printf '  "reasons": ['
  sep=""
  for r in "${reasons[@]}"; do
    printf '%s"%s"' "$sep" "$(echo "$r" | sed 's/"/\\"/g')"
    sep=", "
  done
  printf ']\n}\n'
} >"$out/summary.json"
note "summary: $out/summary.json"
if [ "$verdict" = PASS ]; then
  echo "PASS"
else
  (IFS=';'; echo "FAIL: ${reasons[*]}")
  exit 1
fi
