"""``python -m benchmarks NAME|all|list [ARGS]``; ``python -m benchmarks render`` writes every
table of measured figures in the docs (speed, long runs, accuracy, fuzzing, the Dask engine)
from a results directory."""

import sys

import harness

if __name__ == "__main__":
    if sys.argv[1:2] == ["render"]:
        from benchmarks import render

        sys.exit(render.main(sys.argv[2:]))
    sys.exit(harness.main("benchmarks", sys.argv[1:], doc=__doc__))
