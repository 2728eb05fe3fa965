# The command-line tools and benchmarks, one executable per .cpp with a main():
#   src/tools/cli/    tissue_cli, the command-line face of the core
#   src/tools/bench/  speed, error against run time and stability (scripts/bench)
#   src/tools/repro/  the papers' figures, tables and experiments
# each linked with the core; TT_TOOLS lists them. Included by the catkin build (CMakeLists.txt)
# and by the standalone build (test/standalone, TT_BUILD_TOOLS=ON), after cmake/core.cmake.
set(TT_TOOLS "")
# What the programs share, compiled once (src/tools/common, included as "common/NAME.h"): the
# command line, clocks and option lists, the liver and muscle scenes, and the work-precision
# problems with their CSV rows (common/work_precision/).
file(GLOB TT_TOOLS_COMMON_SOURCES CONFIGURE_DEPENDS "${TT_ROOT}/src/tools/common/*.cpp"
     "${TT_ROOT}/src/tools/common/work_precision/*.cpp")
add_library(tt_tools_common STATIC ${TT_TOOLS_COMMON_SOURCES})
target_include_directories(tt_tools_common PUBLIC "${TT_ROOT}/src/tools")
target_link_libraries(tt_tools_common PUBLIC tissue_trainer_core)
target_compile_options(tt_tools_common PRIVATE -Wall -Wextra)
# Where the repository's config/ is when $TT_SOURCE_DIR does not say (liver_bench_scene.cpp).
target_compile_definitions(tt_tools_common PRIVATE TT_SOURCE_ROOT="${TT_ROOT}")
file(GLOB TT_TOOL_SOURCES CONFIGURE_DEPENDS "${TT_ROOT}/src/tools/cli/*.cpp"
     "${TT_ROOT}/src/tools/bench/*.cpp" "${TT_ROOT}/src/tools/repro/*.cpp")
foreach(src ${TT_TOOL_SOURCES})
  get_filename_component(tool ${src} NAME_WE)
  add_executable(${tool} ${src})
  target_link_libraries(${tool} tissue_trainer_core tt_tools_common)
  target_compile_options(${tool} PRIVATE -Wall -Wextra)
  # Where the repository's config/ is when $TT_SOURCE_DIR does not say.
  target_compile_definitions(${tool} PRIVATE TT_SOURCE_ROOT="${TT_ROOT}")
  list(APPEND TT_TOOLS ${tool})
endforeach()

# bench_adamss has one source file per experiment, in src/tools/repro/bench_adamss/.
file(GLOB TT_BENCH_ADAMSS_SOURCES CONFIGURE_DEPENDS "${TT_ROOT}/src/tools/repro/bench_adamss/*.cpp")
add_executable(bench_adamss ${TT_BENCH_ADAMSS_SOURCES})
if(TT_CORE_UNITY)  # unity batches, as for the core
  set_target_properties(bench_adamss PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
endif()
target_link_libraries(bench_adamss tissue_trainer_core tt_tools_common)
target_compile_options(bench_adamss PRIVATE -Wall -Wextra)
target_compile_definitions(bench_adamss PRIVATE TT_SOURCE_ROOT="${TT_ROOT}")
list(APPEND TT_TOOLS bench_adamss)

# bench_bullet_peer and bench_bullet_liver run Bullet's deformable bodies beside our models:
# they link the double-precision Bullet (Debian's libBullet*-float64; FindBullet's
# BULLET_LIBRARIES are the single-precision ones of the contact library, which these tools do
# not link: the two export the same symbols).
foreach(tool bench_bullet_peer bench_bullet_liver)
  if(TARGET ${tool})
    find_library(TT_BULLET64_SOFTBODY BulletSoftBody-float64 REQUIRED)
    find_library(TT_BULLET64_DYNAMICS BulletDynamics-float64 REQUIRED)
    find_library(TT_BULLET64_COLLISION BulletCollision-float64 REQUIRED)
    find_library(TT_BULLET64_MATH LinearMath-float64 REQUIRED)
    find_path(TT_BULLET64_INCLUDE btBulletDynamicsCommon.h PATH_SUFFIXES bullet REQUIRED)
    target_include_directories(${tool} SYSTEM PRIVATE ${TT_BULLET64_INCLUDE})
    target_compile_definitions(${tool} PRIVATE BT_USE_DOUBLE_PRECISION)
    target_link_libraries(${tool} ${TT_BULLET64_SOFTBODY} ${TT_BULLET64_DYNAMICS}
      ${TT_BULLET64_COLLISION} ${TT_BULLET64_MATH})
  endif()
endforeach()
# bench_bullet_liver runs bench_bullet_liver_state (our contact, on the single-precision
# Bullet) from the directory it is in.
if(TARGET bench_bullet_liver AND TARGET bench_bullet_liver_state)
  add_dependencies(bench_bullet_liver bench_bullet_liver_state)
endif()

# bench_scene_parts times the instrument contact query of the simulation node (Bullet);
# bench_implicit_step steps the liver with the tool pressed in; bench_bullet_liver_state
# presses it for bench_bullet_liver; bench_real_time_clock plays the palpation with it.
foreach(tool bench_scene_parts bench_implicit_step bench_bullet_liver_state bench_real_time_clock)
  if(TARGET ${tool})
    target_link_libraries(${tool} tissue_trainer_contact)
  endif()
endforeach()
