"""Studies shared by the tests of tests/study/: every distribution kind, a profiled bat."""

import copy
import math

from mcbat.study import Study
from tests.conftest import ROOT

STUDIES = ROOT / "studies"


# Every distribution kind, on inputs of every section (cylinder bat: any axial is fine).
ALL_KINDS = {
    "study": {"name": "all kinds", "samples": 200_000, "seed": 7},
    "ball": {"preset": "baseball"},
    "bat": {"preset": "cross_nathan_2006"},
    "contact": {
        "axial": {"dist": "uniform", "low": 0.05, "high": 0.20},
        "angle": {"dist": "lhs", "low": 0.0, "high": 1.0},
        "approach_azimuth": {"dist": "sobol", "low": 0.0, "high": 1.0},
    },
    "ball_velocity": {
        "x": {"dist": "normal", "mean": -20.0, "std": 2.0},
        "y": {"dist": "truncnormal", "mean": 0.0, "std": 1.0, "low": -0.5, "high": 2.0},
        "z": {"dist": "truncnormal", "mean": 0.0, "std": 1.0, "low": 3.0, "high": 5.0},
    },
    "ball_spin": {
        "x": {"dist": "choice", "values": [-1.0, 0.0, 2.0], "weights": [1, 2, 5]},
        "y": {"dist": "grid", "start": 0.0, "stop": 3.0, "num": 4},
        "z": {"dist": "grid", "start": 10.0, "stop": 30.0, "num": 3},
    },
    "bat_velocity": {
        "x": {"dist": "mixture", "weights": [0.25, 0.75],
              "components": [5.0, {"dist": "uniform", "low": 0.0, "high": 1.0}]},
        "y": {"dist": "sobol", "low": 0.0, "high": 1.0},
        "z": 0.5,
    },
    "bat_spin": {"y": {"dist": "lhs", "low": 0.0, "high": 1.0}},
    "friction": {"mu": {"dist": "uniform", "low": 0.0, "high": 1.0}},
    "restitution": {"loss_fraction": {"dist": "uniform", "low": 0.0, "high": 1.0}},
}

# A profiled bat, contact by distance from the barrel end and impact parameter.
PROFILED = {
    "study": {"name": "profiled", "samples": 1000},
    "ball": {"preset": "baseball"},
    "bat": {"preset": "r161"},
    "contact": {
        "from_barrel_end": {"dist": "uniform", "low": 5, "high": 50, "unit": "cm"},
        "impact_parameter": {"dist": "uniform", "low": -1.5, "high": 1.5, "unit": "in"},
        "approach_azimuth": {"dist": "uniform", "low": -30, "high": 30, "unit": "deg"},
    },
    "ball_velocity": {"x": {"dist": "uniform", "low": -40, "high": -10}},
    "friction": {"mu": 0.5},
}


def study(data=ALL_KINDS, **changes):
    data = copy.deepcopy(data)
    for dotted, value in changes.items():
        section, key = dotted.split("__")
        data.setdefault(section, {})[key] = value
    return Study.from_dict(data, source="test.toml")


def close(value, expected, sigma, n, k=5.0):
    assert abs(value - expected) < k * sigma / math.sqrt(n), (value, expected)
