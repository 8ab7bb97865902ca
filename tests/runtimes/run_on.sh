#!/usr/bin/env bash
# Runs a test binary on one OpenCL implementation (tests/runtimes/lanes.cmake adds one ctest entry per lane):
#   run_on.sh intel    RT_DIR     WORK_DIR -- COMMAND...  Intel's CPU runtime from the venv .ci/install-intel-opencl-rt makes
#   run_on.sh oclgrind ICD_LIBRARY WORK_DIR -- COMMAND... the Oclgrind simulator, its race, bounds, uninitialised
#                                                         and API checks on; any report fails the run
#   run_on.sh oclgrind-vectors ...                        the same without the uninitialised-value check
#   run_on.sh nvidia-limits - WORK_DIR -- COMMAND...      the default device clamped to NVIDIA's limits
# Only that implementation is visible (OCL_ICD_VENDORS names one .icd), so the tests' default device rule picks
# it, and CLR_TEST_EXPECT_DEVICE makes the tests fail if they ran on anything else (or on nothing: a runtime that
# failed to load would otherwise skip every test). A runtime that is not installed exits 77, which ctest reports as skipped, with one line saying why.
set -uo pipefail
lane=$1 where=$2 work=$3
shift 3
[ "${1:-}" = "--" ] && shift
mkdir -p "$work"

skip() {
  echo "SKIPPED ($lane): $*"
  exit 77
}

case "$lane" in
  intel)
    lib="$where/lib/libintelocl.so"
    [ -f "$lib" ] || skip "Intel's OpenCL CPU runtime is not installed at $where (.ci/install-intel-opencl-rt installs it with pip)"
    mkdir -p "$work/vendors" "$work/lib"
    # The wheel's own .icd names a placeholder path; this one names the installed library.
    echo "$lib" >"$work/vendors/intel-cpu.icd"
    # The runtime's libraries without the wheel's own libOpenCL, so the system's ICD loader stays in charge.
    for f in "$where"/lib/*.so*; do
      case "$(basename "$f")" in libOpenCL*) ;; *) ln -sf "$f" "$work/lib/" ;; esac
    done
    export OCL_ICD_VENDORS="$work/vendors"
    export LD_LIBRARY_PATH="$work/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    export CLR_TEST_EXPECT_DEVICE="Intel(R) OpenCL"
    exec "$@"
    ;;
  oclgrind | oclgrind-vectors)
    [ -f "$where" ] || skip "Oclgrind is not installed (apt-get install oclgrind)"
    mkdir -p "$work/vendors"
    echo "$where" >"$work/vendors/oclgrind.icd"
    export OCL_ICD_VENDORS="$work/vendors"
    # The default device rule never picks a simulator: the tests name it.
    export CLRADIOSITY_DEVICE=oclgrind CLR_TEST_EXPECT_DEVICE=Oclgrind
    export OCLGRIND_CHECK_API=1 OCLGRIND_DATA_RACES=1
    # Oclgrind 21.10's uninitialised-value plugin itself crashes (SIGSEGV in Uninitialized::instructionExecuted)
    # on kernels that load float3/float8 vectors (the RHS, the vMF mixture): those run in the oclgrind-vectors
    # lane with every other check on.
    [ "$lane" = oclgrind ] && export OCLGRIND_UNINITIALIZED=1
    # Bounds checks are always on. Reports go to a log file, not interleaved with the tests' output.
    log="$work/oclgrind.log"
    rm -f "$log"
    export OCLGRIND_LOG="$log"
    "$@"
    status=$?
    if [ -s "$log" ]; then
      echo "Oclgrind reported errors (log: $log):"
      head -n 200 "$log"
      exit 1
    fi
    exit $status
    ;;
  nvidia-limits)
    export CLRADIOSITY_EMULATE_LIMITS=nvidia CLR_TEST_EXPECT_DEVICE="[nvidia limits]"
    exec "$@"
    ;;
  *)
    echo "run_on.sh: unknown lane '$lane'" >&2
    exit 2
    ;;
esac
