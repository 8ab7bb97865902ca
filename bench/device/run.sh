#!/usr/bin/env bash
# On a bare GPU machine (a driver, no network, no build dependencies), from the repository root, with the archive
# of bench/device/pack.sh: unpacks it, registers the NVIDIA OpenCL driver with the packed ICD loader, and runs
# bench/gpu_acceptance.sh on the GPU (docs/nvidia.md):
#
#   bench/device/run.sh [--paper] BUNDLE OUT_DIR [DEVICE]     (DEVICE default nvidia)
#
# --paper sets PAPER=1: after the acceptance figures, the paper's runs on Wooden Staircase and Veach Ajar (the header
# of gpu_acceptance.sh), the whole within PAPER_BUDGET_S (default 540 s, counted from this script's start, the
# unpacking included) so that it fits one 10-minute device call. Their scenes come from the bundle where
# `bench/device/pack.sh --paper` packed them (the ../shared beside a checkout does not travel to a device machine),
# else from CLR_SHARED_SCENES.
#
# or, for a measurement of its own in the same setting, runs COMMAND with BUILD_DIR set to the unpacked build tree
# (e.g. "$BUILD_DIR"/bench/bench_nn --device nvidia):
#
#   bench/device/run.sh --exec BUNDLE COMMAND...
set -uo pipefail
# The paper mode's budget starts here.
export PAPER_START=${PAPER_START:-$(date +%s)}
usage="usage: bench/device/run.sh [--paper] BUNDLE OUT_DIR [DEVICE] | bench/device/run.sh --exec BUNDLE COMMAND..."
exec_mode=false
if [ "${1:-}" = --paper ]; then
  export PAPER=1
  shift
fi
if [ "${1:-}" = --exec ]; then
  exec_mode=true
  shift
  [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
  bundle=$1
  shift
else
  [ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
  bundle=$1 out=$2 device=${3:-nvidia}
fi
root=$(cd "$(dirname "$0")/../.." && pwd)
unpacked=$(mktemp -d)
trap 'rm -rf "$unpacked"' EXIT
[ -f "$bundle" ] || { echo "run: no bundle at $bundle (bench/device/pack.sh makes it)" >&2; exit 2; }
tar -C "$unpacked" -xJf "$bundle" || { echo "run: cannot unpack $bundle" >&2; exit 2; }
# The paper's scenes, where the bundle carries them and CLR_SHARED_SCENES names no folder of its own.
if [ -d "$unpacked/scenes" ] && [ ! -d "${CLR_SHARED_SCENES:-/nonexistent}" ]; then
  export CLR_SHARED_SCENES=$unpacked/scenes
fi
# The binaries read scenes through the source folder they were built in: point that path at this checkout.
source_dir=$(cat "$unpacked/source_dir")
if [ ! -e "$source_dir" ]; then
  mkdir -p "$(dirname "$source_dir")" && ln -s "$root" "$source_dir"
fi
# The driver's OpenCL library, where NVIDIA's container images mount it or a distribution installs it.
icd=""
for dir in /usr/local/nvidia/lib64 /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/local/nvidia/lib; do
  [ -e "$dir/libnvidia-opencl.so.1" ] && { icd=$dir/libnvidia-opencl.so.1; break; }
done
# The packed loader reads OCL_ICD_VENDORS: the system's registrations (a driver that fails to load is skipped) and
# NVIDIA's, which its container images do not register.
mkdir -p "$unpacked/vendors"
cp /etc/OpenCL/vendors/*.icd "$unpacked/vendors/" 2>/dev/null
[ -n "$icd" ] && echo "$icd" >"$unpacked/vendors/nvidia.icd"
export OCL_ICD_VENDORS=$unpacked/vendors
export LD_LIBRARY_PATH=$unpacked/lib${icd:+:$(dirname "$icd")}${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
echo "NVIDIA OpenCL driver: ${icd:-not found}"
if $exec_mode; then
  BUILD_DIR=$unpacked/build "$@"
else
  BUILD_DIR=$unpacked/build "$root/bench/gpu_acceptance.sh" "$device" "$out"
fi
