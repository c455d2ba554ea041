#!/usr/bin/env bash
# Fuzzes the robot spec parser (URDF with <gazebo> tags) and urdf_doctor with libFuzzer, under
# AddressSanitizer and UndefinedBehaviorSanitizer, at low priority on one core. Not part of the CI suite.
#
#   scripts/fuzz.sh [SECONDS]    run for SECONDS (default 600)
#
# Builds bullet_sim/fuzz/fuzz_model_spec.cpp with clang-14 (installed, with its sanitizer runtimes and
# libFuzzer, when missing) in its own workspace under $BULLET_SIM_FUZZ_DIR (default /tmp/bullet_sim_fuzz), seeds
# the corpus with our descriptions' expanded URDFs and the test fixtures, and exits non-zero when libFuzzer finds
# a crash, a leak, a timeout or an out-of-memory; the input that causes it is kept in $BULLET_SIM_FUZZ_DIR/artifacts
# (rerun it: fuzz_model_spec FILE). Leaks inside third-party libraries are suppressed by scripts/lsan.supp.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
RUN_SECONDS=${1:-600}
DIR=${BULLET_SIM_FUZZ_DIR:-/tmp/bullet_sim_fuzz}
WS=$DIR/ws
export PATH=/usr/bin:/usr/local/bin:$PATH

# shellcheck source=scripts/lib.sh
source "$REPO/scripts/lib.sh"

"$REPO/scripts/workspace.sh" install  # ROS, the libraries and xacro
install_debian_packages clang-14 libclang-rt-14-dev libfuzzer-14-dev

log "building fuzz_model_spec in $WS"
mkdir -p "$WS"
nice catkin_make -C "$WS" --source "$REPO" \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCATKIN_ENABLE_TESTING=OFF -DBULLET_SIM_FUZZ=ON fuzz_model_spec
set +u  # catkin's setup.bash reads unset variables
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u

log "seeding the corpus"
corpus=$DIR/corpus
rm -rf "$DIR/artifacts"
mkdir -p "$corpus" "$DIR/artifacts"
for description in smartwheelchair_model/urdf/smartwheelchair_model.urdf.xacro smartcar_description/urdf/smartcar.urdf.xacro \
  yahboomcar_description/urdf/yahboomcar.urdf.xacro; do
  xacro "$REPO/$description" >"$corpus/seed_$(basename "$description" .urdf.xacro).urdf"
done
cp "$REPO"/bullet_sim/test/fixtures/robots/*.urdf "$REPO"/bullet_sim/test/fixtures/doctor/*.urdf "$corpus/"

log "fuzzing for $RUN_SECONDS s (log: $DIR/fuzz-0.log)"
cd "$DIR"
rm -f fuzz-0.log
status=0
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$REPO/scripts/lsan.supp:print_suppressions=0" \
  nice -n 19 "$WS/devel/lib/bullet_sim/fuzz_model_spec" -jobs=1 -workers=1 -max_total_time="$RUN_SECONDS" \
  -timeout=10 -rss_limit_mb=2048 -max_len=65536 -dict="$REPO/bullet_sim/fuzz/urdf.dict" \
  -artifact_prefix="$DIR/artifacts/" "$corpus" || status=$?
tail -n 5 fuzz-0.log
findings=$(find "$DIR/artifacts" -type f | wc -l)
echo "corpus: $(find "$corpus" -type f | wc -l) inputs; findings in $DIR/artifacts: $findings"
if [ "$status" -ne 0 ] || [ "$findings" -ne 0 ]; then
  echo "FAILED: libFuzzer found a problem (status $status); see $DIR/fuzz-0.log" >&2
  exit 1
fi
