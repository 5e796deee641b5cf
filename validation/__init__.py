"""Validation experiments of mcbat (coverage, injection and recovery, fuzzing, accuracy
against the reference solvers, the generated tables of the docs):
``python -m validation NAME|all|list [ARGS]`` (benchmarks/README.md)."""
