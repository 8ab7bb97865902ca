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

note() { echo "$*" | tee -a "$log"; }
# step NAME LIMIT_S COMMAND...: runs COMMAND with its output in OUT_DIR/NAME.txt and the log; records its status and
# seconds.
step() {
  local name=$1 limit=$2
  shift 2
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

for f in "$clr" "$bench" "$tests" "$build/bench/bench_guide" "$build/bench/bench_pipeline"; do
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
if [ -z "$mape" ]; then
  reasons+=("no MAPE from the Cornell training")
elif ! awk -v m="$mape" -v max="$mape_max" 'BEGIN { exit !(m == m + 0 && m <= max) }'; then
  reasons+=("Cornell MAPE $mape above $mape_max")
fi

render_s=""
run_dir=$out/clradiosity-out/cornell-box-run
if [ -d "$run_dir" ]; then
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
if [ -f "$run_dir/log.csv" ]; then
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

verdict=PASS
[ ${#reasons[@]} -gt 0 ] && verdict=FAIL
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
