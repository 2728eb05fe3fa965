# Shared by scripts/demo, scripts/test and scripts/bench: install what is missing, build the
# catkin workspace outside the tracked tree. Source it; do not run it.
set -euo pipefail

TT_REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TT_WORKSPACE="${TT_WORKSPACE:-$TT_REPO/.build/ws}"
TT_JOBS="${TT_JOBS:-2}"

# Debian's packages the build, tests and demo need (ROS 1 is packaged by Debian).
TT_PACKAGES=(
  build-essential cmake pkg-config catkin ros-base-dev python3-catkin-pkg
  python3-rostest librostest-dev librosbag-dev python3-rosbag python3-roslaunch
  python3-rostopic python3-rosnode python3-rosparam
  libtf2-ros-dev libtf2-geometry-msgs-dev liburdfdom-dev liburdf-dev ros-message-generation
  libstd-msgs-dev libgeometry-msgs-dev libsensor-msgs-dev libvisualization-msgs-dev
  ros-std-msgs ros-geometry-msgs ros-sensor-msgs ros-visualization-msgs
  ros-std-srvs libstd-srvs-dev ros-diagnostic-msgs libdiagnostic-msgs-dev
  libbullet-dev libosmesa6-dev libpng-dev libeigen3-dev libyaml-cpp-dev libgtest-dev
  # CHOLMOD, the sparse Cholesky factor of the implicit solver's preconditioner, and OpenBLAS
  # under it (twice as fast as the reference BLAS). The threaded build, because only it may be
  # called from two threads at once; the core keeps it to the calling thread.
  libsuitesparse-dev libopenblas0-pthread
  # hypre's BoomerAMG, the algebraic multigrid preconditioner, and the MPI it is built with.
  libhypre-dev mpi-default-dev
  # The two-host test's network namespaces (ip netns, veth).
  iproute2
  # The compiler cache: a rebuild after a small change, or in a second clone, takes seconds.
  ccache
  # Ninja: it compiles a program's files while the library under it is still compiling, where
  # make waits for the whole library first.
  ninja-build
  # Python message modules, so that rostopic echo, rosbag and rospy read every topic.
  python3-std-msgs python3-geometry-msgs python3-sensor-msgs python3-visualization-msgs
  python3-diagnostic-msgs python3-std-srvs
  # The assessment's plots (scripts/assessment_plots.py, run by assess_bag).
  python3-matplotlib python3-yaml
)

# The benchmark report's plots (scripts/bench, and the report check of scripts/test), TetGen
# for the unstructured cube of bench_adamss mesh_independence, and clang, which compiles the
# unit-test program of scripts/test in a third of g++'s time (cmake/compile_with_clang.sh).
TT_BENCH_PACKAGES=(python3-matplotlib tetgen clang)

tt_say() { printf '[tissue_trainer] %s\n' "$*"; }

# Installs the given Debian packages that are missing (apt-get, through sudo when not root).
tt_install_packages() {
  local missing=()
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$pkg")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    tt_say "all $# Debian packages present"
    return
  fi
  local sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  tt_say "installing ${#missing[@]} missing Debian packages: ${missing[*]}"
  "${sudo[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
  tt_say "packages installed"
}

tt_install_deps() { tt_install_packages "${TT_PACKAGES[@]}"; }
tt_install_bench_deps() { tt_install_packages "${TT_BENCH_PACKAGES[@]}"; }

# ROS tools write into HOME unless told otherwise; keep ROS networking on loopback.
tt_ros_env() {
  export ROS_HOME="${ROS_HOME:-$TT_REPO/.build/ros_home}"
  export ROS_LOG_DIR="${ROS_LOG_DIR:-$ROS_HOME/log}"
  export ROS_HOSTNAME=127.0.0.1
  export ROS_MASTER_URI="${ROS_MASTER_URI:-http://127.0.0.1:11311}"
  export MESA_SHADER_CACHE_DISABLE=true
  mkdir -p "$ROS_HOME"
}

# Builds the given targets of the catkin workspace (default: everything and the tests). The
# pyenv python3 that may be first on PATH lacks Debian's catkin_pkg, so /usr/bin comes first.
# ccache, when present, caches every compilation (CCACHE_DIR, default ~/.cache/ccache, else the
# workspace's ccache/ when HOME is not writable); paths
# below the repository are hashed relative to it, so another clone reuses the cache too.
tt_build() {
  local targets=("$@")
  [ ${#targets[@]} -gt 0 ] || targets=(all tests)
  tt_ros_env
  mkdir -p "$TT_WORKSPACE/src"
  ln -sfn "$TT_REPO" "$TT_WORKSPACE/src/tissue_trainer"
  local launcher="" cache_note=""
  if command -v ccache >/dev/null; then
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$TT_REPO}"
    # Its default folder is under HOME; where HOME cannot take it, the workspace's folder does.
    if [ -z "${CCACHE_DIR:-}" ] && ! { mkdir -p "${HOME:-/nonexistent}/.cache/ccache" &&
                                      [ -w "${HOME:-/nonexistent}/.cache/ccache" ]; } 2>/dev/null; then
      export CCACHE_DIR="$TT_WORKSPACE/ccache"
    fi
    # Compilations with a precompiled header are cached only with this sloppiness.
    export CCACHE_SLOPPINESS="${CCACHE_SLOPPINESS:-pch_defines,time_macros}"
    launcher=ccache cache_note=", ccache"
  fi
  # A workspace configured for make before Ninja was used is configured again (CMake keeps one
  # generator per build folder); the compiler cache makes that rebuild cheap.
  local cache="$TT_WORKSPACE/build/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
    tt_say "the workspace was configured for make: configuring it again for Ninja"
    rm -rf "$TT_WORKSPACE/build"
  fi
  tt_say "building ${targets[*]} in $TT_WORKSPACE (Release, $TT_JOBS jobs, Ninja$cache_note)"
  local start=$SECONDS log="$TT_WORKSPACE/build.log"
  if ! (cd "$TT_WORKSPACE" && PATH="/usr/bin:$PATH" catkin_make --use-ninja \
        -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" \
        -j"$TT_JOBS" "${targets[@]}" >"$log" 2>&1); then
    grep -E "error|Error" "$log" | head -40 || true
    tt_say "build failed; full log: $log"
    return 1
  fi
  tt_say "build done in $((SECONDS - start)) s"
  TT_BIN="$TT_WORKSPACE/devel/lib/tissue_trainer"
  export TT_BIN
}

tt_source_workspace() {
  set +u
  # shellcheck disable=SC1091
  source "$TT_WORKSPACE/devel/setup.bash"
  set -u
}
