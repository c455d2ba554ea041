#!/usr/bin/env bash
# Runs `rosrun bullet_sim bench` on the wheelchair in home.world and on the bench scenario (bullet_sim/bench:
# the robot and home our peers measured PyBullet and MuJoCo with), and rewrites docs/performance.md between
# <!-- bench:begin --> and <!-- bench:end --> (created under its title when missing), and
# its camera table (bench --camera) between <!-- bench-camera:begin --> and <!-- bench-camera:end -->, and the
# live viewer's cost (bench --web-viewer) between <!-- bench-web:begin --> and <!-- bench-web:end -->.
# Run after building, on a machine as quiet as you can make it:
#   source devel/setup.bash && scripts/bench_readme.sh [all|physics|camera|web]   # default all
# BENCH_REPEAT=5 runs per figure (medians).
set -euo pipefail
SECTIONS=${1:-all}
case "$SECTIONS" in
all | physics | camera | web) ;;
*)
  echo "usage: $0 [all|physics|camera|web]" >&2
  exit 2
  ;;
esac
export PATH=/usr/bin:$PATH:/usr/local/bin  # Debian's ROS tools and the python3 below
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
REPEAT=${BENCH_REPEAT:-5}
SCENARIO=$REPO/bullet_sim/bench
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# bench NAME ARGS...: runs bench with ARGS (and --repeat REPEAT unless ARGS give one) into $OUT/NAME.json.
bench() {
  local name=$1
  shift
  local repeat=(--repeat "$REPEAT")
  if [[ " $* " == *" --repeat "* ]]; then repeat=(); fi  # bench takes one --repeat
  echo "rosrun bullet_sim bench $*" >"$OUT/$name.command"
  echo "== $name: bench $*" >&2
  rosrun bullet_sim bench "${repeat[@]}" "$@" >"$OUT/$name.json"
}

CHAIR=$(rospack find smartwheelchair_model)/urdf/smartwheelchair_model.urdf.xacro
ROBOT=(--robot "$SCENARIO/bench_robot.urdf" --world "$SCENARIO/bench_home.world")

# The camera figures of issue 13: the wheelchair in home.world with its lidar on, driving 4 s of the arc (the
# flat leaves room for that much), a camera on it. The load averages before and after go into the page.
camera_section() {
  mkdir -p "$OUT/camera"
  # How busy the machine is without us: its CPU time over 2 s before the runs (/proc/stat's first line).
  head -1 /proc/stat >"$OUT/camera/stat_before"
  sleep 2
  head -1 /proc/stat >>"$OUT/camera/stat_before"
  cut -d' ' -f1-3 /proc/loadavg >"$OUT/camera/load_before"
  local chair=(--robot "$CHAIR" --world home.world --duration 4)
  bench camera/rgb "${chair[@]}" --camera 640x480@30
  bench camera/depth "${chair[@]}" --camera 640x480@20 --depth
  bench camera/rgb_hd "${chair[@]}" --camera 1920x1080@30
  bench camera/depth_hd "${chair[@]}" --camera 1920x1080@30 --depth
  cut -d' ' -f1-3 /proc/loadavg >"$OUT/camera/load_after"
  /usr/bin/python3 "$REPO/scripts/bench_readme_camera.py" "$OUT/camera" "$REPO/docs/performance.md" "$REPEAT"
}
if [[ $SECTIONS == camera ]]; then
  camera_section
  exit 0
fi

# The live viewer's cost (issue 35): the wheelchair turning in place in home.world (clear of its walls for as
# long as it turns), its lidar on, with one page open on the viewer, against the same run without it.
web_section() {
  mkdir -p "$OUT/web"
  cut -d' ' -f1-3 /proc/loadavg >"$OUT/web/load_before"
  bench web/viewer --robot "$CHAIR" --world home.world --cmd 0,0.5 --duration 300 --web-viewer
  cut -d' ' -f1-3 /proc/loadavg >"$OUT/web/load_after"
  /usr/bin/python3 "$REPO/scripts/bench_readme_web.py" "$OUT/web" "$REPO/docs/performance.md" "$REPEAT"
}
if [[ $SECTIONS == web ]]; then
  web_section
  exit 0
