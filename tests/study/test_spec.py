"""Reading study files (mcbat.study.spec.load_study): every kind of bad file is refused
naming the file, the key and the value; TOML errors name the line; the shipped studies
load and solve."""

import tomllib

import numpy as np
import pytest

from mcbat.core import status
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.errors import InputError
from mcbat.study import Study, load_study
from tests.study.cases import STUDIES

BASE_TOML = """\
[study]
name = "bad"
samples = 10

[ball]
preset = "baseball"

[bat]
preset = "cross_nathan_2006"

[contact]
from_barrel_end = { dist = "uniform", low = 14, high = 16, unit = "cm" }
impact_parameter = { dist = "uniform", low = -1.5, high = 1.5, unit = "in" }

[ball_velocity]
x = -4.0

[friction]
mu = 0.5

[restitution]
e = 0.6
"""


BAD = [
    # (replace, with, key named in the error, text in the message)
    ('samples = 10', 'samples = 10\nsampels = 3', "study.sampels", "unknown key"),
    ('x = -4.0', 'x = -4.0\nw = 1', "ball_velocity.w", "unknown key"),
    ('x = -4.0', 'x = { dist = "uniform", low = -5, high = -3, spread = 1 }',
     "ball_velocity.x.spread", "unknown key"),
    ('e = 0.6', 'e = 0.6\n[solvers]\nsteps = 3', "solvers",
     "unknown key"),
    ('mu = 0.5', 'mu = { dist = "gaussian", mean = 0.5, std = 0.1 }', "friction.mu.dist",
     "'gaussian'"),
    ('low = 14, high = 16', 'low = 16, high = 14', "contact.from_barrel_end.low",
     "low = 16 >= high = 14"),
    ('mu = 0.5', 'mu = { dist = "normal", mean = 0.5, std = -0.1 }', "friction.mu.std",
     "-0.1"),
    ('mu = 0.5', 'mu = { dist = "uniform", low = -0.2, high = 0.5 }', "friction.mu.low",
     "-0.2"),
    ('mu = 0.5', 'mu = -0.5', "friction.mu", "-0.5"),
    ('mu = 0.5', 'mu = { dist = "normal", mean = 0.5, std = 0.1 }', "friction.mu",
     "truncnormal with low >= 0"),
    ('e = 0.6', 'e = 1.2', "restitution.e", "1.2"),
    ('e = 0.6', 'e = 0.6\ne_x = -0.1', "restitution.e_x", "-0.1"),
    ('e = 0.6', 'e = 0.6\ne_x = { dist = "uniform", low = 0.5, high = 1.5 }',
     "restitution.e_x.high", "1.5"),
    ('e = 0.6', 'e = 0.6\nloss_fraction = 0.3\ne_x = 0.1', "restitution.loss_fraction",
     "not both"),
    ('e = 0.6', 'e = { dist = "choice", values = [0.5, -0.1] }', "restitution.e.values[1]",
     "-0.1"),
    ('e = 0.6', 'loss_fraction = { dist = "uniform", low = 0.5, high = 1.5 }',
     "restitution.loss_fraction.high", "1.5"),
    ('x = -4.0', 'x = { value = -4.0, unit = "rpm" }', "ball_velocity.x.unit", "'rpm'"),
    ('unit = "in"', 'unit = "parsec"', "contact.impact_parameter.unit", "'parsec'"),
    ('low = -1.5, high = 1.5, unit = "in"', 'low = -1.5, high = 3.0, unit = "in"',
     "contact.impact_parameter.high", "3.0 in"),
    ('impact_parameter = { dist = "uniform", low = -1.5, high = 1.5, unit = "in" }', '',
     "contact", "'angle' or 'impact_parameter'"),
    ('mu = 0.5', '', "friction.mu", "missing required key"),
    ('x = -4.0', 'x = "fast"', "ball_velocity.x", "'fast'"),
    ('mu = 0.5', 'mu = { dist = "choice", values = [0.1, 0.2], weights = [1, 2, 3] }',
     "friction.mu.weights", "one weight per value"),
    ('mu = 0.5', 'mu = { dist = "choice", values = [0.1, 0.2], weights = [1, -2] }',
     "friction.mu.weights[1]", "-2"),
    ('x = -4.0', 'x = { dist = "grid", start = 0, stop = 1, num = 0 }', "ball_velocity.x.num",
     "got 0"),
    ('low = 14, high = 16', 'low = 14, high = 90', "contact.from_barrel_end.high", "90 cm"),
    ('preset = "baseball"', 'mass = { dist = "uniform", low = 0.1, high = 0.2 }\nradius = 0.036',
     "ball.mass", "fixed number"),
    ('preset = "baseball"', 'mass = -0.145\nradius = 0.036', "ball.mass", "-0.145"),
    ('preset = "cross_nathan_2006"', 'preset = "louisville"', "bat.preset", "'louisville'"),
    ('samples = 10', 'samples = 10.5', "study.samples", "10.5"),
    ('e = 0.6', 'e = 0.6\n[solver]\ntolerance = 0', "solver.tolerance", "0"),
]


