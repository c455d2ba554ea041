"""What the sweep tests share: Ray nodes on this machine that a test starts and stops by their PIDs (never with
`ray stop`, which ends every Ray process of the machine) and that end with it, and a stand-in for `scenario`."""
import os
import signal
import socket
import subprocess
import threading
import time

STOP_GRACE = 3.0  # [s] a cluster's processes get after SIGTERM
START_TIMEOUT = 90  # [s] for `ray start`
POLL = 0.1  # [s]
# Ray without its usage report and without the token auth of shared clusters.
RAY_ENV = {"RAY_USAGE_STATS_ENABLED": "0", "RAY_AUTH_MODE": "disabled"}
# `rosrun bullet_sim sweep`, ending with the test's process should that be killed (rosrun execs the tool).
SWEEP = ["setpriv", "--pdeathsig", "KILL", "rosrun", "bullet_sim", "sweep"]


def free_ports(count):
    sockets = [socket.socket() for _ in range(count)]
    for s in sockets:
        s.bind(("127.0.0.1", 0))
    ports = [s.getsockname()[1] for s in sockets]
    for s in sockets:
        s.close()
    return ports


def own_ancestors():
    """This process and its parents (whose command lines may name a marker: they are not the cluster's)."""
    pids, pid = set(), os.getpid()
    while pid > 1:
        pids.add(pid)
        with open("/proc/%d/stat" % pid) as file:
            pid = int(file.read().rsplit(")", 1)[1].split()[1])
    return pids


def processes_with(marker):
    """{pid: command line} of the processes whose command line or environment holds `marker` (a temp dir)."""
    found = {}
    mine = own_ancestors()
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as file:
                cmdline = file.read()
            with open("/proc/%s/environ" % pid, "rb") as file:
                environment = file.read()
        except OSError:
            continue
        if int(pid) not in mine and (marker.encode() in cmdline or marker.encode() in environment):
            found[int(pid)] = cmdline.replace(b"\0", b" ").decode(errors="replace")
    return found


def stop_processes(marker):
    """Ends the processes that `marker` names (SIGTERM, then SIGKILL), each by its PID."""
    for signal_number in (signal.SIGTERM, signal.SIGKILL):
        for pid in processes_with(marker):
            try:
                os.kill(pid, signal_number)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + STOP_GRACE
        while processes_with(marker) and time.monotonic() < deadline:
            time.sleep(POLL)


def node_ports():
    """`ray start` options giving a node ports of its own."""
    ports = free_ports(6)
    return ["--node-manager-port", str(ports[0]), "--object-manager-port", str(ports[1]),
            "--dashboard-agent-listen-port", str(ports[2]), "--metrics-export-port", str(ports[3]),
            "--runtime-env-agent-port", str(ports[4]), "--min-worker-port", str(ports[5]),
            "--max-worker-port", str(ports[5] + 100)]


class RayNode:
    """A Ray node of `ray start --block` with its own ports and temp dir. Its processes end with stop(), or with
    this test's process if it is killed first: `ray start` gets SIGKILL then (setpriv --pdeathsig) and its reaper
    ends its process group."""

    def __init__(self, arguments, temp_dir, env):
        self.temp_dir = temp_dir
        command = ["setpriv", "--pdeathsig", "KILL", "ray", "start", "--block", "--temp-dir", temp_dir,
                   "--disable-usage-stats"] + arguments + node_ports()
        self.process = subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, text=True, start_new_session=True)
        self.output = []
        threading.Thread(target=lambda: self.output.extend(self.process.stdout), daemon=True).start()
        deadline = time.monotonic() + START_TIMEOUT
        while not any("Ray runtime started" in line for line in self.output):
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError("ray start: " + "".join(self.output))
            time.sleep(POLL)

    def stop(self):
        """Ends the node (SIGTERM to `ray start`, then SIGKILL) and whatever of it is left, each by its PID."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=STOP_GRACE * 3)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(timeout=STOP_GRACE)
        stop_processes(self.temp_dir)


def started(arguments, temp_dir, env):
    """A RayNode of `arguments(ports)`, started again on new ports once if the first start fails: a port found
    free may be taken before Ray binds it (another test's node ending, or starting, on this machine)."""
    try:
        return RayNode(arguments(), temp_dir, env)
    except RuntimeError as first:
        print("ray start failed once, starting again on other ports: %s" % first, flush=True)
        return RayNode(arguments(), temp_dir, env)


def start_head(temp_dir, cpus, env):
    """The head node, on a free port; returns it and its address, 127.0.0.1:PORT."""
    address = []

    def arguments():
        port, dashboard_port, client_port = free_ports(3)
        address[:] = ["127.0.0.1:%d" % port]
        return ["--head", "--port", str(port), "--num-cpus", str(cpus), "--include-dashboard", "false",
                "--dashboard-port", str(dashboard_port), "--ray-client-server-port", str(client_port)]
    return started(arguments, temp_dir, env), address[0]


def start_node(address, temp_dir, cpus, env):
    """One more node, joined to the head at `address`."""
    return started(lambda: ["--address", address, "--num-cpus", str(cpus)], temp_dir, env)


def raylet_of(temp_dir):
    """(pid, node id) of the raylet of the node whose temp dir is `temp_dir`."""
    raylets = [(pid, line) for pid, line in processes_with(temp_dir).items() if "/raylet/raylet " in line]
    if len(raylets) != 1:
        raise RuntimeError("expected one raylet under %s, found %s" % (temp_dir, raylets))
    pid, line = raylets[0]
    return pid, line.split("--node_id=", 1)[1].split()[0]


def real_scenario():
    return subprocess.run(["catkin_find", "--first-only", "bullet_sim", "scenario"], capture_output=True,
                          text=True, check=True).stdout.strip()


def write_stand_in(folder, name, text):
    """An executable stand-in for `scenario` in `folder`: `text` with %(folder)r and %(real)r filled in."""
    path = os.path.join(folder, name)
    with open(path, "w") as file:
        file.write(text % {"folder": folder, "real": real_scenario()})
    os.chmod(path, 0o755)
    return path
