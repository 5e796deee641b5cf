"""The ``mcbat`` command: one module per subcommand (its ``cmd_*`` function and its
``COMMAND``, the subcommand declared as data: ``mcbat.cli.common.Command``), what they share
in ``mcbat.cli.common``, the parser built from the declarations and ``main`` in
``mcbat.cli.app``.

Exit codes: 0 success, 2 user error (one line on stderr, no traceback; also ``mcbat
check`` on a dataset incomplete or inconsistent), 1 internal error, 4 the environment
failed mid-run, 130 interrupted, 141 the reader of stdout went away (``| head``).
``--debug`` shows the traceback of any error.
"""

from mcbat.cli.app import build_parser, main

__all__ = ["build_parser", "main"]
