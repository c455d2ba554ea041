#!/usr/bin/env bash
# Sets up, builds, runs and tests this catkin workspace on Debian 12. Every step is idempotent.
#
#   scripts/workspace.sh run     install what is missing, build, bring up the wheelchair simulation
#   scripts/workspace.sh test    install what is missing, build, run the whole test suite, check the docs site and
#                                replay the fuzz corpus
#   scripts/workspace.sh install | build
#
# The repo root is the catkin source space. When it is cloned as <ws>/src, the workspace is <ws>;
# otherwise it is built in place (build/, devel/ in the repo). BULLET_SIM_WS=<dir> overrides either.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib.sh
source "$REPO/scripts/lib.sh"
WS=$(workspace_of "$REPO")
# Debian's ROS tools run on /usr/bin/python3, not on a pyenv or venv interpreter earlier on PATH.
export PATH=/usr/bin:$PATH:/usr/local/bin

DEBIAN_PACKAGES=(
  catkin ros-base-dev libroscpp-dev python3-rostest python3-roslaunch python3-rostopic rosbash
  libtf2-ros-dev libtf2-eigen-dev python3-tf2-ros libtf-dev python3-tf tf-tools libtopic-tools-dev libsensor-msgs-dev libnav-msgs-dev libgeometry-msgs-dev
  libstd-srvs-dev ros-robot-state-publisher joint-state-publisher libimage-transport-dev libcamera-info-manager-dev
  librosbag-dev python3-rosbag libtf2-msgs-dev
  liburdf-dev liburdfdom-dev liburdfdom-tools libtinyxml2-dev libsdformat-dev
  libbullet-dev libembree-dev libassimp-dev libeigen3-dev libosmesa6-dev libpng-dev libjpeg-dev
  python3-nav-msgs python3-sensor-msgs python3-geometry-msgs python3-std-srvs python3-trajectory-msgs
  ros-message-generation libtrajectory-msgs-dev libactionlib-msgs-dev python3-actionlib-msgs libstd-msgs-dev
  libactionlib-dev python3-actionlib
  python3-std-msgs python3-rospy python3-rosparam python3-rosservice
  libcli11-dev nlohmann-json3-dev libyaml-cpp-dev python3-pip python3-numpy googletest libgtest-dev libgmock-dev cmake g++ make ccache
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev python3-yaml python3-matplotlib python3-tqdm util-linux
  clang-14 libclang-rt-14-dev libfuzzer-14-dev
  libboost-dev libjs-three chromium chromium-driver fonts-liberation python3-selenium python3-pil  # the live viewer, its test
  mkdocs mkdocs-material  # the docs site (scripts/docs.sh)
)
XACRO_VERSION=2.1.1  # Noetic's dialect through the xacro package's script (xacro/xacro)
RAY_VERSION=2.60.0  # sweep runs its scenarios as Ray tasks
KUBERNETES_VALIDATE_VERSION=1.37.0  # sweep_kubernetes.test checks the Kubernetes recipe against its schemas
JSCPD_VERSION=4.0.5  # scripts/duplicates.sh finds repeated code with it (npm)
COACD_VERSION=1.0.14  # splits moving collision meshes into convex parts
MUJOCO_VERSION=4.0.0  # bullet_sim/bench/peers: the same strike in other engines
PYBULLET_VERSION=3.2.7

# Installs NAME==VERSION from PyPI into /usr/bin/python3, unless that version is there.
install_pypi() {
  local name=$1 version=$2
  if [ "$(/usr/bin/python3 -c "import importlib.metadata as m; print(m.version('$name'))" 2>/dev/null)" != "$version" ]; then
    log "installing $name $version from PyPI into /usr/bin/python3"
    as_root /usr/bin/python3 -m pip install --break-system-packages --no-warn-script-location "$name==$version"
  fi
}

install_dependencies() {
  install_debian_packages "${DEBIAN_PACKAGES[@]}"
  install_pypi xacro "$XACRO_VERSION"
  command -v npm >/dev/null || install_debian_packages nodejs npm
  if [ "$(jscpd --version 2>/dev/null)" != "$JSCPD_VERSION" ]; then
    log "installing jscpd $JSCPD_VERSION from npm"
    as_root npm install --global --no-fund --no-audit "jscpd@$JSCPD_VERSION"
  fi
  install_pypi ray "$RAY_VERSION"
  install_pypi kubernetes-validate "$KUBERNETES_VALIDATE_VERSION"
  install_pypi coacd "$COACD_VERSION"
  install_pypi mujoco "$MUJOCO_VERSION"
  install_pypi pybullet "$PYBULLET_VERSION"
}

