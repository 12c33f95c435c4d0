"""The first calls of a fresh process may come from several threads at once.

The built-in models are registered lazily, on first use.  A thread that asked while
another was registering them saw an empty registry: ``vi.map2d(vi.presets.get(...))``
raised "p must be a vibimpact.System or the parameter set of a built-in model (), got
Params" in the calibration script, which runs its maps from a thread pool.  Each case
runs in a fresh interpreter (the registry fills once per process), with the threads
released together by a barrier.
"""
import subprocess
import sys
import textwrap

import pytest

#: the call each thread makes (``vi`` imported, nothing used yet); it must return the
#: same value in every thread
CALLS = {
    "registry": "(models.of_params(vi.Params()) is not None, tuple(models.names()))",
    "preset names": "tuple(vi.presets.names())",
    "system of a parameter set": "vi.System(vi.presets.get('fig8')).n_state",
    "simulate": "float(vi.simulate(vi.presets.get('fig8'), periods=3).strobe.sum())",
    "sweep": ("vi.sweep(vi.presets.get('fig8'), vi.grid('1.0:1.02:0.01'), "
              "analyses=('period',), execution=vi.Execution(workers=1))"
              ".regime.values.tobytes()"),
    "map2d": ("vi.map2d(vi.presets.get('fig8'), vi.grid('1.0:1.02:0.01'), "
              "{'kh': [50.0, 60.0]}, analyses=('period',), "
              "execution=vi.Execution(workers=1)).regime.values.tobytes()"),
}

SCRIPT = textwrap.dedent('''
    import threading
    import vibimpact as vi
    from vibimpact import models

    N = {n}
    barrier = threading.Barrier(N)
    out = [None] * N


    def ask(i):
        barrier.wait()
        try:
            out[i] = ("ok", {call})
        except Exception as exc:
            out[i] = ("error", f"{{type(exc).__name__}}: {{exc}}")


    threads = [threading.Thread(target=ask, args=(i,)) for i in range(N)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    print(repr(out))
''')


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
@pytest.mark.parametrize("call", CALLS)
def test_first_calls_from_several_threads_all_see_every_built_in_model(call):
    """Hypothesis: when the first calls of a process come from several threads at once,
    every thread succeeds and gets the same result (none sees a half-filled registry of
    built-in models)."""
    n = 8 if call in ("registry", "preset names", "system of a parameter set") else 2
    code = SCRIPT.format(n=n, call=CALLS[call])
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = eval(proc.stdout.strip().splitlines()[-1])  # noqa: S307 -- our own repr
    errors = [v for k, v in out if k != "ok"]
    assert errors == []
    assert len({v for _, v in out}) == 1
    if call == "registry":
        assert out[0][1][0] and "rotor" in out[0][1][1]