fi

# home.world has a wall 2.5 m north of the origin: 5 s of the arc keeps the chair clear of it.
bench wheelchair --robot "$CHAIR" --world home.world --duration 5
bench default "${ROBOT[@]}"
bench contact "${ROBOT[@]}" --wheel-model contact
bench raycast "${ROBOT[@]}" --wheel-model raycast
bench lidar3d "${ROBOT[@]}" --lidar 1800x16
bench obstacles "${ROBOT[@]}" --lidar 1800x16 --obstacles 1000
# One start per process: start-up gets runs of its own, short ones.
for run in $(seq "$REPEAT"); do bench "startup$run" "${ROBOT[@]}" --duration 0.1 --repeat 1; done

/usr/bin/python3 - "$OUT" "$REPO/docs/performance.md" "$REPEAT" <<'EOF'
import datetime, json, os, sys, textwrap

repo = os.path.dirname(os.path.dirname(os.path.abspath(sys.argv[2])))  # the page is docs/performance.md
sys.path.insert(0, os.path.join(repo, "scripts"))
from bench_machine import cpu_model
from readme_section import write_section

out, readme, repeat = sys.argv[1], sys.argv[2], sys.argv[3]
runs = {name[:-5]: json.load(open(os.path.join(out, name))) for name in os.listdir(out) if name.endswith(".json")}
commands = {name: open(os.path.join(out, name + ".command")).read().strip() for name in runs}
d, chair = runs["default"], runs["wheelchair"]


def median(values):
    values = sorted(values)
    middle = len(values) // 2
    return values[middle] if len(values) % 2 else (values[middle - 1] + values[middle]) / 2

starts = [run for name, run in runs.items() if name.startswith("startup")]
startup_s = median(run["startup_s"] for run in starts)
startup_cpu_s = median(run["startup_cpu_s"] for run in starts)


def met(ok):
    return "yes" if ok else "**no**"


def mega(rays):
    return "%.1f M" % (rays / 1e6)


physics = d["rtf_physics"]
rows = [
    ("RTF physics only, 1 kHz, default wheel model", "%.0f (%s)" % (physics, d["wheel_model"]), "8.1", "42.8",
     ">= 100 and >= 3x MuJoCo", met(physics >= max(100, 3 * 42.8))),
    ("RTF, contact wheel model", "%.0f" % runs["contact"]["rtf_physics"], "8.1", "42.8", ">= 30",
     met(runs["contact"]["rtf_physics"] >= 30)),
    ("RTF with 360-ray lidar at 10 Hz", "%.0f (%.0f %% of physics only)" % (d["rtf_lidar"], 100 * d["rtf_lidar"] / physics),
     "6.8", "40.1", ">= 95 % of our physics-only figure", met(d["rtf_lidar"] >= 0.95 * physics)),
    ("RTF with 1800 x 16 rays at 10 Hz", "%.0f" % runs["lidar3d"]["rtf_lidar"], "0.44", "5.7", ">= 20",
     met(runs["lidar3d"]["rtf_lidar"] >= 20)),
    ("rays/s, one core, home world", "%s (360 rays), %s (1800 x 16)" % (mega(d["rays_per_s"]), mega(runs["lidar3d"]["rays_per_s"])),
     "0.30 M", "1.95 M", ">= 15 M", met(min(d["rays_per_s"], runs["lidar3d"]["rays_per_s"]) >= 15e6)),
    ("rays/s with 1,000 static obstacles", "%s (1800 x 16)" % mega(runs["obstacles"]["rays_per_s"]), "", "", ">= 10 M",
     met(runs["obstacles"]["rays_per_s"] >= 10e6)),
    ("render 640 x 480 chase view", "%.1f ms" % d["render_ms"], "139 ms", "17.7 ms", "<= 15 ms", met(d["render_ms"] <= 15)),
    ("PNG encode 640 x 480", "%.1f ms" % d["png_ms"], "", "", "<= 10 ms", met(d["png_ms"] <= 10)),
    ("start to first step", "%.2f s (%.2f s of CPU)" % (startup_s, startup_cpu_s), "0.24 s", "0.46 s", "<= 0.3 s", met(startup_s <= 0.3)),
    ("10 s arc from rest, position error", "%.3f m" % d["pose_error_m"], "0.16 m", "0.058 m", "<= 0.05 m",
     met(d["pose_error_m"] <= 0.05)),
    ("same, after the 1 s spin-up", "%.3f m" % d["pose_error_steady_m"], "", "", "<= 0.01 m",
     met(d["pose_error_steady_m"] <= 0.01)),
    ("peak RSS", "%.0f MB (%.0f MB before the first render)" % (d["peak_rss_mb"], d["peak_rss_before_render_mb"]),
     "", "~117 MB", "<= 150 MB", met(d["peak_rss_mb"] <= 150)),
]

