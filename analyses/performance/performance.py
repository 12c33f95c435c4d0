"""Regenerate the whole of ``reports/performance.md`` with one command.

Run as ``python analyses/performance/performance.py [--no-full-map]`` (long: each section
states what its script measured; the 30,000-point map, left out by ``--no-full-map``, is
the longest part).  Each benchmark is its own script, run here in a
fresh process one after the other (never two at once: they time the machine), and each
replaces its own section of the report:

=========================  ==========================================================
``benchmark_kernel.py``    throughput, accuracy orders
``first_run.py``           the CLI's first run on an empty and a filled numba cache
``benchmark_sweep.py``     the main job warm, serial and on 2 workers
``profile_sweep.py``       where the main job's time goes; the transient extrapolation
``work_precision.py``      error against run time vs SciPy; overhead against the RHS floor
``stress.py``              the numerical stress table
``benchmark_map.py``       parameter-map throughput on 1 and 2 workers; the 30k-point map
``lyapunov_error_control.py``  the tangent vectors' error test of the exponents
``census_bench.py``        the attractor census, a 200 x 200 basin image, early stopping
``ring_bench.py``          the ring model's sweep against eq. (5)'s; its cost per period
``variational_bench.py``   the rotor's hand-written variational functions against the
                           generic ones (issue 42)
=========================  ==========================================================

With ``--smoke DIR`` every script runs in its smoke mode (``--smoke DIR``: tiny problems,
the report written under ``DIR``).
"""
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # analyses/: _common
from _common import smoke  # noqa: E402

SCRIPTS = ("benchmark_kernel.py", "first_run.py", "benchmark_sweep.py", "profile_sweep.py",
           "work_precision.py", "stress.py", "benchmark_map.py", "lyapunov_error_control.py",
           "census_bench.py", "ring_bench.py", "variational_bench.py", "call_overhead.py")


def main(argv):
    ap = smoke.parser(__doc__)
    ap.add_argument("--no-full-map", action="store_true",
                    help="project the 30,000-point map's time without running it")
    opts = ap.parse_args(argv)
    failed = []
    for name in SCRIPTS:
        args = [sys.executable, str(HERE / name)]
        if name == "benchmark_map.py" and opts.no_full_map:
            args.append("--no-full")
        if opts.smoke is not None:
            args += ["--smoke", str(opts.smoke)]
        t0 = time.perf_counter()
        print(f"== {name}", flush=True)
        rc = subprocess.run(args, cwd=HERE.parents[1], stdout=subprocess.DEVNULL).returncode
        print(f"   exit {rc}, {time.perf_counter() - t0:.0f} s", flush=True)
        if rc:
            failed.append(name)
    if failed:
        print(f"failed: {', '.join(failed)} (their sections were left as they were)",
              file=sys.stderr)
        return 1
    print(f"{smoke.moved(HERE.parents[1] / 'reports' / 'performance.md', opts.smoke)} "
          "regenerated")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
