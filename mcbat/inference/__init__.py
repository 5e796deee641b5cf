"""The spin of measured batted balls, inferred through the game model.

Statcast measures a ball in play's launch speed, launch angle and spray angle, and the
pitch; it publishes no batted-ball spin. ``infer_spin`` finds, for each ball, the
contact that reproduces the three measured numbers with the measured pitch through
mcbat's game model (``docs/batting.md``), and reports the spin that contact gives
(``docs/spin_inference.md``; equations in ``mcbat/core/contact_inference/README.md``).

The package: ``mcbat.inference.columns`` (the measured columns, read and checked),
``mcbat.inference.assumptions`` (what is assumed, and the iteration's settings),
``mcbat.inference.spin`` (the inference and its forward model),
``mcbat.inference.output`` (the Parquet file); their public names are importable from
here.

Example
-------
>>> import pandas as pd
>>> from mcbat.inference import infer_spin
>>> balls = pd.DataFrame({
...     "pitch_speed": [86.0], "vertical_approach_angle": [-5.0],
...     "horizontal_approach_angle": [0.0], "spin_rate": [2300.0], "spin_axis": [210.0],
...     "handedness": ["R"], "launch_speed": [102.0], "launch_angle": [27.0],
...     "spray_angle": [-10.0]})
>>> out = infer_spin(balls)
>>> out.loc[0, "inference_status"]
'converged'
"""

from mcbat.inference.assumptions import InferenceOptions, SpinAssumptions
from mcbat.inference.columns import INPUT_COLUMNS, OPTIONAL_COLUMNS, OUTPUT_UNITS, STATUS_NAMES
from mcbat.inference.output import CARRIED_COLUMNS, METADATA_KEY, write
from mcbat.inference.spin import infer_spin, predict_batted_balls

__all__ = ["CARRIED_COLUMNS", "INPUT_COLUMNS", "METADATA_KEY", "OPTIONAL_COLUMNS",
           "OUTPUT_UNITS", "STATUS_NAMES", "InferenceOptions", "SpinAssumptions", "infer_spin",
           "predict_batted_balls", "write"]