warnings = sorted({w for run in runs.values() for w in run["warnings"]})
today = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
lines = [
    "Generated by `scripts/bench_readme.sh` on %s, on a %s-core %s (`nproc`, `/proc/cpuinfo`), with"
    % (today, len(os.sched_getaffinity(0)), cpu_model()),
    "`rosrun bullet_sim bench` (JSON on stdout; `bench --help` says what each figure is). Each figure is the",
    "median of %s runs. The scenario is our peers' (`bullet_sim/bench`: a 33 kg robot with drive wheels of" % repeat,
    "r = 0.284 m, two casters and a 360-beam lidar, in a furnished 10 x 10 m home), driving v = 0.5 m/s,",
    "w = 0.3 rad/s for 10 s after 0.5 s at rest, 1 ms steps. Timings on a shared 2-core machine vary by about",
    "+-25 % from run to run; rerun the script on yours.",
    "",
    "| figure | ours | PyBullet | MuJoCo | target | met |",
    "|---|---|---|---|---|---|",
] + ["| %s |" % " | ".join(row) for row in rows] + [
    "",
] + textwrap.wrap("Per wheel model (`--wheel-model`), physics only: %s." % "; ".join(
    "%s, RTF %.0f, position error %.3f m from rest and %.3f m after the spin-up"
    % (run["wheel_model"], run["rtf_physics"], run["pose_error_m"], run["pose_error_steady_m"])
    for run in (runs["contact"], runs["raycast"])), 110) + [
    "",
    "The wheelchair (its xacro in `home.world`, the first 5 s of the same arc, which is what the flat leaves room",
    "for): RTF %.0f physics only and %.0f with its 360-beam 5.5 Hz lidar; %.2f s to the first step, xacro"
    % (chair["rtf_physics"], chair["rtf_lidar"], chair["startup_s"]),
    "included; peak RSS %.0f MB; position error %.3f m from rest (its 1.8 m/s^2 `wheelAcceleration` ramp lags"
    % (chair["peak_rss_mb"], chair["pose_error_m"]),
    "the unicycle by design) and %.3f m after the spin-up." % chair["pose_error_steady_m"],
    "",
    "Commands (each with `--repeat %s`; start-up is the median of %s runs of the first with `--duration 0.1"
    % (repeat, repeat),
    "--repeat 1`):",
    "",
    "```",
] + [commands[name].replace(repo + "/", "") for name in
     ("default", "contact", "raycast", "lidar3d", "obstacles", "wheelchair")] + ["```"]
if warnings:
    lines += ["", "Load warnings:"] + ["- " + w for w in warnings]

write_section(readme, "bench", lines,
              lambda text, section: text.replace("# Performance\n", "# Performance\n" + section + "\n", 1))
print("\n".join(lines))
EOF

if [[ $SECTIONS == all ]]; then
  camera_section
  web_section
fi
