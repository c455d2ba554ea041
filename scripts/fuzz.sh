#!/usr/bin/env bash
# Fuzzes bullet_sim's readers with libFuzzer (clang-14) under AddressSanitizer and UndefinedBehaviorSanitizer:
# fuzz_model (the URDF reader and urdf_doctor), fuzz_world (the SDF readers of worlds and of models to
# spawn) and fuzz_mesh (the mesh importer), in bullet_sim/fuzz/.
#
#   scripts/fuzz.sh [SECONDS [TARGET...]]  fuzz each target (default: all) for SECONDS (default 600), at the
#                                          lowest priority; merge what it finds into bullet_sim/fuzz/corpus/TARGET
#                                          and copy every input that crashed into bullet_sim/fuzz/crashes/TARGET
#   scripts/fuzz.sh --ci                   replay the committed corpus and crashes, then a short run with a fixed
#                                          -seed and -runs: deterministic; scripts/workspace.sh test runs it, after
#                                          its build, whose libraries the targets then link (see ci_build)
#   scripts/fuzz.sh --seed                 rewrite the seed corpus from the shipped descriptions, worlds, meshes
#
# The targets are built in a catkin workspace of their own under $BULLET_SIM_FUZZ_DIR (default: build_fuzz in the
# workspace, which git and catkin ignore), with ccache when it is installed. A crash inside a library we cannot patch (assimp, sdformat) is fixed by the
# simulator reading such files in a child process; its input goes to crashes/TARGET/library/, which
# bad_input_test replays through the simulator's own loaders. Leaks inside third-party libraries are
# suppressed by scripts/lsan.supp. Exits non-zero when an input crashes, leaks, times out or runs out of memory.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib.sh
source "$REPO/scripts/lib.sh"
FUZZ=$REPO/bullet_sim/fuzz
DIR=${BULLET_SIM_FUZZ_DIR:-$(workspace_of "$REPO")/build_fuzz}
WS=$DIR/ws
TARGETS=(fuzz_model fuzz_world fuzz_mesh)
CI_MUTATIONS=100     # new inputs per target in the CI's short run, after its corpus
CI_SEED=1
export PATH=/usr/bin:$PATH:/usr/local/bin
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1
export LSAN_OPTIONS="suppressions=$REPO/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

build() {
  log "building the fuzz targets in $WS"
  mkdir -p "$WS"
  local launcher=()
  if command -v ccache >/dev/null; then launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  local sanitizers="-fsanitize=address,undefined -fno-sanitize-recover=undefined"
  nice catkin_make -C "$WS" --source "$REPO" "${launcher[@]}" \
    -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS="$sanitizers -fsanitize=fuzzer-no-link -fno-omit-frame-pointer" \
    -DCMAKE_SHARED_LINKER_FLAGS="$sanitizers" -DCMAKE_EXE_LINKER_FLAGS="$sanitizers" \
    -DCATKIN_ENABLE_TESTING=OFF -DBULLET_SIM_FUZZ=ON fuzz_targets >"$DIR/build.log" 2>&1 ||
    { tail -n 30 "$DIR/build.log"; echo "FAILED: building the fuzz targets; see $DIR/build.log" >&2; exit 1; }
  set +u  # catkin's setup.bash reads unset variables
  # shellcheck disable=SC1091
  source "$WS/devel/setup.bash"
  set -u
}

