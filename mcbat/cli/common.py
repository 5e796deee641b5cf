"""What every subcommand shares: exit codes, the parser class, a command declared as data
(``Command``, its arguments ``arg``, ``switch``, ``int_option`` and the arguments several
commands take, ``CASES``, ``EXPORT``, ``STRICT``, ``JSON``, ``QUIET``), flags for library
parameters, JSON input and output, reading a Statcast export, and output-path checks."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import sys
import unicodedata
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

from mcbat.errors import InputError, call_syntax

__all__ = ["CASES", "EXIT_BROKEN_PIPE", "EXIT_ENVIRONMENT", "EXIT_INTERNAL", "EXIT_OK",
           "EXIT_USER", "EXPORT", "FIGURE_FORMATS", "JSON", "QUIET", "STRICT", "TABLE_FORMATS",
           "Argument", "ArgumentParser", "Command", "Group", "UsageError", "arg", "as_flags",
           "check_figure", "check_input_file", "check_output", "each_case", "flag_of", "flags",
           "int_arg", "int_option", "json_value", "located", "note_left_out", "one_line",
           "print_json", "progress", "read_cases", "read_export", "switch", "writing"]

EXIT_OK = 0
EXIT_INTERNAL = 1
EXIT_USER = 2
EXIT_ENVIRONMENT = 4  # the environment failed mid-run (a lost Dask scheduler)
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a reader that went away

#: The file types a figure can be written as.
FIGURE_FORMATS = (".png", ".pdf", ".svg")
#: The file types a table of Statcast's balls can be written as (``--out``).
TABLE_FORMATS = (".parquet", ".pq", ".csv")


class UsageError(Exception):
    """A command-line usage error (bad flag or value): exit code 2."""


class ArgumentParser(argparse.ArgumentParser):
    """argparse that reports usage errors on one line with exit code 2."""

    def error(self, message):
        """Raise ``UsageError`` (argparse would print the usage and exit)."""
        raise UsageError(message)


@dataclass(frozen=True)
class Argument:
    """One argument of a command: the names and keywords of ``add_argument``."""

    names: tuple[str, ...]
    options: Mapping[str, object]

    def add_to(self, parser) -> None:
        """Add the argument to ``parser`` (a parser or a group of one)."""
        parser.add_argument(*self.names, **self.options)


@dataclass(frozen=True)
class Group:
    """Arguments shown under a title of their own in the help (``title``), or of which a
    command takes at most one (``exclusive``)."""

    arguments: tuple[Argument, ...]
    title: str | None = None
    exclusive: bool = False

    def add_to(self, parser) -> None:
        """Add the group and its arguments to ``parser``."""
        group = parser.add_mutually_exclusive_group() if self.exclusive else \
            parser.add_argument_group(self.title)
        for argument in self.arguments:
            argument.add_to(group)


@dataclass(frozen=True)
class Command:
    """A subcommand as data: its name, its line in ``mcbat --help`` (``help``), the text of
    its own ``--help`` (``description``), its arguments in the order of its usage line,
    the function that runs it (``run(args) -> exit code``) and the values of ``args`` that
    no argument sets (``defaults``). ``mcbat.cli.app`` builds the parser from it."""

    name: str
    help: str
    description: str
    arguments: tuple[Argument | Group, ...]
    run: Callable[[argparse.Namespace], int]
    defaults: Mapping[str, object] = field(default_factory=lambda: MappingProxyType({}))


def arg(*names: str, **options) -> Argument:
    """An argument: ``add_argument(*names, **options)``."""
    return Argument(names, MappingProxyType(options))


def switch(flag: str, help: str) -> Argument:
    """An on/off flag (``store_true``)."""
    return arg(flag, action="store_true", help=help)


def int_option(flag: str, **options) -> Argument:
    """An integer option whose error names ``flag`` (``int_arg``)."""
    return arg(flag, type=int_arg(flag), **options)


#: A file of JSON cases, or stdin (``read_cases``).
CASES = arg("file", nargs="?", default="-", metavar="FILE|-")
#: A Statcast export (``read_export``).
EXPORT = arg("file", metavar="FILE", help="the export (.csv, .csv.gz or .parquet)")
#: A Statcast export's pitch given twice refused (``read_export``).
STRICT = switch("--strict", "refuse a pitch given twice (the same game_pk, at_bat_number "
                "and pitch_number) instead of dropping the copy and counting it")
#: The result printed as one JSON object.
JSON = switch("--json", "print one JSON object")
#: No progress bar (``progress``), no compiling line (``mcbat.cli.compiling``).
QUIET = switch("--quiet", "no progress bar (nor the line that a first run is compiling the "
               "kernels)")


def progress(args) -> bool:
    """Whether the command shows its progress: not with ``--quiet``."""
    return not getattr(args, "quiet", False)


def one_line(text: str) -> str:
    r"""``text`` with every line break and control character escaped (``\x85``,
    ``\u2028``): an error message that echoes the user's input stays one line."""
    return "".join(
        ch if ch == " " or unicodedata.category(ch) not in ("Cc", "Cf", "Zl", "Zp")
        else ch.encode("unicode_escape").decode("ascii") for ch in text)


