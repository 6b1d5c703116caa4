"""``python -m hosedrogue``: the command line (:func:`hosedrogue.cli.main`)."""

import sys

from .cli import main

if __name__ == "__main__":  # importing this module (documentation tools do) must not run the CLI
    sys.exit(main())
