"""``python -m mcbat.cli``: the ``mcbat`` command."""

import sys

from mcbat.cli.app import main

sys.exit(main())
