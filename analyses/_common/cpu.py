"""CPU time of the machine and of this process: how benchmarks say whether other work
shared the machine while they ran (their CPU time minus the benchmark's own)."""
from __future__ import annotations

import os


def machine_cpu():
    """CPU seconds all processes of the machine have used (``/proc/stat``: user, nice,
    system, irq, softirq, steal), or None where it cannot be read."""
    try:
        with open("/proc/stat") as fh:
            f = [int(v) for v in fh.readline().split()[1:]]
    except (OSError, ValueError):
        return None
    return (f[0] + f[1] + f[2] + sum(f[5:8])) / os.sysconf("SC_CLK_TCK")


def own_cpu():
    """CPU seconds of this process and of its reaped children (worker processes are
    children, reaped when they stop)."""
    import resource

    a, b = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(
        resource.RUSAGE_CHILDREN)
    return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime
