#!/usr/bin/env bash
# Finds repeated blocks of code in the simulator (bullet_sim's src, include and plugins) with jscpd (from npm,
# which `scripts/workspace.sh install` puts on PATH) and fails when there are more than the budget: a block of
# 50 tokens or more written twice is a place where one piece of code should serve both.
#
#   scripts/duplicates.sh            prints the pairs, exits 1 above the budget
#   scripts/duplicates.sh --budget N
#
# Left out: the message translation of the ROS layer (src/ros/*_messages.cpp, robot_adapter.cpp), whose blocks
# repeat one message's fields after another's, and the tests.
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUDGET=6
if [ "${1:-}" = "--budget" ]; then BUDGET=$2; fi

command -v jscpd >/dev/null || { echo "duplicates.sh: jscpd is missing: run scripts/workspace.sh install" >&2; exit 2; }
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
cd "$REPO/bullet_sim"
jscpd --silent --min-tokens 50 --formats-exts cpp:cpp,h --reporters json --output "$OUT" \
  --ignore "**/*_test.cpp,**/src/ros/*_messages.cpp,**/src/ros/robot_adapter.cpp" src include plugins >/dev/null
/usr/bin/python3 - "$OUT/jscpd-report.json" "$BUDGET" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
budget = int(sys.argv[2])
pairs = report["duplicates"]
for pair in pairs:
    a, b = pair["firstFile"], pair["secondFile"]
    print(f'{pair["lines"]:3d} lines  {a["name"]}:{a["start"]}-{a["end"]}  ~  {b["name"]}:{b["start"]}-{b["end"]}')
print(f"{len(pairs)} repeated blocks (budget {budget})")
sys.exit(1 if len(pairs) > budget else 0)
PY
