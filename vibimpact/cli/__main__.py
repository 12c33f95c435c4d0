"""``python -m vibimpact.cli``: the command line (:func:`vibimpact.cli.main`)."""
import sys

from vibimpact.cli import main

sys.exit(main())