# For CI, the targets link the test suite's own build of bullet_sim, so that no second build of it (minutes
# under the sanitizers) is needed: the fuzzer instruments only the targets then, and sanitizes allocations
# everywhere. It replays inputs exactly; the coverage-guided search is for the long runs.
ci_build() {
  local lib
  lib=$(workspace_of "$REPO")/devel/lib
  [ -f "$lib/libbullet_sim_core.so" ] || { echo "FAILED: build the workspace first (no $lib/libbullet_sim_core.so)" >&2; exit 1; }
  WS=$DIR/ci
  mkdir -p "$WS/devel/lib/bullet_sim"
  log "building the fuzz targets against $lib"
  for target in "${TARGETS[@]}"; do
    clang++-14 -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
      -I"$REPO/bullet_sim/include" -I/usr/include/eigen3 "$FUZZ/$target.cpp" -o "$(binary "$target")" \
      "$lib/libbullet_sim_doctor.a" "$lib/libbullet_sim_tools.a" -L"$lib" -lbullet_sim_core -ltinyxml2 -Wl,-rpath,"$lib" ||
      { echo "FAILED: building $target" >&2; exit 1; }
  done
}

binary() { echo "$WS/devel/lib/bullet_sim/$1"; }

# Options of a target: bounds on each input, and its dictionary (bullet_sim/fuzz/<name>.dict) if it has one.
options() {
  local dict=$FUZZ/${1#fuzz_}.dict
  echo "-timeout=10 -rss_limit_mb=2048 -max_len=65536"
  if [ -f "$dict" ]; then echo "-dict=$dict"; fi
}

# The seed corpus: our own descriptions, worlds and meshes, as the targets take them.
seed() {
  log "seeding bullet_sim/fuzz/corpus"
  local corpus=$FUZZ/corpus
  rm -rf "$corpus"
  mkdir -p "$corpus"/{fuzz_model,fuzz_world,fuzz_mesh}
  for description in smartwheelchair_model/urdf/smartwheelchair_model.urdf.xacro smartcar_description/urdf/smartcar.urdf.xacro \
    yahboomcar_description/urdf/yahboomcar.urdf.xacro tianracer_description/urdf/tianracer.urdf.xacro \
    rover_description/urdf/rover.urdf.xacro; do
    xacro "$REPO/$description" >"$corpus/fuzz_model/$(basename "$description" .urdf.xacro).urdf"
  done
  cp "$REPO"/bullet_sim/test/fixtures/robots/*.urdf "$REPO"/bullet_sim/test/fixtures/doctor/*.urdf \
    "$REPO"/bullet_sim/test/fixtures/bad_input/*.urdf "$corpus/fuzz_model/"
  cp "$REPO"/bullet_sim/worlds/*.world "$REPO"/bullet_sim_bringup/worlds/*.world "$REPO"/bullet_sim/test/fixtures/worlds/*.world \
    "$corpus/fuzz_world/"
  for model in "$REPO"/bullet_sim/models/*/model.sdf "$REPO"/bullet_sim/test/fixtures/models/*.sdf; do
    cp "$model" "$corpus/fuzz_world/$(basename "$(dirname "$model")")_$(basename "$model")"
  done
  # fuzz_mesh takes one byte for the format (0 STL, 1 OBJ, 2 COLLADA), then the file.
  for mesh in "$REPO"/*/meshes/*.stl "$REPO"/bullet_sim/test/fixtures/worlds/meshes/*.stl; do
    { printf '\x00'; cat "$mesh"; } >"$corpus/fuzz_mesh/$(basename "$(dirname "$(dirname "$mesh")")")_$(basename "$mesh")"
  done
  for seed_file in "$FUZZ"/seeds/*; do cp "$seed_file" "$corpus/fuzz_mesh/"; done
}

# Replays the committed crashes, then the corpus with a short, seeded fuzz after it: what CI runs. libFuzzer runs
# every corpus input first (the replay), then CI_MUTATIONS more; -runs counts both.
ci() {
  local status=0
  for target in "${TARGETS[@]}"; do
    local crashes=()
    mapfile -t crashes < <(find "$FUZZ/crashes/$target" -maxdepth 1 -type f 2>/dev/null | sort)
    if [ ${#crashes[@]} -gt 0 ]; then
      log "$target: replaying ${#crashes[@]} crashes"
      # shellcheck disable=SC2046
      "$(binary "$target")" $(options "$target") "${crashes[@]}" >"$DIR/$target.crashes.log" 2>&1 ||
        { status=1; tail -n 30 "$DIR/$target.crashes.log"; }
    fi
    local scratch=$DIR/ci/corpus/$target inputs
    rm -rf "$scratch" && mkdir -p "$scratch" && cp -r "$FUZZ/corpus/$target/." "$scratch/"
    inputs=$(find "$scratch" -type f | wc -l)
    log "$target: replaying $inputs corpus inputs, then $CI_MUTATIONS more with -seed=$CI_SEED"
    # shellcheck disable=SC2046
    "$(binary "$target")" $(options "$target") -seed=$CI_SEED -runs=$((inputs + CI_MUTATIONS)) \
      -artifact_prefix="$DIR/ci/$target-" "$scratch" >"$DIR/$target.ci.log" 2>&1 ||
      { status=1; tail -n 30 "$DIR/$target.ci.log"; }
  done
  [ "$status" -eq 0 ] || echo "FAILED: an input crashed a fuzz target; logs in $DIR" >&2
  return "$status"
}

# Fuzzes each target for $1 seconds; keeps what it finds.
fuzz() {
  local seconds=$1
  shift
  local status=0
  for target in "$@"; do
    local work=$DIR/corpus/$target artifacts=$DIR/artifacts/$target
    rm -rf "$artifacts" && mkdir -p "$work" "$artifacts" "$FUZZ/crashes/$target"
    log "$target: fuzzing for $seconds s (log: $DIR/$target.log)"
    # -fork keeps going after a crash, so one run finds what it can; new inputs go to $work.
    # shellcheck disable=SC2046
    nice -n 19 "$(binary "$target")" $(options "$target") -fork=1 -ignore_crashes=1 -ignore_timeouts=1 \
      -ignore_ooms=1 -max_total_time="$seconds" -artifact_prefix="$artifacts/" "$work" "$FUZZ/corpus/$target" \
      >"$DIR/$target.log" 2>&1 || status=1
    tail -n 3 "$DIR/$target.log"
    log "$target: merging the new inputs into bullet_sim/fuzz/corpus/$target"
    local merged=$DIR/merged/$target
    rm -rf "$merged" && mkdir -p "$merged"
    # shellcheck disable=SC2046
    nice -n 19 "$(binary "$target")" $(options "$target") -merge=1 "$merged" "$FUZZ/corpus/$target" "$work" \
      >"$DIR/$target.merge.log" 2>&1 || status=1
    rm -rf "${FUZZ:?}/corpus/$target" && cp -r "$merged" "$FUZZ/corpus/$target"
    local found
    found=$(find "$artifacts" -type f | wc -l)
    cp "$artifacts"/* "$FUZZ/crashes/$target/" 2>/dev/null || true
    echo "$target: corpus $(find "$FUZZ/corpus/$target" -type f | wc -l) inputs; $found new crashes in bullet_sim/fuzz/crashes/$target"
    [ "$found" -eq 0 ] || status=1
  done
  return "$status"
}

install_debian_packages clang-14 libclang-rt-14-dev libfuzzer-14-dev
mkdir -p "$DIR"
touch "$DIR/CATKIN_IGNORE"  # in place, the main build must not take its packages for sources
case "${1:-}" in
  --seed)
    set +u  # catkin's setup.bash reads unset variables; xacro finds our packages through it
    # shellcheck disable=SC1091
    source "$(workspace_of "$REPO")/devel/setup.bash"
    set -u
    seed
    ;;
  --ci) ci_build; ci ;;
  *)
    "$REPO/scripts/workspace.sh" install  # ROS, the libraries and xacro
    build
    seconds=${1:-600}
    shift || true
    if [ $# -eq 0 ]; then set -- "${TARGETS[@]}"; fi
    fuzz "$seconds" "$@"
    ;;
esac
