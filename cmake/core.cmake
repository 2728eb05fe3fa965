# The ROS-free physics core: every .cpp under src/core, Eigen and yaml-cpp only.
# Included by the catkin build (CMakeLists.txt) and by the sanitizer build (test/sanitize).
get_filename_component(TT_ROOT "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)

find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
find_package(Threads REQUIRED)
# OpenMP runs the per-element loops on tt::setThreadCount() threads (src/core/parallel.cpp);
# without it the core stays sequential.
find_package(OpenMP COMPONENTS CXX)

file(GLOB_RECURSE TT_CORE_FILES CONFIGURE_DEPENDS
  "${TT_ROOT}/src/core/*.cpp" "${TT_ROOT}/src/core/*.h" "${TT_ROOT}/include/tissue_trainer/core/*.h")
foreach(f ${TT_CORE_FILES})
  file(STRINGS "${f}" ros_includes REGEX "#include[ \t]*[<\"](ros|tf2|rosbag|sensor_msgs|geometry_msgs)/")
  if(ros_includes)
    message(FATAL_ERROR "${f}: the core must not include ROS headers (${ros_includes})")
  endif()
endforeach()

file(GLOB_RECURSE TT_CORE_SOURCES CONFIGURE_DEPENDS "${TT_ROOT}/src/core/*.cpp")
# Rooms with a dependency of their own are libraries of their own (below).
list(FILTER TT_CORE_SOURCES EXCLUDE REGEX "/src/core/contact/")
add_library(tissue_trainer_core ${TT_CORE_SOURCES})
target_include_directories(tissue_trainer_core PUBLIC "${TT_ROOT}/include")
target_link_libraries(tissue_trainer_core PUBLIC Eigen3::Eigen yaml-cpp Threads::Threads)
target_compile_features(tissue_trainer_core PUBLIC cxx_std_17)
target_compile_options(tissue_trainer_core PRIVATE -Wall -Wextra)
# CHOLMOD (SuiteSparse 5, Debian's libsuitesparse-dev: no CMake package of its own) for the
# Cholesky preconditioner of the implicit solver, and UMFPACK for the real and complex sparse
# LU of the Radau IIA integrator (a compiled library: Eigen's own SparseLU, a header template
# instantiated for both scalar types, made this one file take a minute to compile; 26 s now).
find_path(TT_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(TT_CHOLMOD_LIBRARY cholmod)
find_library(TT_UMFPACK_LIBRARY umfpack)
if(NOT TT_CHOLMOD_INCLUDE_DIR OR NOT TT_CHOLMOD_LIBRARY OR NOT TT_UMFPACK_LIBRARY)
  message(FATAL_ERROR "CHOLMOD or UMFPACK not found: install Debian's libsuitesparse-dev")
endif()
target_include_directories(tissue_trainer_core PRIVATE "${TT_CHOLMOD_INCLUDE_DIR}")
target_link_libraries(tissue_trainer_core PRIVATE "${TT_CHOLMOD_LIBRARY}" "${TT_UMFPACK_LIBRARY}")
# hypre's BoomerAMG (Debian's libhypre-dev: no CMake package of its own) for the algebraic
# multigrid preconditioner of the implicit solver. Debian builds hypre with MPI, so its
# headers include mpi.h and its library needs MPI initialised (mpi-default-dev: OpenMPI).
find_path(TT_HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre)
find_library(TT_HYPRE_LIBRARY HYPRE)
set(MPI_CXX_SKIP_MPICXX ON)  # the C interface only
find_package(MPI COMPONENTS CXX)
if(NOT TT_HYPRE_INCLUDE_DIR OR NOT TT_HYPRE_LIBRARY OR NOT MPI_CXX_FOUND)
  message(FATAL_ERROR "hypre or MPI not found: install Debian's libhypre-dev and mpi-default-dev")
endif()
target_include_directories(tissue_trainer_core PRIVATE "${TT_HYPRE_INCLUDE_DIR}")
target_link_libraries(tissue_trainer_core PRIVATE "${TT_HYPRE_LIBRARY}" MPI::MPI_CXX)
if(OpenMP_CXX_FOUND)
  target_link_libraries(tissue_trainer_core PRIVATE OpenMP::OpenMP_CXX)
  target_compile_definitions(tissue_trainer_core PRIVATE TT_HAVE_OPENMP)
endif()
# The element kernels are small fixed-size Eigen expressions inside long loops: -O3 (inlining,
# unrolling and SLP vectorisation of the 3x3 products) runs the StVK force loop about 1.7x
# faster than -O2 with gcc 12 (12 -> 21 M tets/s on the 10k-tet grid). Only for optimised
# builds, and portable: no -march, so the binary runs on any x86-64 CPU.
# TT_CORE_O3=OFF leaves the build type's level (the sanitizer build compiles at -O1).
option(TT_CORE_O3 "Compile the core at -O3 in optimised builds" ON)
if(TT_CORE_O3 AND
   (CMAKE_BUILD_TYPE MATCHES "^(Release|RelWithDebInfo|MinSizeRel)$" OR NOT CMAKE_BUILD_TYPE))
  target_compile_options(tissue_trainer_core PRIVATE -O3)
endif()
set_target_properties(tissue_trainer_core PROPERTIES POSITION_INDEPENDENT_CODE ON)
# The core compiles in batches of 8 files, each batch one translation unit (CMake's unity
# build): a batch parses and instantiates once what its files share. It cut the core's
# compilation from 575 to 325 s of one core (docs/building.md). Helpers in unnamed namespaces
# must therefore have names distinct across the core's files. TT_CORE_UNITY=OFF compiles file
# by file.
# The law registrations (12-17 s each) compile one by one, so that an edit of any core file
# recompiles at most about 30 s: batched together they took 58 s.
option(TT_CORE_UNITY "Compile the core in unity batches" ON)
if(TT_CORE_UNITY)
  set_target_properties(tissue_trainer_core PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  file(GLOB TT_LAW_REGISTRATIONS "${TT_ROOT}/src/core/material/*_registration.cpp")
  set_source_files_properties(${TT_LAW_REGISTRATIONS} "${TT_ROOT}/src/core/material/psd_projection.cpp"
    PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
endif()
# Every core file parses Eigen and much of the standard library, about 140,000 lines before
# its own code: a precompiled header parses them once for the whole library.
option(TT_CORE_PCH "Precompile the headers every core file includes" ON)
if(TT_CORE_PCH)
  target_precompile_headers(tissue_trainer_core PRIVATE
    <Eigen/Core> <Eigen/Geometry> <Eigen/SparseCore> <algorithm> <cmath> <functional> <memory>
    <stdexcept> <string> <vector>)
endif()

# Instrument-tissue contact: Bullet collision detection (CMake's FindBullet gives absolute
# paths; Debian's BulletConfig.cmake does not).
set(TT_OPTIONAL_CORE_LIBRARIES "")
file(GLOB_RECURSE TT_CONTACT_SOURCES CONFIGURE_DEPENDS "${TT_ROOT}/src/core/contact/*.cpp")
if(TT_CONTACT_SOURCES)
  find_package(Bullet REQUIRED)
  add_library(tissue_trainer_contact ${TT_CONTACT_SOURCES})
  target_include_directories(tissue_trainer_contact PUBLIC ${BULLET_INCLUDE_DIRS})
  target_link_libraries(tissue_trainer_contact PUBLIC tissue_trainer_core ${BULLET_LIBRARIES})
  target_compile_options(tissue_trainer_contact PRIVATE -Wall -Wextra)
  set_target_properties(tissue_trainer_contact PROPERTIES POSITION_INDEPENDENT_CODE ON)
  list(APPEND TT_OPTIONAL_CORE_LIBRARIES tissue_trainer_contact)
endif()