def int_arg(flag):
    """An argparse ``type`` reading an integer, naming ``flag`` when it is not one."""
    def parse(text):
        try:
            return int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{flag} must be an integer, got {text!r}") \
                from None
    return parse


def flag_of(parameter: str) -> str:
    """The flag of a library parameter: ``chunk_size`` -> ``--chunk-size``."""
    return "--" + parameter.replace("_", "-")


def as_flags(error: InputError, parameters) -> InputError:
    """``error`` with the library parameters in ``parameters`` written as their flags.

    Both the field the error is about (``error.field``) and the other parameters its
    message mentions (``error.mentions``) are data: a mention of ``overwrite=True``
    becomes ``--overwrite``, ``scheduler=ADDRESS`` becomes ``--scheduler ADDRESS``, and
    a parameter without a flag keeps its call syntax.
    """
    names = {name: flag_of(name) for name in parameters}

    def spell(name, value):
        if name not in names:
            return call_syntax(name, value)
        if value is True:
            return names[name]
        return f"{names[name]} {value}"

    return InputError(names.get(error.field, error.field), error.render_message(spell),
                      error.source)


@contextlib.contextmanager
def flags(*parameters):
    """Report the library's errors about these Python parameters as their flags
    (``as_flags``)."""
    try:
        yield
    except InputError as err:
        raise as_flags(err, parameters) from None


def located(error: InputError, source: str) -> InputError:
    """``error`` as found in ``source`` (``FILE: case 3``), its mentions kept."""
    return InputError(error.field, error.template, source, mentions=error.mentions)


def reject_constant(name):
    """``json.loads``'s ``parse_constant``: NaN and Infinity are not JSON (RFC 8259)."""
    raise ValueError(f"non-finite number {name} is not allowed")


def read_cases(path):
    """Parse ``path`` (or ``-`` for stdin) as one JSON case or a JSON array of cases;
    returns ``(source, cases, single)``."""
    source = "<stdin>" if path == "-" else path
    try:
        if path == "-":  # bytes: the encoding is checked below (a text stdin has none)
            stream = getattr(sys.stdin, "buffer", None)
            raw = stream.read() if stream is not None else sys.stdin.read().encode()
        else:
            with open(path, "rb") as handle:
                raw = handle.read()
        text = raw.decode("utf-8-sig")  # JSON is UTF-8 (RFC 8259); a BOM is tolerated
    except OSError as err:
        raise InputError(None, f"cannot read input: {err.strerror}", source) from None
    except UnicodeDecodeError as err:
        raise InputError(None, f"not UTF-8 text (byte {err.start}); JSON input must be UTF-8",
                         source) from None
    try:
        data = json.loads(text, parse_constant=reject_constant)
    except ValueError as err:
        raise InputError(None, f"not valid JSON: {err}", source) from None
    except RecursionError:
        raise InputError(None, "not valid JSON: nested too deeply", source) from None
    single = isinstance(data, dict)
    cases = [data] if single else data
    if not isinstance(cases, list) or not cases:
        raise InputError(None, "expected a JSON object (one case) or a non-empty array of "
                         "cases", source)
    return source, cases, single


