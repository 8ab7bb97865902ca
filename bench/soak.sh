#!/usr/bin/env bash
# Soak test (issue 16): train for MINUTES on the default device and log resident memory (VmRSS) and device memory
# every INTERVAL seconds, then check that memory stays flat after warm-up and that log.csv holds no NaN.
#
#   bench/soak.sh SCENE.xml MINUTES [INTERVAL_S] [CLRADIOSITY] [-- extra train options]
#
# Prints one row per sample (seconds, VmRSS MiB, device MiB) and a verdict; exits 1 when memory grew or a loss
# was not finite. Device memory comes from nvidia-smi where it exists; on PoCL the device's buffers are host memory
# and already in VmRSS. "Flat": the VmRSS slope over the last half of the samples (the first half is warm-up),
# projected over the whole run, is within GROWTH_PCT (default 5 %) of the mean. A leak of one batch's buffers per
# step would double memory within seconds; 5 % leaves room for allocator noise.
set -euo pipefail

scene=${1:?usage: soak.sh SCENE.xml MINUTES [INTERVAL_S] [CLRADIOSITY] [-- train options]}
minutes=${2:?minutes}
interval=${3:-5}
bin=${4:-build/release/clradiosity}
shift $(($# < 4 ? $# : 4))
[[ ${1:-} == -- ]] && shift
growth_pct=${GROWTH_PCT:-5}

run=$(mktemp -d "${TMPDIR:-/tmp}/clr_soak.XXXXXX")
samples="$run/memory.csv"
trap 'kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true' EXIT

"$bin" train "$scene" --minutes "$minutes" "$@" -o "$run/run" >"$run/train.out" 2>&1 &
pid=$!
start=$(date +%s.%N)

device_mib() {
  if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-compute-apps=pid,used_memory --format=csv,noheader,nounits 2>/dev/null |
      awk -F', *' -v p="$1" '$1 == p { print $2; found = 1 } END { if (!found) print "na" }'
  else
    echo na
  fi
}

echo "seconds,vmrss_mib,device_mib" | tee "$samples"
while kill -0 "$pid" 2>/dev/null; do
  rss_kib=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2>/dev/null || true)
  [[ -n $rss_kib ]] || break
  now=$(date +%s.%N)
  printf '%.1f,%.1f,%s\n' "$(echo "$now - $start" | bc)" "$(echo "$rss_kib / 1024" | bc -l)" "$(device_mib "$pid")" |
    tee -a "$samples"
  sleep "$interval"
done
trap - EXIT
wait "$pid" || { echo "soak: training failed:"; tail -n 3 "$run/train.out"; exit 1; }

log="$run/run/log.csv"
steps=$(tail -n 1 "$log" | cut -d, -f1)
# Columns: step, seconds, loss, lookups, non_finite, … (docs/cli.md, "The run directory"). A NaN loss would print
# as nan or -nan.
bad_loss=$(awk -F, 'NR > 1 && ($3 ~ /nan|inf/) { n++ } END { print n + 0 }' "$log")
dropped=$(awk -F, 'NR > 1 { s += $5 } END { print s + 0 }' "$log")
verdict=$(awk -F, -v g="$growth_pct" 'NR > 1 { t[++n] = $1; r[n] = $2; if ($2 > peak) peak = $2 }
  END {
    if (n < 8) { print "too few samples (" n ") to judge"; exit }
    # Least-squares slope of VmRSS over the last half (the first holds warm-up: grow-only buffers reach the largest
    # batch, the host copies of the first checkpoint), projected over the whole run.
    h = int(n / 2)
    for (i = h + 1; i <= n; i++) { m++; st += t[i]; sr += r[i]; stt += t[i] * t[i]; str += t[i] * r[i] }
    slope = (m * str - st * sr) / (m * stt - st * st)  # MiB per second
    mean = sr / m
    grow = slope * t[n] / mean * 100
    printf "%s: VmRSS %.1f MiB after warm-up (peak %.1f), slope %+.3f MiB/min over the last half = %+.2f %% over the run\n",
      grow <= g ? "flat" : "GREW", mean, peak, slope * 60, grow
  }' "$samples")
echo "soak: $steps steps in $minutes min; $verdict; non-finite losses in log.csv: $bad_loss; dropped samples: $dropped"
echo "soak: samples in $samples, run in $run/run"
[[ $verdict == flat* && $bad_loss == 0 ]]
