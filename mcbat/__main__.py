"""``python -m mcbat``: the ``mcbat`` command."""

import sys

from mcbat.cli import main

sys.exit(main())
