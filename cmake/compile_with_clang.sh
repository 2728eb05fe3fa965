#!/bin/sh
# Compiler launcher of the unit-test program (CMakeLists.txt, TT_TESTS_WITH_CLANG): CMake calls
# it as `compile_with_clang.sh COMPILER ARGS...`; it compiles with clang++ instead of COMPILER
# (through ccache when present), or with COMPILER itself where clang++ is missing. The tests'
# own code only: the library they test keeps the project's compiler. clang++ 14 compiles the
# tests' template-heavy batches about three times faster than g++ 12 (docs/building.md).
compiler="$1"
shift
cache=""
command -v ccache >/dev/null 2>&1 && cache=ccache
command -v clang++ >/dev/null 2>&1 && compiler=clang++
exec $cache "$compiler" "$@"
