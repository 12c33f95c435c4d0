"""The parts the commands of the command line share: option types and parsers
(``args``), the one-line errors (``errors``), figure options (``figures``), input and
output files (``files``, ``inputs``), checkpoints (``checkpoints``), the standard streams
(``streams``), the steps of the census commands (``census_steps``), a recorded run's size
(``rerun_size``) and a run's start from a sweep file (``start``).  A command imports
these, never another command."""
