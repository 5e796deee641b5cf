"""What the commands share: library errors become flags through the error's data (its
field and its mentions of other parameters), never by rewriting its text."""

import pytest

from mcbat.cli.common import as_flags, flags, located
from mcbat.errors import InputError, Metavar


def test_the_field_and_each_mention_become_flags():
    err = InputError("workers", "give either {scheduler} (join a running cluster) or "
                     "{workers} (start a local one), not both", "study.toml",
                     mentions={"scheduler": Metavar("ADDRESS"), "workers": Metavar("N")})
    # In Python: call syntax.
    assert str(err) == ("study.toml: workers: give either scheduler=ADDRESS (join a running "
                        "cluster) or workers=N (start a local one), not both")
    cli = as_flags(err, ["workers", "scheduler"])
    assert str(cli) == ("study.toml: --workers: give either --scheduler ADDRESS (join a "
                        "running cluster) or --workers N (start a local one), not both")
    assert cli.field == "--workers" and cli.source == "study.toml"


@pytest.mark.parametrize("value, python, flag", [
    (True, "overwrite=True", "--overwrite"),          # a switch: the flag alone
    ("dask", "overwrite='dask'", "--overwrite dask"),  # a value: the flag and the value
    (12, "overwrite=12", "--overwrite 12"),
    (Metavar("DIR"), "overwrite=DIR", "--overwrite DIR"),
])
def test_a_mention_is_spelled_by_its_value(value, python, flag):
    err = InputError("out", "pass {overwrite} to replace it", mentions={"overwrite": value})
    assert err.message == f"pass {python} to replace it"
    assert as_flags(err, ["out", "overwrite"]).message == f"pass {flag} to replace it"


def test_only_the_parameters_given_become_flags():
    err = InputError("chunk_size", "choose {chunk_size} or more; {allow_partial} reads it",
                     mentions={"chunk_size": 40, "allow_partial": True})
    cli = as_flags(err, ["chunk_size"])  # no flag for allow_partial: call syntax stays
    assert str(cli) == "--chunk-size: choose --chunk-size 40 or more; allow_partial=True reads it"
    assert str(as_flags(err, [])) == str(err)


def test_text_that_only_looks_like_a_parameter_is_left_as_it_is():
    # A message that echoes the user's text (a file name, a value) is not rewritten: only
    # what the raise site declared as a mention is.
    err = InputError("out", "cannot write overwrite=True/{overwrite}/x: {samples}",
                     "samples=3", mentions={"overwrite": True})
    cli = as_flags(err, ["out", "overwrite", "samples"])
    assert str(cli) == "samples=3: --out: cannot write overwrite=True/--overwrite/x: {samples}"


def test_flags_context_and_located_keep_the_mentions():
    with pytest.raises(InputError) as info:
        with flags("out", "overwrite"):
            raise located(InputError("out", "holds a dataset; pass {overwrite}",
                                     mentions={"overwrite": True}), "here: case 2")
    assert str(info.value) == "here: case 2: --out: holds a dataset; pass --overwrite"
    inner = InputError("mu", "with {e} above 1", mentions={"e": 2}).within("case", "f.json")
    assert str(inner) == "f.json: case.mu: with e=2 above 1" and inner.mentions == {"e": 2}


def test_a_raise_site_of_the_library_names_its_mention():
    """A real raise site: the library's text names the parameter, the CLI's the flag."""
    from mcbat.runner.study_run import make_engine

    with pytest.raises(InputError) as info:
        make_engine("local", workers=2)
    assert str(info.value) == "workers: only with engine='dask'"
    assert str(as_flags(info.value, ["workers", "engine"])) == \
        "--workers: only with --engine dask"
