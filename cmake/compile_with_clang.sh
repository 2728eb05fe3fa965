#!/bin/sh
# Compiler launcher of the unit-test program (CMakeLists.txt, TT_TESTS_WITH_CLANG): CMake calls
# it as `compile_with_clang.sh COMPILER ARGS...`; it compiles with clang++ instead of COMPILER
# (through ccache when present), or with COMPILER itself where clang++ is missing. The tests'
# own code only: the library they test keeps the project's compiler. clang++ 14 compiles the
# tests' template-heavy batches about three times faster than g++ 12 (docs/building.md).
compiler="$1"
shift
if command -v clang++ >/dev/null 2>&1; then
  # A precompiled header without its build time inside, so that ccache can reuse it.
  if command -v ccache >/dev/null 2>&1; then
    exec ccache clang++ -Xclang -fno-pch-timestamp "$@"
  fi
  exec clang++ "$@"
fi
if command -v ccache >/dev/null 2>&1; then exec ccache "$compiler" "$@"; fi
exec "$compiler" "$@"
