#!/usr/bin/env bash
# Builds the unit tests (the gtests that need no roscore) under AddressSanitizer and UndefinedBehaviorSanitizer
# in their own workspace and runs them; a sanitizer report or a failing test fails the run. Not part of the CI
# suite.
#
#   scripts/sanitize.sh [TEST ...]    all of bullet_sim's gtests, or the ones named (e.g. doctor_test)
#
# The workspace is $BULLET_SIM_SANITIZE_WS (default /tmp/bullet_sim_sanitize). Leaks inside third-party
# libraries (Mesa's llvmpipe, ...) are suppressed by scripts/lsan.supp; ours never are.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
WS=${BULLET_SIM_SANITIZE_WS:-/tmp/bullet_sim_sanitize}
export PATH=/usr/bin:$PATH:/usr/local/bin

# shellcheck source=scripts/lib.sh
source "$REPO/scripts/lib.sh"

"$REPO/scripts/workspace.sh" install  # ROS, the libraries, g++ and xacro
install_debian_packages libasan8 libubsan1  # gcc 12's sanitizer runtimes

sanitizers="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
log "building the unit tests with $sanitizers in $WS"
mkdir -p "$WS"
nice catkin_make -C "$WS" --source "$REPO" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$sanitizers" -DCMAKE_EXE_LINKER_FLAGS="$sanitizers" \
  -DCMAKE_SHARED_LINKER_FLAGS="$sanitizers" tests
set +u  # catkin's setup.bash reads unset variables
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u

# Every report is fatal (halt_on_error), and the tools the tests run (urdf_doctor, render_model) inherit it.
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS="suppressions=$REPO/scripts/lsan.supp:print_suppressions=0"

if [ $# -gt 0 ]; then
  tests=("$@")
else
  mapfile -t tests < <(find "$WS/devel/lib/bullet_sim" -maxdepth 1 -name '*_test' -type f -printf '%f\n' | sort)
fi
failed=()
for test in "${tests[@]}"; do
  log "$test"
  if nice "$WS/devel/lib/bullet_sim/$test" --gtest_brief=1 >"$WS/$test.log" 2>&1; then
    tail -n 3 "$WS/$test.log"
  else
    tail -n 60 "$WS/$test.log"
    failed+=("$test")
  fi
done
log "sanitized unit tests: $((${#tests[@]} - ${#failed[@]})) passed, ${#failed[@]} failed ${failed[*]:-}"
[ ${#failed[@]} -eq 0 ]