def each_case(source, items, solve) -> list:
    """``solve(item)`` for each item of ``source``; a bad one's error names its case
    (``FILE: case 3``)."""
    results = []
    for index, item in enumerate(items):
        try:
            results.append(solve(item))
        except InputError as err:
            raise located(err, f"{source}: case {index}") from None
    return results


def json_value(value):
    """``value`` with non-finite floats (also inside lists and dicts) as None: strict JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple)):
        return [json_value(v) for v in value]
    if isinstance(value, dict):
        return {k: json_value(v) for k, v in value.items()}
    return value


def print_json(value) -> None:
    """Print ``value`` as strict JSON (non-finite numbers as null), indented."""
    json.dump(json_value(value), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


@contextlib.contextmanager
def reading_progress(stream=None):
    """On a terminal, a line on stderr that counts the rows of a Statcast export as they
    are read (a season's export takes tens of seconds), cleared when the command goes on;
    nothing when stderr is a file or a pipe, so that logs and tests see only the
    command's own lines."""
    stream = sys.stderr if stream is None else stream
    if not getattr(stream, "isatty", lambda: False)():
        yield
        return
    from mcbat.statcast import reader

    def report(rows, label, done):
        stream.write(f"\rmcbat: reading {label}: {rows:,} rows" + ("\n" if done else ""))
        stream.flush()

    with reader.progress(report):
        yield


def read_export(path, strict: bool, lines: bool = False):
    """The tidy table of the Statcast export ``path`` (``mcbat.statcast.read``), a pitch
    given twice refused with ``--strict``; with ``lines``, also the file line of each row
    (``read_with_lines``)."""
    from mcbat.statcast import reader

    with flags("strict"):
        if lines:
            return reader.read_with_lines(path, strict=strict)
        return reader.read(path, strict=strict)


@contextlib.contextmanager
def writing(path, flag="--out"):
    """An ``OSError`` of writing ``path`` (the value of ``flag``) reported as the user's
    error."""
    try:
        yield
    except OSError as err:
        raise InputError(flag, f"cannot write: {err.strerror or err}", path) from None


def check_output(path, flag, suffixes):
    """Refuse an output path that cannot be written, before any work is done (nothing to
    check when no path is given: ``None`` or empty)."""
    import os

    if not path:
        return
    target = Path(path)
    if target.suffix.lower() not in suffixes:
        raise InputError(flag, f"unsupported file type {target.suffix or '(none)'!r} for "
                         f"{path} (use one of: {', '.join(suffixes)})")
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(flag, f"cannot write {path}: no such directory {str(parent)!r}")
    if target.is_dir():
        raise InputError(flag, f"cannot write {path}: it is a directory")
    if not os.access(parent, os.W_OK):
        raise InputError(flag, f"cannot write {path}: the directory is not writable")


def check_figure(path, flag) -> None:
    """Refuse a figure path (if given) that cannot be written, before any work is done."""
    check_output(path, flag, FIGURE_FORMATS)


def note_left_out(source, left_out, what="row(s)") -> None:
    """Print on stderr, in one line, the rows a command left out of ``source``, by reason
    (``{"duplicate pitches": 3, ...}``; reasons counted 0 are not named). Commands call it
    once their work is done, so that a failing command's stderr is its one error line."""
    items = {k: int(v) for k, v in (left_out or {}).items() if v}
    if not items:
        return
    total = sum(items.values())
    reasons = ", ".join(f"{n:,} {reason}" for reason, n in items.items())
    print(one_line(f"mcbat: {source}: {total:,} {what} left out: {reasons}"),
          file=sys.stderr)


def check_input_file(path, flag=None):
    """Refuse, before any work, an input path that is not a regular file (a directory, a
    device, a FIFO: ``mcbat.statcast.files.check_regular_file``) or does not exist."""
    from mcbat.statcast.files import check_regular_file

    check_regular_file(path, str(path), flag)
