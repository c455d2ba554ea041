"""What the benchmark scripts say of the machine they measured on."""


def cpu_model():
    """The CPU's model name, as /proc/cpuinfo gives it."""
    with open("/proc/cpuinfo") as file:
        for line in file:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown CPU"
