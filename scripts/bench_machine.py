"""What the benchmark scripts say of the machine they measured on."""


def cpu_model():
    """The CPU's model name, as /proc/cpuinfo gives it."""
    with open("/proc/cpuinfo") as file:
        for line in file:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown CPU"


def load_average():
    """The load average over 1, 5 and 15 minutes, as /proc/loadavg gives it: "0.60 0.82 0.97"."""
    with open("/proc/loadavg") as file:
        return " ".join(file.read().split()[:3])