@pytest.mark.parametrize("old, new, key, text", BAD, ids=[b[2] for b in BAD])
def test_bad_study_files(tmp_path, old, new, key, text):
    assert old in BASE_TOML
    path = tmp_path / "bad_study.toml"
    path.write_text(BASE_TOML.replace(old, new, 1))
    with pytest.raises(InputError) as info:
        load_study(path)
    message = str(info.value)
    assert message.startswith(f"{path}: {key}: "), message
    assert text in message, message
    assert info.value.field == key and info.value.source == str(path)


def test_base_toml_is_valid(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text(BASE_TOML)
    s = load_study(path)
    assert s.source_text == BASE_TOML and s.name == "bad" and s.seed == 0
    assert s.chunk_size is None and s.grid_size is None


def test_toml_syntax_error_names_file_and_line(tmp_path):
    path = tmp_path / "syntax.toml"
    path.write_text(BASE_TOML.replace("mu = 0.5", "mu = = 0.5"))
    line = BASE_TOML.splitlines().index("mu = 0.5") + 1
    with pytest.raises(InputError) as info:
        load_study(path)
    assert str(info.value).startswith(f"{path}: line {line}, column ")
    assert "invalid TOML" in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="cannot read the study file"):
        load_study(tmp_path / "nope.toml")


def test_example_study_loads_and_solves():
    s = load_study(STUDIES / "example.toml")
    assert s.name == "example" and s.samples == 20_000 and s.seed == 2012
    cols = s.sample(0, 2000)
    assert np.all(cols["axial"] > 0.105 - 1e-12) and np.all(cols["axial"] < 0.125)
    assert set(np.unique(cols["ball_wz_in"])) == {79.0, 0.0, -72.0}
    inputs = np.stack([cols[f] for f in INPUT_FIELDS])
    out, st, es = allocate_outputs(inputs.shape[1])
    solve_batch(inputs, s.solver["steps"], s.solver["tolerance"], s.solver["max_steps"],
                out, st, es)
    assert np.all(st == status.OK)


def test_throughput_study_covers_every_end_state():
    s = load_study(STUDIES / "throughput.toml")
    assert s.samples == 2_000_000
    cols = s.sample(0, 200_000)
    assert np.any(np.abs(cols["bat_slope"]) > 0.05)  # tapered contacts
    for name in ("ball_wx_in", "ball_wy_in", "ball_wz_in", "bat_vx_in", "bat_wy_in"):
        assert np.any(cols[name] != 0.0), name
    assert cols["e"].min() < 0.01 and cols["e"].max() > 0.99
    inputs = np.stack([cols[f] for f in INPUT_FIELDS])
    out, st, es = allocate_outputs(inputs.shape[1])
    solve_batch(inputs, s.solver["steps"], s.solver["tolerance"], s.solver["max_steps"],
                out, st, es)
    ok = st == status.OK
    assert ok.mean() > 0.99
    stick = out[OUTPUT_FIELDS.index("stick_impulse")]
    stuck = ok & (es == status.STUCK)
    sliding = ok & (es == status.SLIDING) & np.isnan(stick)
    reslip = ok & (es == status.SLIDING) & np.isfinite(stick)
    assert stuck.sum() > 10_000 and sliding.sum() > 10_000
    assert reslip.sum() >= 50  # ~0.1 % of the mix


def test_shipped_studies_parse_as_plain_toml():
    for name in ("example.toml", "throughput.toml"):
        with open(STUDIES / name, "rb") as f:
            data = tomllib.load(f)
        assert Study.from_dict(data).config_hash() == load_study(STUDIES / name).config_hash()