build() {
  if [ "$WS" = "$REPO" ]; then
    # In place, catkin must not take the build, devel or install space for source packages.
    for space in build devel install; do
      mkdir -p "$WS/$space"
      touch "$WS/$space/CATKIN_IGNORE"
    done
  fi
  mkdir -p "$WS"
  # The compat/ packages (gazebo_msgs, ...) are built only where the system lacks the real ones.
  "$REPO/scripts/compat_packages.sh" "$REPO/compat" "$WS"
  log "building $WS"
  # ccache lets a second tree of the same sources (a worktree, the plugin test's scratch copy) reuse the objects:
  # it relates paths to the workspace, and leaves the build folder out of what it hashes.
  export CCACHE_BASEDIR=$WS CCACHE_NOHASHDIR=true
  catkin_make -C "$WS" --source "$REPO" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
    -DCMAKE_C_COMPILER_LAUNCHER=ccache
}

source_workspace() {
  set +u  # catkin's setup.bash reads unset variables
  # shellcheck disable=SC1091
  source "$WS/devel/setup.bash"
  set -u
}

run_main_job() {
  source_workspace
  log "bringing up the wheelchair in home.world (Ctrl-C stops it)"
  exec roslaunch bullet_sim_bringup wheelchair.launch
}

run_tests() {
  source_workspace
  local results=$WS/build/test_results
  rm -rf "$results"
  log "running the test suite"
  export CCACHE_BASEDIR=$WS CCACHE_NOHASHDIR=true  # see build()
  # run_tests exits 0 even when tests fail; catkin_test_results is the verdict.
  catkin_make -C "$WS" --source "$REPO" run_tests
  log "test results"
  local status=0
  catkin_test_results --verbose "$results" || status=$?
  # Count test cases from the result files: catkin_test_results counts gtest suites twice.
  local passed failed gtests
  read -r passed failed gtests < <(/usr/bin/python3 - "$results" <<'PY'
import glob, sys, xml.etree.ElementTree as ET
passed = failed = gtests = 0
for path in glob.glob(sys.argv[1] + "/*/*.xml"):
    # rostest-*.xml has a case per test node and can say "ok" for a node whose own cases (rosunit-*.xml) fail:
    # passes count from the former only, failures from both.
    summary_only = "/rosunit-" in path
    try:
        cases = list(ET.parse(path).iter("testcase"))
    except ET.ParseError:  # a test killed at its time limit leaves an empty or cut file: a failure
        print("unreadable test result (the test was killed?): " + path, file=sys.stderr)
        failed += 1
        continue
    for case in cases:
        bad = case.find("failure") is not None or case.find("error") is not None
        failed += bad
        passed += not bad and not summary_only and case.find("skipped") is None
        gtests += "/gtest-" in path
print(passed, failed, gtests)
PY
  )
  echo "$passed passed, $failed failed"
  if [ "$((passed + failed))" -eq 0 ]; then
    echo "FAILED: no test ran" >&2
    exit 1
  fi
  if [ "$gtests" -eq 0 ]; then
    echo "FAILED: no gtest ran (is googletest installed?)" >&2
    exit 1
  fi
  log "documentation (scripts/docs.sh --check)"
  "$REPO/scripts/docs.sh" --check || status=1
  log "repeated code (scripts/duplicates.sh)"
  "$REPO/scripts/duplicates.sh" || status=1
  log "line length (scripts/line_length.py)"
  /usr/bin/python3 "$REPO/scripts/line_length.py" || status=1
  # The fuzz targets replay their committed corpus and crashes, then fuzz briefly with a fixed seed.
  log "fuzz targets (scripts/fuzz.sh --ci)"
  "$REPO/scripts/fuzz.sh" --ci || status=1
  return "$status"
}

case "${1:-}" in
  install) install_dependencies ;;
  build) install_dependencies; build ;;
  run) install_dependencies; build; run_main_job ;;
  test) install_dependencies; build; run_tests ;;
  *) sed -n '2,10p' "$0" >&2; exit 2 ;;
esac
