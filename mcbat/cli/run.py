"""``mcbat run``: a study into a Parquet dataset."""

from __future__ import annotations

from pathlib import Path

from mcbat.cli.common import EXIT_OK, flags, int_arg
from mcbat.errors import InputError

__all__ = ["RUN_PARAMETERS", "add_parser", "cmd_run"]

#: The parameters of :func:`mcbat.runner.run_study` that are flags of ``mcbat run``.
RUN_PARAMETERS = ("out", "samples", "seed", "threads", "chunk_size", "engine", "scheduler",
                  "workers", "overwrite", "summary_only", "columns", "tolerance")


def add_parser(sub) -> None:
    """Add ``mcbat run`` to the subparsers ``sub``."""
    run = sub.add_parser(
        "run", help="run a Monte Carlo study (TOML) into a Parquet dataset directory",
        description="Sample the study's inputs, solve every impact with the parallel kernel "
                    "and write a Parquet dataset (one file per chunk). An interrupted run "
                    "resumes: complete chunk files are kept.")
    run.add_argument("study", metavar="STUDY.toml")
    run.add_argument("--out", metavar="DIR", help="dataset directory, or a URL that pyarrow "
                     "or fsspec can write (default: results/<study name>)")
    run.add_argument("--samples", type=int_arg("--samples"), metavar="N",
                     help="number of impacts (default: the study's)")
    run.add_argument("--seed", type=int_arg("--seed"), metavar="S",
                     help="random seed (default: the study's)")
    run.add_argument("--threads", type=int_arg("--threads"), metavar="K",
                     help="kernel threads (default: all cores); with --engine dask, numba "
                          "threads per worker (default: cores / workers, or 1 with "
                          "--scheduler)")
    run.add_argument("--chunk-size", type=int_arg("--chunk-size"), metavar="C",
                     help="rows per Parquet file (default: the study's, or 262,144 = 4 x 65,536)")
    run.add_argument("--engine", choices=("local", "dask"), default="local",
                     help="local: numba threads in this process (default); dask: one task "
                          "per chunk on a Dask cluster (docs/cluster.md)")
    run.add_argument("--scheduler", metavar="ADDRESS",
                     help="--engine dask: join the running Dask scheduler at ADDRESS "
                          "(tcp://host:8786); --out must be storage every worker shares")
    run.add_argument("--workers", type=int_arg("--workers"), metavar="N",
                     help="--engine dask: start a local cluster of N worker processes "
                          "(default: one per core)")
    run.add_argument("--columns", metavar="A,B,...",
                     help="store only these columns (and sample_id); overrides the study's "
                          "[output] columns")
    run.add_argument("--summary-only", action="store_true",
                     help="compute the study's [summary] (binned statistics, "
                          "_summary.parquet) without storing the rows")
    run.add_argument("--overwrite", action="store_true",
                     help="replace an existing dataset written with another config")
    run.add_argument("--tolerance", type=float, default=None, metavar="T",
                     help="the kernel's tolerance: the local error allowed per slip step, "
                          "relative to the impact's scales, 0 < T < 1 (default: the "
                          "study's [solver] tolerance, else 5e-9); part of the dataset's "
                          "config")
    run.add_argument("--quiet", action="store_true",
                     help="no progress bar (nor the line that a first run is compiling "
                          "the kernels)")
    run.set_defaults(func=cmd_run)


def cmd_run(args) -> int:
    """Run the study ``args.study`` into a dataset and print the run's report."""
    from mcbat.runner import run_study
    from mcbat.study import load_study

    study = load_study(args.study)  # validates everything before anything is written
    if args.columns is not None:
        with flags("columns"):
            study = study.with_overrides(columns=args.columns)
    if args.out is not None and not args.out.strip():
        raise InputError("--out", "must not be empty (give a directory or a URL; without "
                         "--out the dataset goes to results/<study name>)")
    out = args.out if args.out is not None else str(Path("results") / study.name)
    if out[:9].lower() == "memory://":
        raise InputError("--out", "memory:// keeps files in this process's memory: they would "
                         "vanish when the command ends (the Python API can use it); give a "
                         "directory or a persistent URL", out)
    with flags(*RUN_PARAMETERS):
        summary = run_study(study, out, samples=args.samples, seed=args.seed,
                            threads=args.threads, chunk_size=args.chunk_size,
                            overwrite=args.overwrite, progress=not args.quiet,
                            engine=args.engine, scheduler=args.scheduler,
                            workers=args.workers, summary_only=args.summary_only,
                            tolerance=args.tolerance)
    for line in summary.lines():
        print(line)
    return EXIT_OK
