"""Tools for checking the library, not for using it.

:mod:`vibimpact.testing.reference` is an independent SciPy integration of a built-in model:
the cross-check of the kernel in the tests and the SciPy baseline of the benchmarks
(``analyses/performance/``).
"""
