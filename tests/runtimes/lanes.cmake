# The kernel and engine tests on more than PoCL (docs/nvidia.md). Included by tests/CMakeLists.txt.
#
# Groups, by gtest suite: `kernel` — the device layer and every kernel against its host twin; `engine` — training,
# rendering and the numerical extremes built on them. PoCL runs them as one ctest entry per test (labelled here);
# each other lane runs a group in one process, so its programs compile once:
#   intel.*          Intel's OpenCL CPU runtime (pip wheel in a venv that .ci/install-intel-opencl-rt makes)
#   nvidia_limits.*  PoCL with CLRADIOSITY_EMULATE_LIMITS=nvidia (work-group 1024, 48 KiB local, ¼ allocation, ...)
#   oclgrind.kernel  the small kernel tests under the Oclgrind simulator with its checks on (an interpreter: the
#                    engine tests and the GEMM tile sweep would take hours there)
#   NvptxCompile.*   every host program compiled for nvptx64-nvidia-nvcl by clang-15 with libclc (per-test entries)
# A lane whose runtime or tools are missing is skipped (exit 77) with a line saying what to install.
set(CLR_KERNEL_SUITES ClTest ReduceKernel KernelSource DeviceList DeviceLimits GemmTest MlpTest HashGridTest LossTest
                      CheckpointTest)
set(CLR_ENGINE_SUITES Training ExtremeFurnace ExtremeSceneScale ExtremeRadianceScale Renderer)
# Under Oclgrind: kernel tests whose sizes an interpreter finishes in seconds. Oclgrind 21.10's uninitialised-value
# check misreads vector-typed kernels (it flags the GEMM's float4 fma) and then crashes inside itself (SIGSEGV in
# Uninitialized::instructionExecuted, on float3/float8 loads), so the kernels with vector types run in a second
# entry with every other check on. Left out: the GEMM backend probe and the chi² sampling tests, which take minutes
# there; the fused MLP's test takes ~40 s and stays in, as the only test of mlp_fused.cl. The local-memory tiled GEMM
# (scalar code) passes every check when its test runs alone, but after the other tests in one process the
# uninitialised-value check reports its panel stores of in-bounds, host-written input (as it does for gemm_own; not
# diagnosed further), so it too runs in the second entry, where the race check covers its barriers and local memory.
set(CLR_OCLGRIND_TESTS ReduceKernel.* ClTest.FillWritesExactlyTheRange ClTest.Oversized* ClTest.MemoryAccountingTracksPeak
                       ClTest.Adam* Powers/LossTest.* ClTest.ShForwardAndGradientMatchTwin Accumulation/HashGridTest.*
                       GemmTest.TiledBlocksFitNvidiasLimits)
set(CLR_OCLGRIND_VECTOR_TESTS ClTest.IncidentRhsMatchesDoubleTwin ClTest.VmfStaysFiniteAtTheExtremes
                              ClTest.VmfLogPdfGradientMatchesFiniteDifferences
                              ClTest.GuideKlAndIklGradientsMatchFiniteDifferences ClTest.IklFlipsTheKlGradientWherePIsBelowQ
                              GemmTest.OwnKernelMatchesTwinWithEveryTile GemmTest.TiledKernelMatchesTwinWithEveryBlock
                              Shapes/MlpTest.* ClTest.EncoderConcatenatesItsParts
                              ClTest.ChunkedInferenceMatchesOnePiece ClTest.FusedSmallMlpMatchesLayerPath)

set(CLR_INTEL_OPENCL_RT ${CMAKE_SOURCE_DIR}/build/intel-opencl-rt
    CACHE PATH "venv holding Intel's OpenCL CPU runtime (pip install intel-opencl-rt intel-cmplr-lib-rt)")
find_file(CLR_OCLGRIND_ICD liboclgrind-rt-icd.so PATHS /usr/lib/oclgrind /usr/lib/x86_64-linux-gnu/oclgrind)
# libclc-15's bitcode is read only by an LLVM 15 clang: Debian 12's plain `clang` is 14.
find_program(CLR_NVPTX_CLANG_EXE NAMES clang-15)
find_file(CLR_LIBCLC_NVPTX nvptx64--nvidiacl.bc PATHS /usr/lib/clc /usr/lib/llvm-15/lib/clc /usr/share/clc)
set(clang_path "")
set(libclc_path "")
if(CLR_NVPTX_CLANG_EXE)
  set(clang_path ${CLR_NVPTX_CLANG_EXE})
