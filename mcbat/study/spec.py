"""Study files: a TOML file -> a validated study (``Study`` in the bat frame,
``mcbat.study.game.GameStudy`` in the field frame).

The file format (sections, keys, units, distributions, validation and how samples are
drawn) is described in ``docs/study-format.md``. This module reads the file and picks the
kind of study; it also gathers the names other code imports from it: the bat-frame study
(``mcbat.study.impact``), the sections every study shares
(``mcbat.study.sections``), the drawing scheme (``mcbat.study.drawing``) and the
input checks (``mcbat.checks``).
"""

from __future__ import annotations

import re
import tomllib

from mcbat.checks import check_string, check_tolerance
from mcbat.errors import InputError
from mcbat.study.drawing import LHS_BLOCK, LHS_SPAWN_KEY, SOBOL_BITS, SOBOL_SPAWN_KEY
from mcbat.study.game import GameStudy
from mcbat.study.impact import COLUMNS, FORMAT_VERSION, MAX_DESCRIPTION, MAX_SAMPLES, Study
from mcbat.study.impact_inputs import NOISE_OUTPUTS
from mcbat.study.sections import check_solver, check_study_name, fill_bodies, parse_ball, parse_bat

__all__ = ["COLUMNS", "FORMAT_VERSION", "GameStudy", "LHS_BLOCK", "LHS_SPAWN_KEY",
           "MAX_DESCRIPTION", "MAX_SAMPLES", "MAX_STUDY_BYTES", "NOISE_OUTPUTS", "SOBOL_BITS",
           "SOBOL_SPAWN_KEY", "Study", "check_solver", "check_string", "check_study_name",
           "check_tolerance", "fill_bodies", "load_study", "parse_ball", "parse_bat"]

#: Longest study file (bytes): its text is stored in every chunk file's Parquet footer,
#: which a reader refuses beyond ~100 MB.
MAX_STUDY_BYTES = 1 << 20


def load_study(path) -> Study:
    """Read and validate a TOML study file.

    Raises
    ------
    InputError
        Naming the file: unreadable, invalid TOML (with line and column) or an invalid
        study (with the dotted key and the offending value).
    """
    source = str(path)
    try:
        with open(path, "rb") as handle:  # the text goes into every chunk file's footer
            raw = handle.read(MAX_STUDY_BYTES + 1)
        if len(raw) > MAX_STUDY_BYTES:
            raise InputError(None, f"a study file is at most {MAX_STUDY_BYTES:,} bytes (its "
                             "text is stored in every chunk file's footer)", source=source)
        text = raw.decode("utf-8-sig")  # a leading BOM is allowed
    except UnicodeDecodeError as exc:
        raise InputError(None, f"not UTF-8 text (byte {exc.start}); TOML files are UTF-8: "
                         "save it as UTF-8", source=source) from None
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise InputError(None, f"cannot read the study file: {reason}", source=source) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise _toml_error(exc, text, source) from None
    except RecursionError:
        raise InputError(None, "invalid TOML: nested too deeply", source=source) from None
    return Study.from_dict(data, source=source, text=text)


def _toml_error(exc, text, source):
    message = str(exc)
    m = re.match(r"^(.*) \(at line (\d+), column (\d+)\)$", message, re.S)
    if m:
        where = f"line {m.group(2)}, column {m.group(3)}"
        message = m.group(1)
    else:
        m = re.match(r"^(.*) \(at end of document\)$", message, re.S)
        lines = max(1, len(text.splitlines()))
        where = f"line {lines} (end of document)"
        message = m.group(1) if m else message
    return InputError(None, f"{where}: invalid TOML: {message}", source=source)
