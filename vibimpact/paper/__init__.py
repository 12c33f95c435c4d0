"""What belongs to the paper of this project (Půst & Kozánek), not to the library core.

:mod:`vibimpact.paper.claims` holds the paper's claims as data and their automated check
on sweeps (the calibration's objective and the paper report's verdicts,
``analyses/paper/``).
"""