endif()
if(CLR_LIBCLC_NVPTX)
  set(libclc_path ${CLR_LIBCLC_NVPTX})
endif()
target_compile_definitions(clr_tests PRIVATE CLR_NVPTX_CLANG="${clang_path}" CLR_NVPTX_LIBCLC="${libclc_path}")

# "*Suite.*": parameterised suites carry an instantiation prefix ("Powers/LossTest.").
list(JOIN CLR_KERNEL_SUITES ".*:*" kernel_filter)
list(JOIN CLR_ENGINE_SUITES ".*:*" engine_filter)
list(JOIN CLR_OCLGRIND_TESTS ":" filter_oclgrind)
list(JOIN CLR_OCLGRIND_VECTOR_TESTS ":" filter_oclgrind_vectors)
set(filter_kernel "*${kernel_filter}.*")
set(filter_engine "*${engine_filter}.*")
set(lane_runner ${CMAKE_CURRENT_SOURCE_DIR}/runtimes/run_on.sh)
set(lane_work ${CMAKE_CURRENT_BINARY_DIR}/lanes)

# One ctest entry NAME: run_on.sh LANE WHERE runs clr_tests with FILTER; labelled with the lane and GROUP.
function(clr_add_lane name lane where group filter timeout)
  add_test(NAME ${name} COMMAND bash ${lane_runner} ${lane} ${where} ${lane_work}/${name} -- $<TARGET_FILE:clr_tests>
                                --gtest_filter=${filter})
  string(REGEX REPLACE "\\..*" "" lane_label ${name})
  set_tests_properties(${name} PROPERTIES LABELS "${lane_label};${group}" SKIP_RETURN_CODE 77 TIMEOUT ${timeout})
endfunction()

# The runtime is installed by the test run itself (a fixture), so the main job's build never downloads it.
add_test(NAME intel.install COMMAND bash ${CMAKE_SOURCE_DIR}/.ci/install-intel-opencl-rt ${CLR_INTEL_OPENCL_RT})
set_tests_properties(intel.install PROPERTIES FIXTURES_SETUP intel_rt LABELS intel TIMEOUT 900)
clr_add_lane(intel.kernel intel ${CLR_INTEL_OPENCL_RT} kernel ${filter_kernel} 900)
clr_add_lane(intel.engine intel ${CLR_INTEL_OPENCL_RT} engine ${filter_engine} 900)
set_tests_properties(intel.kernel intel.engine PROPERTIES FIXTURES_REQUIRED intel_rt)
clr_add_lane(nvidia_limits.kernel nvidia-limits - kernel ${filter_kernel} 900)
clr_add_lane(nvidia_limits.engine nvidia-limits - engine ${filter_engine} 900)
set(oclgrind_icd /nonexistent/liboclgrind-rt-icd.so)
if(CLR_OCLGRIND_ICD)
  set(oclgrind_icd ${CLR_OCLGRIND_ICD})
endif()
clr_add_lane(oclgrind.kernel oclgrind ${oclgrind_icd} kernel ${filter_oclgrind} 600)
clr_add_lane(oclgrind.kernel_vectors oclgrind-vectors ${oclgrind_icd} kernel ${filter_oclgrind_vectors} 600)

# Labels for PoCL's per-test entries, set when ctest lists the tests (gtest_discover_tests runs at test time).
string(REPLACE ";" "|" kernel_re "${CLR_KERNEL_SUITES}")
string(REPLACE ";" "|" engine_re "${CLR_ENGINE_SUITES}")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/clr_test_labels.cmake
     "foreach(t IN LISTS clr_tests_TESTS)\n"
     "  if(t MATCHES \"^([A-Za-z0-9_]+/)?(${kernel_re})\\\\.\")\n"
     "    set_tests_properties(\"\${t}\" PROPERTIES LABELS \"pocl;kernel\")\n"
     "  elseif(t MATCHES \"^([A-Za-z0-9_]+/)?(${engine_re})\\\\.\")\n"
     "    set_tests_properties(\"\${t}\" PROPERTIES LABELS \"pocl;engine\")\n"
     "  elseif(t MATCHES \"^EveryHostProgram/NvptxCompile\\\\.|^NvptxCompileTarget\\\\.\")\n"
     "    set_tests_properties(\"\${t}\" PROPERTIES LABELS nvptx)\n"
     "  endif()\n"
     "endforeach()\n")
set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${CMAKE_CURRENT_BINARY_DIR}/clr_test_labels.cmake)
