"""gzserver's and gzclient's command lines, served by bullet_sim: the node types gzserver, gazebo, debug and
gzclient of this gazebo_ros stand-in. Options are Gazebo 11's; the world and the pause become the parameters of
bullet_sim's simulator, which this process becomes (exec). ROS arguments (name:=value) pass through.
"""
import argparse
import os
import shutil
import signal
import sys

EMPTY_WORLD = "worlds/empty.world"
PHYSICS_ENGINES = ("ode", "bullet", "dart", "simbody")
# System plugins whose work bullet_sim's simulator does itself (the ROS API and Gazebo's paths).
SERVED_PLUGINS = ("libgazebo_ros_api_plugin.so", "libgazebo_ros_paths_plugin.so")


def no_window(program):
    """The one line that says there is no window, and how to see the simulation instead."""
    return ("%s: bullet_sim is headless, so there is no window to show. Take pictures with "
            "`rosservice call /gazebo/snapshot \"{file: 'view.png', view: 'chase'}\"` or "
            "`rosrun bullet_sim render_model`." % program)


def warn(program, message):
    print("[WARN] %s: %s" % (program, message), file=sys.stderr, flush=True)


def gzserver_parser(program):
    """Gazebo 11's gzserver options; unknown ones are allowed, as gzserver allows them."""
    parser = argparse.ArgumentParser(prog=program, allow_abbrev=False,
                                     description="Run bullet_sim's simulator with gzserver's command line.")
    parser.add_argument("-v", "--version", action="store_true", help="print the version and exit")
    parser.add_argument("--verbose", action="store_true", help="accepted")
    parser.add_argument("-u", "--pause", action="store_true", help="start paused")
    parser.add_argument("--lockstep", action="store_true",
                        help="ray sensors cast within the step they measure (the simulator's ~lockstep)")
    parser.add_argument("-e", "--physics", help="accepted: bullet_sim always simulates with Bullet")
    parser.add_argument("-p", "--play", help="not supported: bullet_sim plays no Gazebo logs")
    parser.add_argument("-r", "--record", action="store_true", help="not honoured: record with rosbag")
    for option in ("--record_encoding", "--record_path", "--record_period", "--record_filter"):
        parser.add_argument(option, help="not honoured")
    parser.add_argument("--record_resources", action="store_true", help="not honoured")
    parser.add_argument("--seed", type=float, help="the seed of the sensors' noise")
    parser.add_argument("--initial_sim_time", type=float, help="not honoured: time starts at the first step")
    parser.add_argument("--iters", type=int, help="not honoured: the simulation runs until stopped")
    parser.add_argument("--minimal_comms", action="store_true", help="accepted")
    parser.add_argument("-s", "--server-plugin", action="append", default=[], help="system plugins")
    parser.add_argument("-o", "--profile", help="not honoured: bullet_sim has no physics presets")
    parser.add_argument("-g", "--gui-plugin", action="append", default=[], help=argparse.SUPPRESS)
    parser.add_argument("--gui-client-plugin", action="append", default=[], help=argparse.SUPPRESS)
    parser.add_argument("world_file", nargs="?", default=EMPTY_WORLD,
                        help="a world file: a path, or a name on Gazebo's resource path or in bullet_sim's worlds")
    parser.add_argument("pass_through", nargs="*", help=argparse.SUPPRESS)
    return parser


def simulator_arguments(program, argv):
    """bullet_sim simulator's arguments for gzserver's command line `argv`. Exits on -v, -h and -p."""
    ros_arguments = [a for a in argv if ":=" in a]
    options, unknown = gzserver_parser(program).parse_known_args([a for a in argv if ":=" not in a])
    if options.version:
        print("bullet_sim's gzserver (Gazebo 11's command line)")
        sys.exit(0)
    if options.play:
        warn(program, "-p/--play [%s]: bullet_sim cannot play Gazebo logs" % options.play)
        sys.exit(1)
    if unknown:
        warn(program, "unknown options %s ignored, as gzserver ignores them" % unknown)
    for name, value in (("-r/--record", options.record), ("--iters", options.iters),
                        ("--initial_sim_time", options.initial_sim_time), ("-o/--profile", options.profile)):
        if value:
            warn(program, "%s is not honoured by bullet_sim" % name)
    if options.physics and options.physics not in PHYSICS_ENGINES:
        warn(program, "unknown physics engine [%s]; bullet_sim simulates with Bullet" % options.physics)
    for plugin in options.server_plugin:
        if os.path.basename(plugin) not in SERVED_PLUGINS:
            warn(program, "system plugin [%s] ignored: bullet_sim loads no Gazebo plugins" % plugin)
    if options.pass_through:
        warn(program, "arguments after the world file %s ignored" % options.pass_through)

    arguments = ["_world:=" + options.world_file, "_world_fallback:=" + EMPTY_WORLD]
    if options.pause:
        arguments.append("_paused:=true")
    if options.lockstep:
        arguments.append("_lockstep:=true")
    if options.seed is not None:
        arguments.append("_seed:=%d" % int(options.seed))
    if not any(a.startswith("__name:=") for a in ros_arguments):
        arguments.append("__name:=gazebo")  # gzserver's ROS API lives under /gazebo
    return arguments + ros_arguments


def simulator_executable(program):
    import roslib.packages
    found = roslib.packages.find_node("bullet_sim", "simulator")
    if not found:
        warn(program, "bullet_sim's simulator is not built: run scripts/workspace.sh build and source "
                      "devel/setup.bash")
        sys.exit(1)
    return found[0]


def run_server(program, argv, under_gdb=False):
    """Becomes bullet_sim's simulator (under gdb for `debug`, when gdb is installed)."""
    arguments = simulator_arguments(program, argv)
    simulator = simulator_executable(program)
    gdb = shutil.which("gdb") if under_gdb else None
    if under_gdb and not gdb:
        warn(program, "gdb is not installed (apt-get install gdb); running the simulator without it")
    if gdb:
        batch = [] if sys.stdin.isatty() else ["-batch"]  # under roslaunch: run, then a backtrace on a crash
        command = [gdb, "-q"] + batch + ["-ex", "run", "-ex", "bt", "--args", simulator] + arguments
    else:
        command = [simulator] + arguments
    sys.stdout.flush()
    os.execv(command[0], command)


def run_client():
    """gzclient: says there is no window, then waits until it is stopped."""
    # The handlers come before the line: a stop that follows the line at once must find them in place.
    for stop in (signal.SIGINT, signal.SIGTERM):
        signal.signal(stop, lambda *_: sys.exit(0))
    print(no_window("gzclient") + " This process stays up until the launch ends.", flush=True)
    while True:
        signal.pause()
