"""``mcbat check``: a dataset checked against its manifest."""

from __future__ import annotations

from mcbat.cli.common import EXIT_OK, Command, arg, switch
from mcbat.errors import InputError

__all__ = ["COMMAND", "cmd_check"]


def cmd_check(args) -> int:
    """Check the dataset ``args.directory``; a dataset not ok is exit 2."""
    from mcbat.dataset.check import check_dataset

    result = check_dataset(args.directory, checksums=not args.quick)
    for line in result.lines():
        print(line)
    # A damaged, incomplete or unverifiable dataset is bad input to every command that
    # reads it: exit 2, the report above on stdout, its first problem as the error line.
    problem = result.first_problem()
    if problem is not None:
        raise InputError(None, problem, str(result.directory))
    return EXIT_OK


COMMAND = Command(
    "check", help="check a dataset directory against its manifest (exit 2 if not ok)",
    description="Verify that every chunk the manifest expects is present, recorded and "
                "unchanged (size, Parquet footer, sample_id range, and the CRC-32 of "
                "every byte), and that no other chunk file is there. Exit 0 when the "
                "dataset is complete and consistent; 2 when it is not, or its manifest "
                "records no checksums to verify it by (the report on "
                "stdout, each problem on one line; on stderr one line naming the "
                "first problem's file and what is wrong) or DIR is not a dataset.",
    arguments=(
        arg("directory", metavar="DIR", help="dataset directory or URL"),
        switch("--quick", "sizes and footers only (what mcbat.load checks), no checksums"),
    ),
    run=cmd_check)
