"""Fuzzing the inputs: study TOML files and impact JSON, valid and broken.

Every example runs the real command line in-process (``mcbat.cli.main``) and must exit 0
or 2, never 1; an error is one line without a traceback; a refused run leaves no directory,
a finished one a complete dataset. ``MCBAT_FUZZ_EXAMPLES`` sets the number of examples per
test (default 150; the long run reported in docs/errors.md used 10,000).
"""

import contextlib
import io
import json
import math
import os
import tempfile
import tomllib
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mcbat
from mcbat.cli import main

ROOT = Path(__file__).resolve().parents[1]
STUDIES = [ROOT / "studies" / name for name in ("example.toml", "game_fastball.toml")]
CASES = [json.loads((ROOT / "examples" / name).read_text())
         for name in ("cabo2012_sec5.json", "game_fastball.json")]
EXAMPLES = int(os.environ.get("MCBAT_FUZZ_EXAMPLES", "150"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=False,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

# ------------------------------------------------------------------ values and mutations

UNITS = ["m", "cm", "in", "ft", "mph", "m/s", "km/h", "rpm", "rad/s", "rps", "deg", "rad",
         "g", "kg", "oz", "K", "degC", "degF", "Pa", "inHg", "furlong", ""]
KINDS = ["uniform", "normal", "truncnormal", "choice", "mixture", "grid", "sobol", "lhs",
         "gaussian"]
numbers = st.one_of(st.integers(-10**6, 10**6), st.integers(-10**400, 10**400),
                    st.floats(allow_nan=True, allow_infinity=True),
                    st.sampled_from([0, -1, 1e-300, 1e300, 5e-324, 2**63, 2**64]))
scalars = st.one_of(numbers, st.booleans(), st.text(max_size=8),
                    st.sampled_from(["", "\x00", "../x", "\ufeff", "é"]))
distributions = st.fixed_dictionaries(
    {"dist": st.sampled_from(KINDS)},
    optional={"low": numbers, "high": numbers, "mean": numbers, "std": numbers,
              "start": numbers, "stop": numbers, "num": numbers,
              "values": st.lists(numbers, max_size=4), "weights": st.lists(numbers, max_size=4),
              "unit": st.sampled_from(UNITS), "components": st.lists(st.just({}), max_size=2),
              "value": numbers})
values = st.one_of(scalars, distributions, st.lists(scalars, max_size=4),
                   st.dictionaries(st.text(max_size=6), scalars, max_size=3))


def paths(tree, prefix=()):
    """Every key path of a nested dict/list."""
    out = []
    items = tree.items() if isinstance(tree, dict) else enumerate(tree) \
        if isinstance(tree, list) else ()
    for key, value in items:
        out.append(prefix + (key,))
        out.extend(paths(value, prefix + (key,)))
    return out


def mutate(tree, data, n):
    """Apply ``n`` random edits (replace, delete, add a key) to a copy of ``tree``."""
    tree = json.loads(json.dumps(tree))
    for _ in range(n):
        candidates = paths(tree)
        if not candidates:
            break
        path = data.draw(st.sampled_from(candidates))
        parent = tree
        for key in path[:-1]:
            parent = parent[key]
        op = data.draw(st.sampled_from(["replace", "replace", "delete", "add"]))
        if op == "replace":
            parent[path[-1]] = data.draw(values)
        elif op == "delete":
            del parent[path[-1]]
        elif isinstance(parent, dict):
            parent[data.draw(st.text(min_size=1, max_size=8))] = data.draw(values)
    return tree


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") \
            if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + "}"


def to_toml(study: dict) -> str:
    lines = [f"{json.dumps(k)} = {toml_value(v)}" for k, v in study.items()
             if not isinstance(v, dict)]
    for section, table in study.items():
        if isinstance(table, dict):
            lines.append(f"[{json.dumps(section)}]")
            lines += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ the contract


def run_main(*argv, stdin=None):
    out, err = io.StringIO(), io.StringIO()
    old_stdin = os.sys.stdin
    if stdin is not None:
        os.sys.stdin = io.StringIO(stdin)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            debug = ["--debug"] if os.environ.get("MCBAT_FUZZ_DEBUG") else []
            code = main(debug + [str(a) for a in argv])
    finally:
        os.sys.stdin = old_stdin
    return code, out.getvalue(), err.getvalue()


def assert_contract(code, err, what):
    assert code in (0, 2), f"exit {code} for {what}: {err}"
    if os.environ.get("MCBAT_FUZZ_DEBUG"):  # --debug prints tracebacks on purpose
        return
    assert "Traceback" not in err, err
    if code == 2:
        assert len(err.strip().splitlines()) == 1 and err.startswith("mcbat: error: "), err


@FUZZ
@given(data=st.data())
def test_study_files(data):
    source = data.draw(st.sampled_from(STUDIES))
    study = tomllib.loads(source.read_text())
    text = to_toml(mutate(study, data, data.draw(st.integers(0, 3))))
    if data.draw(st.integers(0, 9)) == 0:  # now and then, break the text itself
        at = data.draw(st.integers(0, len(text)))
        text = text[:at] + data.draw(st.text(max_size=4)) + text[at:]
    with tempfile.TemporaryDirectory() as tmp:
        path, out = Path(tmp) / "s.toml", Path(tmp) / "ds"
        path.write_bytes(text.encode("utf-8", "surrogatepass"))
        code, _, err = run_main("run", path, "--out", out, "--samples", 40, "--quiet")
        assert_contract(code, err, text)
        if code == 2:
            assert not out.exists(), f"a refused run left {sorted(out.iterdir())}"
        else:
            assert mcbat.check(out).ok


@FUZZ
@given(data=st.data())
def test_impact_cases(data):
    case = data.draw(st.sampled_from(CASES))
    mutated = mutate(case, data, data.draw(st.integers(0, 3)))
    payload = [mutated] if data.draw(st.booleans()) else mutated
    text = json.dumps(payload, allow_nan=True)
    code, out, err = run_main("impact", "-", stdin=text)
    assert_contract(code, err, text)
    if code == 0:
        json.loads(out, parse_constant=lambda name: (_ for _ in ()).throw(ValueError(name)))
