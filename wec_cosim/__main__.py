"""``python -m wec_cosim``: the ``wec-cosim`` command line."""

import sys

from .cli import main

sys.exit(main())
