"""``python -m vibimpact``: the ``vibimpact`` command line."""
import sys

from vibimpact.cli import main

if __name__ == "__main__":
    sys.exit(main())
