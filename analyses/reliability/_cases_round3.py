"""Cases of :mod:`reliability` from the third adversarial round (issue 32, part 1): one
class per failure class, each with its variants.

Faults of processes and files (the command line in a subprocess of its own session):

* **stopped process** -- SIGSTOP to a worker (classify, bifurcation, attractors, basins,
  orbits), to the points' queue process (classify) or to a Dask worker (map): the
  command must end (exit 2, one line), never wait for good;
* **SIGTERM with a stopped process** -- the same, then SIGTERM: exit 143;
* **signal during a large write** -- SIGTERM or SIGINT as soon as the temporary of a
  large simulate file, its rerun or a classify has data in it: the signal ends the
  command (exit 128 + signum), no temporary left;
* **killed during a write** -- SIGKILL at that moment, then the same command again (with
  --resume where a checkpoint was kept): it succeeds and leaves only its output;
* **resource tracker killed** -- SIGKILL to multiprocessing's resource tracker of a map:
  exit 0 or one line, no traceback;
* **damaged map store** -- a map's ``regime`` chunk or ``period`` directory removed, a
  chunk truncated to 0 bytes or overwritten, an array's metadata broken, the
  consolidated metadata stripped (with ``period`` removed too): ``plot`` must say so
  (exit 2, one line).

Requests that must be refused in one line (exit 2) or a ValueError (the API, one Python
process each, with a time limit: a hang is a verdict):

* **raw parameter vector** -- ``simulate(vector, model=ROTOR)`` and ``System(vector,
  model=ROTOR)`` with f = -1, NaN in f, eps, kh or eta, eta = 0;
* **array coercion** -- a complex, str or object ``state0``, ``sweep(eta=['1.0',
  ...])``, ``adaptive='no'``;
* **numerical edge** -- ``detect_period`` of a 2-cycle near 1e308 (2 or a ValueError,
  never 1), ``extrapolate_limit`` of one point;
* **tampered file** -- ``rerun`` of a file whose attributes contradict it (a sweep's
  ``param_kh='abc'``, ``-5``, bad JSON, swapped ``regime:flag_meanings``,
  ``eta:units``; a simulation's ``impact_theta:units``, ``reason``, ``counter_steps``,
  ``state_X``, ``param_kh``, a removed ``title``): reported ("different", exit 1, or
  refused, exit 2), never "identical";
* **options refused up front** -- ``--figsize 1e9x1e9``, ``--dpi 1000000`` (before any
  work: no file), ``--preset ''``, ``--eta 1_0:1_1:0.05``, fullwidth digits, a 20-digit
  ``--workers``, ``continue --ds 0.1 --ds-max 0.01``;
* **plot of a bad file** -- NaN in eta, undeclared regime codes.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time

SWEEP = ["--eta", "0.95:1.25:0.002", "--preset", "fig8", "--direction", "both",
         "--no-progress"]

#: case -> (arguments, which child: -1 the newest worker, 0 the queue's, "dask")
STOPPED = {
    "classify, a worker": (["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], -1),
    "classify, the queue process": (["classify", *SWEEP, "--workers", "2", "-o", "c.nc"],
                                    0),
    "bifurcation, a worker": (["bifurcation", *SWEEP, "--workers", "2", "-o", "b.png"],
                              -1),
    "attractors, a worker": (["attractors", "--preset", "fig8", "--eta", "1.25",
                              "--starts", "400", "--workers", "2", "--no-progress", "-o",
                              "a.nc"], -1),
    "basins, a worker": (["basins", "--preset", "fig8", "--eta", "1.25", "--grid", "24x24",
                          "--workers", "2", "-o", "bs.nc"], -1),
    "orbits, a worker": (["orbits", "--preset", "fig11", "--eta", "1.06", "--period",
                          "1:8", "--workers", "2", "-o", "o.nc"], -1),
    "map, a Dask worker": (["map", "--eta", "1.0:1.3:0.002", "--vary", "kh=50:80:5",
                            "--workers", "2", "--no-progress", "-o", "m.zarr"], "dask"),
}

#: a simulate file of about 64 MB (2 million dense samples of 4 states)
BIG = ["simulate", "--eta", "1.2", "--periods", "10000", "--dense", "200", "-o", "s.nc"]
FIG11 = ["classify", "--preset", "fig11", "--eta", "0.9:1.5:0.002", "--workers", "2",
         "--no-progress", "-o", "c.nc"]

#: case -> (arguments, signal, a file made first by these arguments, or None)
WRITES = {
    "simulate 64 MB, SIGTERM": (BIG, signal.SIGTERM, None),
    "simulate 64 MB, SIGINT": (BIG, signal.SIGINT, None),
    "rerun of a 64 MB simulate, SIGTERM": (["rerun", "s.nc"], signal.SIGTERM, BIG),
    "classify fig11, SIGTERM": (FIG11, signal.SIGTERM, None),
    "map to Zarr, SIGTERM": (["map", "--eta", "1.0:1.1:0.01", "--vary", "kh=50:60:10",
                              "--workers", "1", "--no-progress", "-o", "m.zarr"],
                             signal.SIGTERM, None),
}

#: case -> (arguments, output, arguments of the later run that must clean up)
KILLED = {
    "simulate": (BIG, "s.nc", []),
    "bifurcation": (["bifurcation", "--eta", "1.0:1.1:0.01", "--no-progress", "-o",
                     "b.png"], "b.png", []),
    "classify": (["classify", "--eta", "1.0:1.1:0.01", "--no-progress", "-o", "c.nc"],
                 "c.nc", ["--resume"]),
    "continue": (["continue", "--eta", "1.12", "--stop", "1.3", "-o", "br.nc"], "br.nc",
                 []),
    "map to Zarr": (["map", "--eta", "1.0:1.1:0.01", "--vary", "kh=50:60:10",
                     "--workers", "1", "--no-progress", "-o", "m.zarr"], "m.zarr",
                    ["--resume"]),
}

#: API snippets: ENTRY is evaluated; a ValueError (or OK(out) true) is the clean outcome
API = '''
import math, sys
import numpy as np
import xarray as xr
import vibimpact as vi
p = vi.presets.get("fig8")
v = np.array(p.as_array(), dtype=float)
def vec(**kw):
    x = v.copy()
    for k, val in kw.items():
        x[list(vi.ROTOR.param_names).index(k)] = val
    return x
nan = float("nan")
try:
    out = ENTRY
except ValueError as exc:
    print(f"refused: {type(exc).__name__}: {exc}"[:300])
    sys.exit(0)
if OK:
    print(f"ok: {out!r}"[:300])
    sys.exit(0)
print(f"ran: {out!r}"[:300])
sys.exit(3)
'''
#: class -> {case: (entry, condition on out that is also clean, or "False")}
API_CASES = {
    "raw parameter vector": {
        **{f"simulate(vector, {k}={val})": (
            f"vi.simulate(vec({k}={val}), periods=5, model=vi.ROTOR).status", "False")
           for k, val in (("f", "-1.0"), ("f", "nan"), ("eps", "nan"), ("kh", "nan"),
                          ("eta", "0.0"), ("eta", "nan"))},
        **{f"System(vector, {k}={val})": (f"vi.System(vec({k}={val}), model=vi.ROTOR)",
                                          "False")
           for k, val in (("f", "-1.0"), ("eta", "nan"), ("eta", "0.0"))},
    },
    "array coercion": {
        "complex state0": ("vi.simulate(p, periods=2, state0=[1j, 0, 0, 0]).strobe",
                           "False"),
        "state0 of strings": ("vi.simulate(p, periods=2, state0=['0.1', '0', '0', "
                              "'0']).strobe", "False"),
        "object state0 of strings": ("vi.simulate(p, periods=2, state0=np.array(['a', "
                                     "'b', 'c', 'd'], dtype=object)).strobe", "False"),
        "sweep(eta=['1.0', '1.01'])": ("vi.sweep(p, ['1.0', '1.01'])", "False"),
        "SolverSettings(adaptive='no')": ("vi.SolverSettings(adaptive='no')", "False"),
    },
    "numerical edge": {
        "detect_period of a 2-cycle near 1e308": (
            "vi.analysis.detect_period(np.array([[1e308, -1e308], [-1e308, 1e308]] * "
            "20))", "out == 2"),
        "extrapolate_limit of one point": ("vi.analysis.extrapolate_limit([1.0])",
                                           "False"),
        "sweep of an np.arange grid stores vi.grid's values": (
            "vi.sweep(p, np.arange(0.9, 1.5 + 1e-12, 0.002)[:3], analyses=())"
            "['eta'].values", "np.array_equal(out, vi.grid('0.9:1.5:0.002')[:3])"),
    },
    "flag coerced": {
        "write_netcdf(overwrite='no') over a file": (
            "vi.io.write_netcdf(vi.simulate(p, periods=2).to_dataset(), 'w.nc') or "
            "vi.io.write_netcdf(vi.simulate(p, periods=2).to_dataset(), 'w.nc', "
            "overwrite='no')", "False"),
        "plot_map(categorical='no')": ("__import__('vibimpact.plotting.map2d', fromlist=["
                                       "'plot_map']).plot_map(xr.Dataset(), "
                                       "categorical='no')", "False"),
        "lyapunov_spectrum(floquet='yes')": (
            "vi.analysis.lyapunov_spectrum(vi.System(p), floquet='yes')", "False"),
    },
}

#: CLI requests refused in one line before any work: class -> {case: (argv, setup)}
TAMPER = '''
import json, sys
import netCDF4
with netCDF4.Dataset(sys.argv[1], "a") as nc:
    exec(sys.argv[2])
'''
CLI_CASES = {
    "options refused up front": {
        "simulate --plot --figsize 1e9x1e9": (["simulate", "--eta", "1.2", "-o", "s.nc",
                                               "--plot", "x.png", "--figsize",
                                               "1e9x1e9"], None),
        "bifurcation --figsize 1e9x1e9": (["bifurcation", "--eta", "0.9:1.5:0.002",
                                           "--figsize", "1e9x1e9", "-o", "b.png"], None),
        "bifurcation --dpi 1000000": (["bifurcation", "--eta", "0.9:1.5:0.002", "--dpi",
                                       "1000000", "-o", "b.png"], None),
        "--preset ''": (["simulate", "--preset", "", "--eta", "1.2", "-o", "s.nc"], None),
        "--eta 1_0:1_1:0.05": (["classify", "--eta", "1_0:1_1:0.05", "-o", "c.nc"], None),
        "--eta in fullwidth digits": (["simulate", "--eta", "\uff11.\uff12", "-o", "s.nc"],
                                      None),
        "--workers of 20 digits": (["classify", "--eta", "1.0:1.02:0.01", "--workers",
                                    "9" * 20, "-o", "c.nc"], None),
        "continue --ds 0.1 --ds-max 0.01": (["continue", "--eta", "1.12", "--stop", "1.3",
                                             "--ds", "0.1", "--ds-max", "0.01", "-o",
                                             "br.nc"], None),
        "continue --ds 1e-300": (["continue", "--eta", "1.12", "--stop", "1.13", "--ds",
                                  "1e-300", "-o", "br.nc"], None),
        "bifurcation --dpi 1e-300": (["bifurcation", "--eta", "1.0:1.1:0.05", "--dpi",
                                      "1e-300", "-o", "b.png"], None),
        "--figsize 0.001x0.001 --dpi 1": (["bifurcation", "--eta", "1.0:1.1:0.05",
                                           "--figsize", "0.001x0.001", "--dpi", "1", "-o",
                                           "b.png"], None),
        "--figsize 65536x1 --dpi 1": (["bifurcation", "--eta", "1.0:1.1:0.05",
                                       "--figsize", "65536x1", "--dpi", "1", "-o",
                                       "b.png"], None),
    },
    "tampered file": {
        **{f"rerun, {what}": (["rerun", "c.nc"], code) for what, code in (
            ("param_kh='abc'", "nc.setncattr('param_kh', 'abc')"),
            ("param_kh=-5", "nc.setncattr('param_kh', -5.0)"),
            ("params of bad JSON", "nc.setncattr('params', '{not json')"),
            ("regime:flag_meanings, two swapped", "w = nc['regime'].flag_meanings.split(); "
             "w[0], w[1] = w[1], w[0]; nc['regime'].setncattr('flag_meanings', ' '.join(w))"),
            ("eta:units='Hz'", "nc['eta'].setncattr('units', 'Hz')"))},
        # a simulate file (SMALL_SIM): the attributes of one run
        **{f"rerun of a simulate file, {what}": (["rerun", "c.nc"], ("sim", code))
           for what, code in (
            ("impact_theta:units='radian'", "nc['impact_theta'].setncattr('units', "
                                            "'radian')"),
            ("reason='diverged at tau=3'", "nc.setncattr('reason', 'diverged at tau=3')"),
            ("counter_steps=1", "nc.setncattr('counter_steps', 1)"),
            ("state_X changed", "nc.setncattr('state_X', 'vertical velocity')"),
            ("param_kh='abc'", "nc.setncattr('param_kh', 'abc')"),
            ("title removed", "nc.delncattr('title')"))},
    },
    "plot of a bad file": {
        "NaN in eta": (["plot", "c.nc", "-o", "p.png"],
                       "nc['eta'][0] = float('nan')"),
        "undeclared regime codes": (["plot", "c.nc", "-o", "p.png"],
                                    "nc['regime'][0] = 99"),
        "period -7": (["plot", "c.nc", "-o", "p.png"], "nc['period'][0] = -7"),
    },
}
SMALL_SWEEP = ["classify", "--eta", "1.0:1.02:0.01", "--no-progress", "-o", "c.nc"]
SMALL_SIM = ["simulate", "--eta", "1.2", "--periods", "2", "--transient", "0", "-o", "c.nc"]


def _children(kit, pid):
    return sorted(kit._descendants(pid))


def _spawned(pid):
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as fh:
            return b"spawn_main" in fh.read()
    except OSError:
        return False


def _wait(cond, proc, limit=120):
    """Poll ``cond()`` until true; False when ``proc`` ended or ``limit`` s passed."""
    deadline = time.monotonic() + limit
    while not cond():
        if proc.poll() is not None or time.monotonic() > deadline:
            return False
        time.sleep(0.005)
    return True


def _start(argv, cwd):
    return subprocess.Popen([sys.executable, "-m", "vibimpact", *argv], cwd=cwd,
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)


def _env():
    env = dict(os.environ)
    env.pop("VIBIMPACT_PRECOMPILED", None)
    return env


def _end(proc, timeout):
    """``(rc or None on a hang, stdout, stderr)``."""
    try:
        out, err = proc.communicate(timeout=timeout)
        return proc.returncode, out, err
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        return None, out, err


def _writing(cwd):
    """A temporary with data in it (a file of more than 0 bytes or a directory with
    entries): the output is being written (the path check's probe is always empty)."""
    for name in os.listdir(cwd):
        if not name.endswith(".tmp"):
            continue
        full = os.path.join(cwd, name)
        try:
            if (os.path.isdir(full) and os.listdir(full)) or os.path.getsize(full) > 0:
                return True
        except OSError:
            pass
    return False


def stopped_cases(kit, base, timeout):
    out = []
    for case, (argv, which) in STOPPED.items():
        for then_term in (False, True):
            if then_term and which == "dask":
                continue
            d = kit._fresh(base, "stop")
            t0 = time.perf_counter()
            proc = _start(argv, d)
            if which == "dask":
                ok = _wait(lambda proc=proc: [c for c in _children(kit, proc.pid)
                                              if _spawned(c)], proc)
                victims = [c for c in _children(kit, proc.pid) if _spawned(c)]
            else:  # the pool's workers are the newest children; the queue's the oldest
                least = 3 if argv[0] in ("classify", "bifurcation") else 2
                ok = _wait(lambda proc=proc, least=least: len(_children(kit, proc.pid))
                           >= least, proc)
                victims = _children(kit, proc.pid)
            if ok and victims:
                os.kill(victims[which if which != "dask" else -1], signal.SIGSTOP)
                if then_term:
                    time.sleep(0.2)
                    proc.send_signal(signal.SIGTERM)
            rc, _, err = _end(proc, timeout)
            klass = "SIGTERM with a stopped process" if then_term else "stopped process"
            o = kit.judge(klass, case, rc, err, time.perf_counter() - t0,
                          {143} if then_term else {0, 2}, d, keep=("b.png",))
            o.tried = bool(ok and victims)
            out.append(o)
    return out


def write_cases(kit, base, timeout):
    out = []
    for case, (argv, sig, first) in WRITES.items():
        d = kit._fresh(base, "write")
        if first is not None:
            kit.run(first, d, timeout)
        t0 = time.perf_counter()
        proc = _start(argv, d)
        ok = _wait(lambda d=d: _writing(d), proc, limit=timeout)
        if ok:
            proc.send_signal(sig)
        rc, _, err = _end(proc, timeout)
        keep = ("s.nc",) if first is not None else ()
        o = kit.judge("signal during a large write", case, rc, err,
                      time.perf_counter() - t0, {128 + sig}, d, keep=keep)
        o.tried = ok
        out.append(o)
    return out


def killed_write_cases(kit, base, timeout):
    out = []
    for case, (argv, output, again) in KILLED.items():
        d = kit._fresh(base, "killed")
        t0 = time.perf_counter()
        proc = _start(argv, d)
        ok = _wait(lambda d=d: _writing(d), proc, limit=timeout)
        if ok:
            os.killpg(proc.pid, signal.SIGKILL)
        _end(proc, timeout)
        rc, _, err, _ = kit.run([*argv, *again], d, timeout)
        o = kit.judge("killed during a write", f"{case}, then the same command", rc, err,
                      time.perf_counter() - t0, {0}, d, keep=(output,))
        o.tried = ok
        out.append(o)
    return out


def tracker_cases(kit, base, timeout):
    d = kit._fresh(base, "tracker")
    argv = ["map", "--eta", "1.0:1.3:0.01", "--vary", "kh=50:80:10", "--workers", "2",
            "--no-progress", "-o", "m.zarr"]
    t0 = time.perf_counter()
    proc = _start(argv, d)

    def tracker():
        for c in _children(kit, proc.pid):
            try:
                with open(f"/proc/{c}/cmdline", "rb") as fh:
                    if b"resource_tracker" in fh.read():
                        return c
            except OSError:
                pass
        return None

    ok = _wait(lambda: tracker() is not None, proc)
    if ok:
        os.kill(tracker(), signal.SIGKILL)
    rc, _, err = _end(proc, timeout)
    o = kit.judge("resource tracker killed", "map --workers 2, tracker SIGKILLed", rc,
                  err, time.perf_counter() - t0, {0, 2}, d, keep=("m.zarr",))
    o.tried = ok
    return [o]


def _chunk(store, name):
    """The first chunk file of variable ``name`` of a Zarr store."""
    return sorted(p for p in (store / name / "c").rglob("*") if p.is_file())[0]


def _no_consolidated(store, remove=None):
    """Strip the root zarr.json of its consolidated metadata (and remove ``remove``)."""
    import json

    meta = json.loads((store / "zarr.json").read_text())
    meta.pop("consolidated_metadata", None)
    (store / "zarr.json").write_text(json.dumps(meta))
    if remove:
        shutil.rmtree(store / remove, ignore_errors=True)


#: case -> what it does to the map store
DAMAGES = {
    "regime chunk removed": lambda s: shutil.rmtree(s / "regime" / "c"),
    "period directory removed": lambda s: shutil.rmtree(s / "period"),
    "regime chunk truncated to 0 bytes": lambda s: _chunk(s, "regime").write_bytes(b""),
    "period chunk of garbage": lambda s: _chunk(s, "period").write_bytes(b"garbage" * 4),
    "regime metadata not JSON": lambda s: (s / "regime" / "zarr.json").write_text("{"),
    "consolidated metadata stripped": _no_consolidated,
    "consolidated metadata stripped, period removed": lambda s: _no_consolidated(
        s, "period"),
}


def damaged_store_cases(kit, base, timeout):
    out = []
    for case, damage in DAMAGES.items():
        d = kit._fresh(base, "damaged")
        kit.run(["map", "--eta", "1.0,1.1", "--vary", "kh=50,60", "--workers", "1",
                 "--no-progress", "-o", "m.zarr"], d, timeout)
        try:
            damage(d / "m.zarr")
        except OSError:
            pass  # the map was not written: the plot below fails and is judged so
        rc, _, err, sec = kit.run(["plot", "m.zarr", "-o", "p.png"], d, timeout)
        o = kit.judge("damaged map store", f"plot, {case}", rc, err, sec, {2}, d,
                      keep=("m.zarr",))
        o.clean = o.clean and not (d / "p.png").exists()
        out.append(o)
    return out


def api_cases(kit, base, timeout):
    return [kit.python_case(base, "api", klass, case,
                            API.replace("ENTRY", entry).replace("OK", ok), timeout,
                            ("refused:", "ok:"))
            for klass, cases in API_CASES.items() for case, (entry, ok) in cases.items()]


def cli_cases(kit, base, timeout):
    out = []
    for klass, cases in CLI_CASES.items():
        for case, (argv, tamper) in cases.items():
            d = kit._fresh(base, "cli")
            keep = ()
            if tamper is not None:
                first = SMALL_SWEEP
                if isinstance(tamper, tuple):  # ("sim", code): a simulate file
                    first, tamper = SMALL_SIM, tamper[1]
                kit.run(first, d, timeout)
                subprocess.run([sys.executable, "-c", TAMPER, str(d / "c.nc"), tamper],
                               env=_env(), capture_output=True, timeout=timeout)
                keep = ("c.nc",)
            before = sorted(os.listdir(d))
            rc, stdout, err, sec = kit.run(argv, d, timeout)
            # a tampered file is reported: a refusal (2) or rerun's "different" (1)
            expect = {1, 2} if klass == "tampered file" else {2}
            o = kit.judge(klass, case, rc, err, sec, expect, d, keep=keep)
            o.clean = (o.clean and sorted(os.listdir(d)) == before and
                       not stdout.startswith("identical"))
            if stdout.strip() and not o.message:
                o.message = stdout.strip().splitlines()[0][:160]
            out.append(o)
    return out


#: class -> the function that runs its cases
CLASSES = {
    "stopped process": stopped_cases, "SIGTERM with a stopped process": stopped_cases,
    "signal during a large write": write_cases, "killed during a write": killed_write_cases,
    "resource tracker killed": tracker_cases, "damaged map store": damaged_store_cases,
    **{k: api_cases for k in API_CASES}, **{k: cli_cases for k in CLI_CASES},
}


def shrink():
    """A smoke run: the first case of every table of this round, the large file small."""
    BIG[BIG.index("--periods") + 1] = "200"
    BIG[BIG.index("--dense") + 1] = "20"
    for table in (STOPPED, WRITES, KILLED):
        for key in list(table)[1:]:
            del table[key]
    for group in (API_CASES, CLI_CASES):
        for cases in group.values():
            for key in list(cases)[1:]:
                del cases[key]
