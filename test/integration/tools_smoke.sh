#!/usr/bin/env bash
# The benchmark and reproduction programs that no other script or test runs, each on its
# --quick set-up (a smoke run of seconds, not a measurement): it must exit 0 and print its
# table. Each is also given an unknown option, which must be one line on stderr naming it and
# exit 2; so are the programs that other programs or launch files run (their option check
# only). One test case per program in RESULT_XML.
# Usage: test/integration/tools_smoke.sh RESULT_XML BIN_DIR [WORK_DIR]
set -uo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
xml="${1:?usage: tools_smoke.sh RESULT_XML BIN_DIR [WORK_DIR]}"
bin="${2:?usage: tools_smoke.sh RESULT_XML BIN_DIR [WORK_DIR]}"
work="$(realpath -m "${3:-$(dirname "$xml")/tools_smoke}")"
rm -rf "$work" && mkdir -p "$work"

# program and its quick arguments, one per line
programs=(
  "bench_abm3_corrector --quick"
  "bench_fd_jacobian --quick"
  "bench_fig4_metastability --quick"
  "bench_fitting --quick --out $work/fitting"
  "bench_force_threshold --quick"
  "bench_forces --quick"
  "bench_haptics --quick"
  "bench_implicit_step --quick --csv $work/implicit_step.csv"
  "bench_iteration_control --quick --out $work/iteration_control"
  "bench_land_beam --quick"
  "bench_land_ventricle --quick"
  "bench_muscle_demo --quick"
  "bench_radau_table_e1 --quick"
  "bench_scene_parts --quick"
)

# Run by a launch file, a test script or another program: the unknown-option check only (the
# ROS programs read their options after ros::init, which needs a master URI, not a master).
option_checks=(
  "bench_bullet_liver_state"
  "bench_training_graph graph"
  "network_probe"
)

xml_escape() { sed -e 's/&/\&amp;/g' -e 's/</\&lt;/g' -e 's/>/\&gt;/g' -e 's/"/\&quot;/g'; }

cases="" failures=0
# One line on stderr naming the option and exit 2, or the failure's text.
refuses_unknown_option() {
  local name="$1"; shift
  (cd "$repo" && "$bin/$name" "$@" --no-such-option) >"$work/$name.bad.out" 2>"$work/$name.bad.err"
  local code=$?
  if [ $code -ne 2 ] || [ "$(wc -l <"$work/$name.bad.err")" -ne 1 ] ||
     ! grep -q -- "--no-such-option" "$work/$name.bad.err"; then
    echo "$name --no-such-option: exit $code, stderr: $(tr '\n' ' ' <"$work/$name.bad.err") (expected exit 2 and one line naming the option)"
  fi
}

record() {  # name seconds failure
  if [ -n "$3" ]; then
    failures=$((failures + 1))
    echo "tools_smoke: FAILED: $3"
    cases+="<testcase classname=\"tools_smoke\" name=\"$1\" time=\"$2\"><failure message=\"$(printf '%s' "$3" | xml_escape)\"/></testcase>"
  else
    echo "tools_smoke: $1: ok in $2 s"
    cases+="<testcase classname=\"tools_smoke\" name=\"$1\" time=\"$2\"/>"
  fi
}

for entry in "${programs[@]}"; do
  read -r -a command <<<"$entry"
  name="${command[0]}"
  log="$work/$name.log"
  start=$SECONDS
  failure=""
  if [ ! -x "$bin/$name" ]; then
    failure="$bin/$name is not built"
  else
    (cd "$repo" && timeout 600 "$bin/$name" "${command[@]:1}") >"$log" 2>&1
    code=$?
    if [ $code -ne 0 ]; then
      failure="$entry exited with $code: $(tail -3 "$log" | tr '\n' ' ')"
    elif [ "$(wc -l <"$log")" -lt 3 ]; then
      failure="$entry printed less than its table: $(tr '\n' ' ' <"$log")"
    else
      failure="$(refuses_unknown_option "$name")"
    fi
  fi
  record "$name" $((SECONDS - start)) "$failure"
done
export ROS_MASTER_URI="${ROS_MASTER_URI:-http://localhost:11311}"
for entry in "${option_checks[@]}"; do
  read -r -a command <<<"$entry"
  name="${command[0]}"
  failure=""
  if [ ! -x "$bin/$name" ]; then
    failure="$bin/$name is not built"
  else
    failure="$(refuses_unknown_option "${command[@]}")"
  fi
  record "$name options" 0 "$failure"
done
printf '<testsuite name="tools_smoke" tests="%d" failures="%d">%s</testsuite>\n' \
  $((${#programs[@]} + ${#option_checks[@]})) "$failures" "$cases" >"$xml"
[ $failures -eq 0 ]
