"""``python -m validation NAME|all|list [ARGS]``: one experiment, or every one in turn."""

import sys

import harness

if __name__ == "__main__":
    sys.exit(harness.main("validation", sys.argv[1:], doc=__doc__))
