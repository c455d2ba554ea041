#!/usr/bin/env bash
# Renders the README's pictures into docs/images with render_model. Run after building:
#   source devel/setup.bash && scripts/make_readme_images.sh
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
OUT=$REPO/docs/images
mkdir -p "$OUT"
render() { rosrun bullet_sim render_model "$@"; }

render --xacro "$(rospack find smartwheelchair_model)/urdf/smartwheelchair_model.urdf.xacro" --world home.world \
  --view chase --size 640x480 --out "$OUT/wheelchair.png"
render --xacro "$(rospack find smartcar_description)/urdf/smartcar.urdf.xacro" --world empty.world \
  --view chase --size 640x480 --out "$OUT/smartcar.png"
render --xacro "$(rospack find yahboomcar_description)/urdf/yahboomcar.urdf.xacro" --world empty.world \
  --view chase --size 640x480 --out "$OUT/yahboomcar.png"
render --xacro "$(rospack find tianracer_description)/urdf/tianracer.urdf.xacro" --world empty.world \
  --view chase --size 640x480 --out "$OUT/tianracer.png"
render --xacro "$(rospack find smartwheelchair_model)/urdf/smartwheelchair_model.urdf.xacro" --world home.world \
  --view top --size 800x640 --out "$OUT/wheelchair_home_top.png"
render --xacro "$(rospack find yahboomcar_description)/urdf/yahboomcar.urdf.xacro" --world home.world \
  --view camera:camera --out "$OUT/yahboomcar_camera.png"
render --urdf "$REPO/bullet_sim/test/fixtures/robots/depth_camera_box.urdf" --world home.world --pose -2,0,0 \
  --view depth:depth_camera --out "$OUT/depth_camera.png"
# A scenario's top view with its trail, and the summary picture of a sweep of its matrix (a local Ray instance).
SCENARIOS=$REPO/bullet_sim/scenarios
RUNS=$(mktemp -d)
rosrun bullet_sim scenario "$SCENARIOS/wheelchair_doorway.yaml" --out "$RUNS/doorway" >/dev/null
cp "$RUNS/doorway/top.png" "$OUT/scenario_doorway_top.png"
rosrun bullet_sim sweep "$SCENARIOS/wheelchair_doorway_matrix.yaml" --out "$RUNS/sweep" --no-progress >/dev/null || true
cp "$RUNS/sweep/summary.png" "$OUT/sweep_summary.png"
rm -rf "$RUNS"
# The live viewer in headless Chromium (multi_robot.launch with web_port).
/usr/bin/python3 "$REPO/scripts/web_viewer_screenshot.py" "$OUT/web_viewer.png" >/dev/null
echo "wrote $(ls "$OUT" | tr '\n' ' ')"
