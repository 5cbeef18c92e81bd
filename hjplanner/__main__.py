"""``python -m hjplanner ...``: the same as the ``hjplanner`` console script."""

import sys

from .cli import main

sys.exit(main())
