#!/usr/bin/env bash
# Soak test (issue 16): train for MINUTES on the default device and log resident memory (VmRSS) and device memory
# every INTERVAL seconds, then check that memory stays flat after warm-up and that log.csv holds no NaN.
#
#   bench/soak.sh SCENE.xml MINUTES [INTERVAL_S] [CLRADIOSITY] [-- extra train options]
#
# Prints one row per sample (seconds, VmRSS MiB, device MiB) and a verdict; exits 1 when memory grew or a loss
# was not finite. Device memory comes from nvidia-smi where it exists; on PoCL the device's buffers are host memory
# and already in VmRSS. "Flat": the mean of the last quarter of samples is within GROWTH_PCT (default 5 %) of the
# mean of the second quarter (the first is warm-up: buffers grow to the batch, kernels compile). A leak of one
# batch's buffers per step would double memory within seconds; 5 % leaves room for allocator noise.
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
# Columns: step, seconds, loss, lookups, non_finite, … (README). A NaN loss would print as nan or -nan.
bad_loss=$(awk -F, 'NR > 1 && ($3 ~ /nan|inf/) { n++ } END { print n + 0 }' "$log")
dropped=$(awk -F, 'NR > 1 { s += $5 } END { print s + 0 }' "$log")
verdict=$(awk -F, -v g="$growth_pct" 'NR > 1 { r[++n] = $2 }
  END {
    if (n < 8) { print "too few samples (" n ") to judge"; exit }
    q = int(n / 4)
    for (i = q + 1; i <= 2 * q; i++) a += r[i]
    for (i = n - q + 1; i <= n; i++) b += r[i]
    a /= q; b /= q
    printf "%s: VmRSS %.1f MiB (2nd quarter) -> %.1f MiB (last quarter), %+.2f %%, peak %.1f MiB\n",
      (b - a) / a * 100 <= g ? "flat" : "GREW", a, b, (b - a) / a * 100, max(r, n)
  }
  function max(x, n,   m, i) { m = x[1]; for (i = 2; i <= n; i++) if (x[i] > m) m = x[i]; return m }' "$samples")
echo "soak: $steps steps in $minutes min; $verdict; non-finite losses in log.csv: $bad_loss; dropped samples: $dropped"
echo "soak: samples in $samples, run in $run/run"
[[ $verdict == flat* && $bad_loss == 0 ]]
