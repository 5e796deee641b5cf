"""The ``mcbat`` parser, built from the ``COMMAND`` each command's module declares
(``mcbat.cli.common.Command``), and ``main``, which maps every error to its exit code
(``mcbat.cli``)."""

from __future__ import annotations

import argparse
import sys

from mcbat import __version__
from mcbat.cli import (
    calibrate,
    check,
    compare,
    compiling,
    fit,
    flight,
    impact,
    infer,
    replay,
    reproduce,
    run,
    statcast,
    synth,
    warmup,
)
from mcbat.cli.common import (
    EXIT_BROKEN_PIPE,
    EXIT_ENVIRONMENT,
    EXIT_INTERNAL,
    EXIT_USER,
    ArgumentParser,
    Command,
    UsageError,
    one_line,
    reading_progress,
)
from mcbat.errors import EnvironmentFailure, InputError

__all__ = ["COMMANDS", "build_parser", "main"]

#: Every command, in the order of `mcbat --help`: single impacts and flights, runs and
#: their datasets, the papers, the statistics, Statcast.
COMMANDS = (impact.COMMAND, flight.COMMAND, run.COMMAND, check.COMMAND, reproduce.COMMAND,
            calibrate.COMMAND, synth.COMMAND, fit.COMMAND, statcast.COMMAND, infer.COMMAND,
            replay.COMMAND, compare.COMMAND, warmup.COMMAND)


def build_parser() -> argparse.ArgumentParser:
    """The ``mcbat`` argument parser, one subcommand per job."""
    parser = ArgumentParser(
        prog="mcbat",
        description="Monte Carlo study of rigid ball-bat impacts with Coulomb friction.",
    )
    parser.add_argument("--debug", action="store_true",
                        help="show Python tracebacks for errors")
    parser.add_argument("--version", action="version", version=f"mcbat {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=ArgumentParser)
    for command in COMMANDS:
        _add_command(sub, command)
    return parser


def _add_command(sub, command: Command) -> None:
    """Add the parser of ``command`` to the subparsers ``sub``."""
    parser = sub.add_parser(command.name, help=command.help, description=command.description)
    for argument in command.arguments:
        argument.add_to(parser)
    parser.set_defaults(func=command.run, **command.defaults)


def main(argv=None) -> int:
    """Run the ``mcbat`` command with ``argv`` (default: ``sys.argv[1:]``); returns the exit
    code (0 ok, 2 user error or a dataset ``mcbat check`` finds not ok, 1 internal error,
    4 the environment failed mid-run, 130 interrupted, 141 broken pipe)."""
    parser = build_parser()
    debug = "--debug" in (sys.argv[1:] if argv is None else argv)
    try:
        args = parser.parse_args(argv)
        if not getattr(args, "func", None):
            parser.print_help(sys.stderr)
            return EXIT_USER
        with compiling.notice(args), reading_progress():  # (mcbat.cli.compiling, .common)
            return args.func(args)
    except UsageError as err:
        print(f"mcbat: error: {one_line(str(err))}", file=sys.stderr)
        return EXIT_USER
    except BrokenPipeError:
        # The reader went away (`mcbat impact ... | head -1`): stop quietly, as a command
        # killed by SIGPIPE would, and keep Python from complaining at exit.
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except KeyboardInterrupt:
        print("mcbat: interrupted; complete chunk files are kept, rerun the same command "
              "to resume", file=sys.stderr)
        return 130
    except Exception as err:  # noqa: BLE001 - the CLI boundary maps errors to exit codes
        if debug:
            import traceback

            traceback.print_exc()
        if isinstance(err, InputError):
            print(f"mcbat: error: {one_line(str(err))}", file=sys.stderr)
            return EXIT_USER
        if isinstance(err, EnvironmentFailure):
            print(f"mcbat: error: {one_line(str(err))}", file=sys.stderr)
            return EXIT_ENVIRONMENT
        print(f"mcbat: internal error: {type(err).__name__}: {one_line(str(err))}"
              + ("" if debug else " (run with --debug for a traceback)"), file=sys.stderr)
        return EXIT_INTERNAL
