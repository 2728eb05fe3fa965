#!/usr/bin/env bash
# The training graph on two hosts for real: two network namespaces joined by a veth pair, host
# A (10.77.0.1: ROS master, simulation, renderer, assessment; launch/host_physics.launch) and
# host B (10.77.0.2: scripted operator, instrument kinematics, haptic bridge;
# launch/host_device.launch), each with its own ROS_IP. A probe on each host
# (network_probe) records what it sees. While the tool presses the liver the link is taken
# down for 1 s and brought back. test/integration/two_hosts_check.py then checks that every
# topic crossed, that the bridge held 1 kHz on B, the contact-model age at the bridge, that
# the force faded to zero within model_timeout + fade_time of the last model, stayed finite
# and bounded, and came back within the rate limit.
# Needs root and `ip netns`; elsewhere the test is recorded as skipped, with one line saying why.
# The namespaces, the link and the processes it starts are removed on every exit path.
# Usage: test/integration/two_hosts.sh RESULT_XML [WORK_DIR]   (the workspace must be built)
set -uo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
xml="${1:?usage: two_hosts.sh RESULT_XML [WORK_DIR]}"
work="$(realpath -m "${2:-$(dirname "$xml")/two_hosts}")"

skip() {
  echo "two_hosts: skipped: $1"
  printf '<testsuite name="two_hosts" tests="1" skipped="1"><testcase classname="two_hosts" name="two_hosts"><skipped message="%s"/></testcase></testsuite>\n' \
    "$1" >"$xml"
  exit 0
}
fail() {
  echo "two_hosts: FAILED: $1"
  printf '<testsuite name="two_hosts" tests="1" failures="1"><testcase classname="two_hosts" name="two_hosts"><failure message="%s"/></testcase></testsuite>\n' \
    "$1" >"$xml"
  exit 1
}

[ "$(id -u)" -eq 0 ] || skip "needs root to make network namespaces (running as uid $(id -u))"
command -v ip >/dev/null || skip "no 'ip' command (iproute2) to make network namespaces"

ns_a="tt_host_a_$$" ns_b="tt_host_b_$$"
veth_a="ttA$$" veth_b="ttB$$"   # interface names: at most 15 characters
addr_a=10.77.0.1 addr_b=10.77.0.2
port=11411                      # the master's port inside host A's namespace
pids=()

cleanup() {
  local pid
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null; done
  for _ in $(seq 50); do
    local alive=0
    for pid in "${pids[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1; done
    [ $alive -eq 0 ] && break
    sleep 0.2
  done
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null; done
  ip link del "$veth_a" 2>/dev/null
  ip netns del "$ns_a" 2>/dev/null
  ip netns del "$ns_b" 2>/dev/null
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if ! ip netns add "$ns_a" 2>/dev/null; then
  skip "cannot make network namespaces here ('ip netns add' refused)"
fi
ip netns add "$ns_b" || fail "ip netns add $ns_b failed"
ip link add "$veth_a" type veth peer name "$veth_b" || fail "cannot make a veth pair"
ip link set "$veth_a" netns "$ns_a" && ip link set "$veth_b" netns "$ns_b" ||
  fail "cannot move the veth ends into the namespaces"
ip -n "$ns_a" addr add "$addr_a/24" dev "$veth_a" && ip -n "$ns_b" addr add "$addr_b/24" dev "$veth_b" ||
  fail "cannot give the hosts their addresses"
for ns in "$ns_a" "$ns_b"; do ip -n "$ns" link set lo up || fail "cannot bring up loopback in $ns"; done
ip -n "$ns_a" link set "$veth_a" up && ip -n "$ns_b" link set "$veth_b" up || fail "cannot bring the link up"

source "$repo/scripts/lib.sh"
set +e
tt_ros_env
tt_source_workspace
bin="$(catkin_find --first-only --libexec tissue_trainer network_probe 2>/dev/null)"
[ -x "$bin" ] || fail "network_probe is not built (build the workspace first)"
rm -rf "$work" && mkdir -p "$work/A" "$work/B"

# host NAME ADDRESS COMMAND...: runs COMMAND on that host, with its own ROS_IP and ROS_HOME.
# Started in the background, it execs (ip netns exec and env exec too), so $! is COMMAND itself
# and the cleanup's SIGINT reaches roslaunch, which then stops its nodes.
host() {
  local ns=$1 address=$2 name=$3
  shift 3
  exec ip netns exec "$ns" env -u ROS_HOSTNAME ROS_IP="$address" \
    ROS_MASTER_URI="http://$addr_a:$port" ROS_HOME="$work/$name" ROS_LOG_DIR="$work/$name/log" \
    "$@"
}

host "$ns_a" "$addr_a" A roscore -p "$port" >"$work/A/roscore.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  ip netns exec "$ns_b" bash -c "exec 3<>/dev/tcp/$addr_a/$port" 2>/dev/null && break
  sleep 0.1
done
ip netns exec "$ns_b" bash -c "exec 3<>/dev/tcp/$addr_a/$port" 2>/dev/null ||
  fail "the master on host A ($addr_a:$port) cannot be reached from host B"

topics_a="/tissue/contact,/tissue/status,/tissue/surface,/tissue/surface_marker,/camera/image_raw,/assessment/summary"
topics_b="/device/measured_cp,/device/measured_js,/device/enable,/device/servo_cf,/instrument/measured_cp,/instrument/measured_cv,/instrument/jaw/measured_js,/tf,/haptic_bridge/status"
mark="$work/contact_mark"
head -1 /proc/stat >"$work/cpu_start"
host "$ns_b" "$addr_b" B "$bin" --duration 90 --out "$work/B" --contact /tissue/contact \
  --topics "$topics_a" --mark-force 0.3 --mark-file "$mark" >"$work/B/probe.log" 2>&1 &
probe_b=$!
pids+=($probe_b)
host "$ns_a" "$addr_a" A "$bin" --duration 90 --out "$work/A" --topics "$topics_b" \
  >"$work/A/probe.log" 2>&1 &
probe_a=$!
pids+=($probe_a)

host "$ns_a" "$addr_a" A roslaunch tissue_trainer host_physics.launch render:=true assess:=true \
  assessment_dir:="$work/A/assessment" >"$work/A/launch.log" 2>&1 &
pids+=($!)
host "$ns_b" "$addr_b" B roslaunch --wait tissue_trainer host_device.launch \
  task:="$repo/test/integration/two_hosts_task.yaml" >"$work/B/launch.log" 2>&1 &
pids+=($!)

for _ in $(seq 600); do [ -s "$mark" ] && break; sleep 0.1; done
[ -s "$mark" ] || fail "no force at the device within 60 s (logs: $work/A, $work/B)"
sleep 1.0   # into the hold
date +%s.%N >"$work/link_down"
ip -n "$ns_b" link set "$veth_b" down || fail "cannot take the link down"
sleep 1.0
# Stamped before the link comes up: a model that arrives at once must not count as one from
# before the cut.
date +%s.%N >"$work/link_up"
ip -n "$ns_b" link set "$veth_b" up || fail "cannot bring the link back up"
sleep 5.0   # recovery, still in the hold

kill -INT "$probe_a" "$probe_b" 2>/dev/null
wait "$probe_a" "$probe_b" 2>/dev/null
head -1 /proc/stat >"$work/cpu_end"
/usr/bin/python3 "$repo/test/integration/two_hosts_check.py" "$work" "$xml" \
  "$repo/config/haptic_bridge.yaml" "$topics_a" "$topics_b"
