# Every dependency comes from a Debian 12 package (.ci/install-deps installs them).
# They are gathered behind one interface target, clr_deps, with SYSTEM includes so that -Werror never
# fires inside a third-party header.
find_package(OpenCL REQUIRED)
find_package(embree 3 REQUIRED)
find_package(OpenEXR REQUIRED)
find_package(glm REQUIRED)
find_package(CLBlast REQUIRED)
find_package(pugixml REQUIRED)
find_package(tinyobjloader REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(Threads REQUIRED)
# oneTBB: the host's persistent worker pool (common/parallel.*); Embree already runs its BVH builds on it.
find_package(TBB REQUIRED)
find_package(ZLIB REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)

add_library(clr_deps INTERFACE)
target_link_libraries(clr_deps INTERFACE OpenCL::OpenCL embree OpenEXR::OpenEXR glm::glm clblast pugixml::pugixml
                                         tinyobjloader::tinyobjloader CLI11::CLI11 nlohmann_json::nlohmann_json
                                         PkgConfig::STB Threads::Threads TBB::tbb ZLIB::ZLIB)
# GLM: radians everywhere, explicit constructors keep float/double mixing visible.
target_compile_definitions(clr_deps INTERFACE GLM_FORCE_RADIANS GLM_FORCE_XYZW_ONLY)

# MPI is optional (data-parallel training and distributed references, docs/mpi.md): on when found, and without
# it the build and every command behave as a single process. Only host/distributed/communicator_mpi.cpp sees
# mpi.h, so switching it changes one object file rather than the whole library.
find_package(MPI COMPONENTS C QUIET)
option(CLR_MPI "Build the MPI communicator (mpirun -np R clradiosity train|reference)" ${MPI_C_FOUND})
if(CLR_MPI AND NOT MPI_C_FOUND)
  message(FATAL_ERROR "CLR_MPI is on but no MPI was found (apt-get install libopenmpi-dev openmpi-bin)")
endif()
message(STATUS "MPI: ${CLR_MPI}")
