"""One model integrated once: the :class:`~vibimpact.System` (model, parameters, solver
settings), the :class:`~vibimpact.Solver` that is the only caller of the kernel's entry
points, :func:`~vibimpact.simulate` and its result, the :class:`~vibimpact.Run`.

Public names are reached as ``vi.System``, ``vi.Solver``, ``vi.SolverSettings``,
``vi.simulate``, ``vi.Run``; the modules are ``run`` (the result), ``solver``, ``system``
and ``simulation``, in that order upwards.
"""
