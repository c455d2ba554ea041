#!/usr/bin/env bash
# Soak test, run on demand (not in CI): the wheelchair, the smartcar and the Yahboom car in one world
# (robot1..3, scripts/soak.launch), 5 publishers at 1 kHz each on their cmd_vel for 60 s of sim time. The
# simulator must keep stepping, its RSS must stay within 5 % after a warm-up, and /clock must never go back.
#
#   scripts/soak.sh [SIM_SECONDS]    default 60; builds the workspace first (see scripts/workspace.sh)
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SIM_SECONDS=${1:-60}
export PATH=/usr/bin:$PATH:/usr/local/bin

"$REPO/scripts/workspace.sh" build
# shellcheck source=scripts/lib.sh
source "$REPO/scripts/lib.sh"
WS=$(workspace_of "$REPO")
set +u  # catkin's setup.bash reads unset variables
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u

# A master of its own on a free port, so the soak neither joins nor disturbs another ROS session.
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://localhost:$port
log_dir=$(mktemp -d /tmp/bullet_sim_soak.XXXXXX)
export ROS_LOG_DIR=$log_dir
roslaunch -p "$port" "$REPO/scripts/soak.launch" >"$log_dir/roslaunch.log" 2>&1 &
launch_pid=$!
trap 'kill -INT $launch_pid 2>/dev/null; wait $launch_pid 2>/dev/null || true' EXIT

status=0
"$REPO/scripts/soak.py" "$SIM_SECONDS" || status=$?
if [ "$status" -ne 0 ]; then
  echo "the simulator's output: $log_dir/roslaunch.log" >&2
fi
exit "$status"
