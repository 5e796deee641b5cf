"""Study files: TOML → a validated :class:`Study` → deterministic solver input columns.

A study is a Monte Carlo scan: every numeric input of the impact solver is either fixed
or drawn from a distribution, and :meth:`Study.sample` turns sample indices into the
float64 input columns of :func:`mcbat.core.batch.solve_batch`.

File format
-----------
::

    [study]
    name = "example"          # required, non-empty string
    description = "..."       # optional string
    samples = 20000           # required: default number of samples (the CLI may override), int >= 1
    seed = 2012               # optional (default 0): default seed (the CLI may override), int >= 0
    chunk_size = 100000       # optional: default rows per output file, int >= 1

    [ball]                    # either  preset = "baseball"
    mass = 0.145              # or fixed numbers: mass, radius, inertia_factor (default 0.4)
    radius = { value = 3.6, unit = "cm" }

    [bat]                     # either  preset = "cross_nathan_2006" | "r161"
    mass = 0.989              # or fixed numbers: mass, radius, transverse_inertia,
    radius = 0.03335          # axial_inertia (a cylinder at the contact), and optionally
    transverse_inertia = 0.046  # length and cm_from_barrel_end (needed for
    axial_inertia = 4.39e-4   # contact.from_barrel_end; both bound the contact position)

    [contact]                 # exactly one of axial | from_barrel_end (length),
    from_barrel_end = { dist = "uniform", low = 14, high = 16, unit = "cm" }
    impact_parameter = { dist = "uniform", low = -1.5, high = 1.5, unit = "in" }
                              # exactly one of angle (angle) | impact_parameter (length);
                              # optional approach_azimuth (angle, default 0)

    [ball_velocity]           # required; x, y, z each a number or a distribution (speed),
    x = { value = -4.0 }      # missing components are 0
    [ball_spin]               # optional; x, y, z (spin), default 0
    z = { dist = "choice", values = [79, 0, -72] }
    [bat_velocity]            # optional; x, y, z (speed), default 0
    [bat_spin]                # optional; x, y, z (spin), default 0

    [friction]                # required
    mu = { dist = "truncnormal", mean = 0.5, std = 0.05, low = 0.0, high = 1.0 }

    [restitution]             # optional: exactly one of e (Stronge's energetic e*, in
    loss_fraction = 0.6183822 # [0, 1]) | loss_fraction (the paper's e^2, in [0, 1],
                              # e* = sqrt(1 - e^2)); without them e* = 1. Optionally
    e_x = 0.16                # e_x, the tangential restitution of Cross & Nathan (2006),
                              # in [0, 1]; default 0 (the rigid model)

    [solver]                  # optional: steps (int >= 1), tolerance (0 < tol < 1),
    tolerance = 1e-9          # max_steps (int >= 1); defaults of mcbat.core.cabo2012.contact

Quantities: axial, from_barrel_end, impact_parameter and the bat/ball radii are lengths;
angle and approach_azimuth angles; velocities speeds; spins spins; mu, e, loss_fraction,
e_x and inertia_factor dimensionless. Without a ``unit`` a value is SI (m, m/s, rad/s, rad,
kg, kg m^2). The lab frame is that of ``docs/physics.md``: the bat CM at the origin, ``z``
along the bat towards the barrel end; ``axial`` is measured from the CM, ``from_barrel_end``
from the barrel end (``axial = cm_from_barrel_end - from_barrel_end``). The impact parameter is
the offset of a ball line perpendicular to the bat, arriving from azimuth
``approach_azimuth``: ``b = (r + R/sqrt(1 + r'^2)) sin(angle - approach_azimuth)``.

Distributions (:mod:`mcbat.study.distributions`): a number, ``{ value, unit }``,
``uniform(low, high)``, ``normal(mean, std)``, ``truncnormal(mean, std, low, high)``,
``choice(values, weights?)``, ``mixture(components, weights?)``, ``grid(start, stop,
num)``, ``sobol(low, high)``, ``lhs(low, high)``; each with an optional ``unit``.

Validation happens completely in :meth:`Study.from_dict`, before anything is sampled:
unknown or missing keys, wrong types, bad parameters (``std <= 0``, ``low >= high``,
weights), units of the wrong quantity, and values or supports outside the physical range
(masses, radii, inertias > 0; ``mu >= 0``; ``e``, ``loss_fraction``, ``e_x`` in [0, 1]; the contact
on the bat; ``|b|`` within the reach ``r(z) + R/sqrt(1 + r'^2)`` over every axial position
the contact can take). Errors are :class:`mcbat.errors.InputError` with the dotted key,
e.g. ``studies/x.toml: contact.impact_parameter.high: ...``.

Determinism
-----------
Sample ``i`` depends only on the study, the seed and ``i``, never on how rows are grouped
into chunks: ``sample(0, n)`` equals any concatenation of ``sample(a, b)`` pieces.

* Random inputs (uniform, normal, truncnormal, choice, mixture) are drawn by a jitted,
  parallel, counter-based sampler (:mod:`mcbat.core.sampling`): the values of input
  ``name`` in sample ``i`` come from one Philox4x32-10 block, key ``seed``, counter ``(i,
  CRC-32 of name)``, so they depend on nothing else (not on the other inputs, the chunk,
  the thread count or the engine). Normal values use the inverse CDF (AS241). (Format
  version 2; version 1 drew numpy PCG64 streams per block of 65,536 samples.)
* Grid inputs form an outer product (the first declared varies slowest); sample ``i``
  takes grid point ``i mod G``, ``G`` the product of the ``num`` s.
* Sobol inputs share one scrambled :class:`scipy.stats.qmc.Sobol` engine (one dimension
  each, in declaration order) seeded with ``SeedSequence(seed, spawn_key=(2**31,))``;
  sample ``i`` is its point ``i`` (``fast_forward(start)``).
* LHS inputs share one :class:`scipy.stats.qmc.LatinHypercube` design per block of
  :data:`LHS_BLOCK` = 65,536 samples, seeded with ``SeedSequence(seed, spawn_key=(2**31 +
  1, k))``: the stratification holds within each full block (a last, partial block is a
  subset).

Adding, removing or reordering random inputs leaves the draws of the others unchanged;
for grid, Sobol and LHS inputs the order matters (the canonical :meth:`Study.config` and
its hash record it).
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
import re
import tomllib
import unicodedata
import warnings
from dataclasses import replace
from types import MappingProxyType

import numpy as np

from mcbat.bodies import BALL_PRESETS, BAT_PRESETS, Ball, Bat, bat_preset
from mcbat.core.batch import INPUT_FIELDS
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.core.geometry import angles_from_impact_parameters, impact_parameters_from_angles
from mcbat.errors import InputError
from mcbat.study import units as u
from mcbat.study.distributions import (
    Choice,
    Normal,
    check_keys,
    check_range,
    integer,
    number,
    parse,
)
from mcbat.study.output import OutputSpec, parse_columns, parse_output, parse_summary
from mcbat.study.random_program import NOISE, compile_program, draw

__all__ = ["COLUMNS", "FORMAT_VERSION", "LHS_SPAWN_KEY", "NOISE_OUTPUTS",
           "LHS_BLOCK", "SOBOL_BITS", "SOBOL_SPAWN_KEY", "Study", "check_solver",
           "check_string", "check_tolerance", "fill_bodies", "load_study", "parse_ball",
           "parse_bat"]

#: Samples per LHS design (the stratification holds within each full block).
LHS_BLOCK = 65536
#: ``spawn_key`` of the Sobol engine's SeedSequence.
SOBOL_SPAWN_KEY = 2**31
#: First element of the ``spawn_key`` of the per-block LHS designs.
LHS_SPAWN_KEY = 2**31 + 1
# Measurement noise (section [noise]) of output <name> is drawn like a random input
# named "noise.<name>", in the counter domain of noise (never an input's stream).
# Outputs that can get simulated measurement noise, and their quantities. The noisy copy
# goes to a separate column "<name>_measured"; the model value is never altered.
NOISE_OUTPUTS = {"exit_speed": "speed", "scattering_angle": "angle",
                 "spin_axial": "spin", "spin": "spin"}
#: Bits of the Sobol engine: at most ``2**SOBOL_BITS`` samples.
SOBOL_BITS = 32
#: Most samples of one run: 10^12 (11 days at 10^6 impacts/s). Beyond it a sample count is
#: a typo, and sample indices would near the range the seeding scheme is laid out for.
MAX_SAMPLES = 10**12
#: Longest ``study.description`` (characters) and study file (bytes): both are stored in
#: every chunk file's Parquet footer, which a reader refuses beyond ~100 MB.
MAX_DESCRIPTION = 10_000
MAX_STUDY_BYTES = 1 << 20
#: Version of the study format and sampling scheme, recorded in :meth:`Study.config`.
FORMAT_VERSION = 2

#: Columns returned by :meth:`Study.sample`: the solver inputs, then the impact parameter.
COLUMNS = INPUT_FIELDS + ("impact_parameter",)

_REQUIRED_SECTIONS = ("study", "ball", "bat", "contact", "ball_velocity", "friction")
_OPTIONAL_SECTIONS = ("ball_spin", "bat_velocity", "bat_spin", "restitution", "solver",
                      "noise", "output", "summary")
_VECTORS = {
    "ball_velocity": ("ball_v", u.SPEED),
    "ball_spin": ("ball_w", u.SPIN),
    "bat_velocity": ("bat_v", u.SPEED),
    "bat_spin": ("bat_w", u.SPIN),
}
_CONTACT_QUANTITIES = {"axial": u.LENGTH, "from_barrel_end": u.LENGTH, "angle": u.ANGLE,
                       "impact_parameter": u.LENGTH, "approach_azimuth": u.ANGLE}
_BALL_KEYS = {"mass": u.MASS, "radius": u.LENGTH, "inertia_factor": u.DIMENSIONLESS}
_BAT_KEYS = {"mass": u.MASS, "radius": u.LENGTH, "transverse_inertia": u.INERTIA,
             "axial_inertia": u.INERTIA, "length": u.LENGTH, "cm_from_barrel_end": u.LENGTH,
             "cm_from_knob": u.LENGTH}
_BAT_REQUIRED = ("mass", "radius", "transverse_inertia", "axial_inertia")


# ---------------------------------------------------------------- parsing helpers


def check_string(value, field):
    """The string ``value`` of key ``field`` (InputError naming it otherwise)."""
    if not isinstance(value, str):
        raise InputError(field, f"must be a string, got {value!r}")
    return value


def _fixed(spec, field, quantity, *, positive=True):
    """A fixed number (plain or ``{value, unit}``) in SI, ``> 0`` if ``positive``."""
    dist = parse(spec, field, quantity, kinds=("fixed",))
    if positive:
        check_range(dist, minimum=0.0, strict_minimum=True, what=field.rsplit(".", 1)[-1])
    return dist.value


def parse_ball(table):
    """The ``[ball]`` section: a :class:`~mcbat.bodies.ball.Ball` (preset or explicit keys)."""
    check_keys(table, "ball", (), ("preset",) + tuple(_BALL_KEYS))
    if "preset" in table:
        for key in table:
            if key != "preset":
                raise InputError(f"ball.{key}", "cannot be combined with 'preset' (give "
                                                "either a preset or the ball's properties)")
        name = check_string(table["preset"], "ball.preset")
        if name not in BALL_PRESETS:
            raise InputError("ball.preset", f"unknown ball preset {name!r} "
                                            f"(expected one of: {', '.join(BALL_PRESETS)})")
        return BALL_PRESETS[name]
    check_keys(table, "ball", ("mass", "radius"), ("inertia_factor",))
    values = {k: _fixed(v, f"ball.{k}", _BALL_KEYS[k]) for k, v in table.items()}
    return Ball(**values)


def parse_bat(table):
    """The ``[bat]`` section: a :class:`~mcbat.bodies.bat.Bat` (preset or explicit keys)."""
    check_keys(table, "bat", (), ("preset",) + tuple(_BAT_KEYS))
    if "preset" in table:
        for key in table:
            if key != "preset":
                raise InputError(f"bat.{key}", "cannot be combined with 'preset' (give "
                                               "either a preset or the bat's properties)")
        name = check_string(table["preset"], "bat.preset")
        if name not in BAT_PRESETS:
            raise InputError("bat.preset", f"unknown bat preset {name!r} "
                                           f"(expected one of: {', '.join(BAT_PRESETS)})")
        return bat_preset(name)
    check_keys(table, "bat", _BAT_REQUIRED, ("length", "cm_from_barrel_end", "cm_from_knob"))
    values = {}
    for key, spec in table.items():
        values[key] = _fixed(spec, f"bat.{key}", _BAT_KEYS[key],
                             positive=key not in ("cm_from_barrel_end", "cm_from_knob"))
    if "cm_from_knob" in values:  # the CM from the knob (game bats): from the barrel end
        if "cm_from_barrel_end" in values or "length" not in values:
            raise InputError("bat.cm_from_knob", "needs bat.length, and not "
                             "bat.cm_from_barrel_end too")
        values["cm_from_barrel_end"] = values["length"] - values.pop("cm_from_knob")
    cm = values.get("cm_from_barrel_end")
    if cm is not None:
        length = values.get("length")
        if cm < 0.0 or (length is not None and cm > length):
            limit = "" if length is None else f" and <= the length {length:.6g} m"
            raise InputError("bat.cm_from_barrel_end",
                             f"must be >= 0{limit}, got {cm:.6g} m")
    return Bat(**values)


def _parse_noise(table):
    """The ``[noise]`` section: standard deviations in SI (the scattering angle's in
    degrees, like its column)."""
    noise = check_keys(table, "noise", (), tuple(NOISE_OUTPUTS))
    out = MappingProxyType({
        name: _fixed(spec, f"noise.{name}", NOISE_OUTPUTS[name], positive=False)
        * (180.0 / math.pi if name == "scattering_angle" else 1.0)
        for name, spec in noise.items()})
    for name, std in out.items():
        if not std >= 0.0:
            raise InputError(f"noise.{name}", f"must be a standard deviation >= 0, "
                             f"got {std!r}")
    return out


def _parse_inputs(data) -> dict:
    """The numeric inputs, in declaration order (sections, then keys, as in the file)."""
    inputs = {}
    for section, table in data.items():
        if section == "contact":
            check_keys(table, "contact", (), tuple(_CONTACT_QUANTITIES))
            for key, spec in table.items():
                inputs[f"contact.{key}"] = parse(spec, f"contact.{key}",
                                                 _CONTACT_QUANTITIES[key])
        elif section in _VECTORS:
            check_keys(table, section, (), ("x", "y", "z"))
            for key, spec in table.items():
                inputs[f"{section}.{key}"] = parse(spec, f"{section}.{key}",
                                                   _VECTORS[section][1])
        elif section == "friction":
            check_keys(table, "friction", ("mu",))
            inputs["friction.mu"] = parse(table["mu"], "friction.mu", u.DIMENSIONLESS)
        elif section == "restitution":
            check_keys(table, "restitution", (), ("e", "loss_fraction", "e_x"))
            if "e_x" not in table or "e" in table or "loss_fraction" in table:
                _exactly_one(table, "restitution", "e", "loss_fraction")
            for key, spec in table.items():
                inputs[f"restitution.{key}"] = parse(spec, f"restitution.{key}",
                                                     u.DIMENSIONLESS)
    return inputs


def check_solver(table):
    """The ``[solver]`` section, validated, with the kernel's defaults filled in."""
    check_keys(table, "solver", (), ("steps", "tolerance", "max_steps"))
    # Upper bounds keep one impact's work bounded (a step budget of 10^6 is ~0.1 s).
    steps = integer(table.get("steps", DEFAULT_STEPS), "solver.steps", minimum=1,
                    maximum=10**4)
    max_steps = integer(table.get("max_steps", DEFAULT_MAX_STEPS), "solver.max_steps",
                        minimum=1, maximum=10**6)
    tolerance = check_tolerance(table.get("tolerance", DEFAULT_TOLERANCE), "solver.tolerance")
    return {"steps": steps, "tolerance": tolerance, "max_steps": max_steps}


def check_tolerance(value, field):
    """The kernel's ``tolerance`` (the local error allowed per slip step, relative to the
    impact's scales; :data:`~mcbat.core.cabo2012.contact.DEFAULT_TOLERANCE`) as a finite float
    with ``0 < tolerance < 1``, or :class:`InputError` naming ``field``."""
    tolerance = number(value, field)
    if not 0.0 < tolerance < 1.0:
        raise InputError(field, f"must be > 0 and < 1, got {tolerance!r}")
    return tolerance


def _exactly_one(table, section, a, b):
    if a in table and b in table:
        raise InputError(f"{section}.{b}", f"give exactly one of '{a}' or '{b}', not both")
    if a not in table and b not in table:
        raise InputError(section, f"missing key: give exactly one of '{a}' or '{b}'")
    return a if a in table else b


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


# ---------------------------------------------------------------- the study


class Study:
    """A validated study: bodies, input distributions, sampling defaults, solver settings.

    Build it with :func:`load_study` (a TOML file) or :meth:`from_dict` (parsed TOML).
    Everything is validated on construction; :meth:`sample` then never raises for input
    reasons.

    Attributes
    ----------
    name, description : str
    samples : int
        Default number of samples.
    seed : int
        Default seed.
    chunk_size : int or None
        Default rows per output file.
    solver : dict
        ``{"steps", "tolerance", "max_steps"}`` for :func:`mcbat.core.batch.solve_batch`.
    ball : mcbat.bodies.Ball
    bat : mcbat.bodies.Bat
    inputs : mapping
        Declared numeric inputs, dotted key → :class:`~mcbat.study.distributions.Dist`,
        in declaration order.
    grid_size : int or None
        ``G``, the number of points of the grid inputs' outer product (None: no grid).
    source : str or None
        The file the study came from.
    source_text : str or None
        The raw TOML text.
    """

    #: ``"impact"`` (the bat frame) or ``"game"`` (:class:`mcbat.study.game.GameStudy`).
    kind = "impact"

    def __init__(self, data, source=None, text=None):
        self.source = None if source is None else str(source)
        self.source_text = text
        try:
            self._parse(data)
        except InputError as err:
            raise err.within(source=self.source) from None
        self._data = copy.deepcopy(data)

    # ------------------------------------------------------------ construction

    @classmethod
    def from_dict(cls, data, source=None, text=None) -> Study:
        """Validate a parsed study (the dict ``tomllib`` returns).

        Parameters
        ----------
        data : dict
            The study, as in the file format (module docstring).
        source : str, optional
            Where it came from (for error messages).
        text : str, optional
            The raw TOML text, kept as :attr:`source_text`.

        Returns
        -------
        Study
            A :class:`mcbat.study.game.GameStudy` when ``data`` has a ``[pitch]``,
            ``[swing]`` or ``[pitches]`` section.

        Raises
        ------
        InputError
            Naming ``source``, the dotted key and the offending value.
        """
        if cls is Study and isinstance(data, dict) and any(
                k in data for k in ("pitch", "swing", "pitches")):
            from mcbat.study.game import GameStudy

            return GameStudy(data, source=source, text=text)
        return cls(data, source=source, text=text)

    def _parse(self, data):
        check_keys(data, "", (), _REQUIRED_SECTIONS + _OPTIONAL_SECTIONS)
        for section in _REQUIRED_SECTIONS:
            if section not in data:
                raise InputError(section, "missing required section "
                                          f"[{section}]")
        for section in data:
            if not isinstance(data[section], dict):
                raise InputError(section, f"must be a table ([{section}]), "
                                          f"got {data[section]!r}")

        self._parse_study_section(data["study"])
        self.ball = parse_ball(data["ball"])
        self.bat = parse_bat(data["bat"])
        self._solver = check_solver(data.get("solver", {}))
        self.noise = _parse_noise(data.get("noise", {}))
        self._parse_output(data)
        inputs = _parse_inputs(data)
        contact = data["contact"]
        self._axial_key = _exactly_one(contact, "contact", "axial", "from_barrel_end")
        self._angle_key = _exactly_one(contact, "contact", "angle", "impact_parameter")
        self.inputs = MappingProxyType(inputs)
        self._check_ranges()
        self._plan()

    def _parse_output(self, data):
        """``[output]`` and ``[summary]`` (:mod:`mcbat.study.output`; the runner checks
        the column names against the dataset's schema)."""
        self.output = parse_output(data.get("output", {}))
        self.output_field = "output.columns"
        self._summary_table = data.get("summary")
        self.summary = (None if self._summary_table is None
                        else parse_summary(self._summary_table))

    def summary_spec(self, column_units):
        """The ``[summary]`` section checked against the dataset's columns
        (``{name: stored unit}``), bounds in the stored units (None without one)."""
        if self._summary_table is None:
            return None
        return parse_summary(self._summary_table, column_units)

    def _parse_study_section(self, table):
        """The ``[study]`` section: name, description, samples, seed, chunk size."""
        study = check_keys(table, "study", ("name", "samples"),
                           ("description", "seed", "chunk_size"))
        self.name = check_string(study["name"], "study.name")
        check_study_name(self.name)
        self.description = check_string(study.get("description", ""), "study.description")
        if len(self.description) > MAX_DESCRIPTION:
            raise InputError("study.description", f"at most {MAX_DESCRIPTION:,} characters, "
                             f"got {len(self.description):,} (it is stored in every chunk "
                             "file's footer)")
        self.samples = integer(study["samples"], "study.samples", minimum=1,
                               maximum=MAX_SAMPLES)
        self.seed = integer(study.get("seed", 0), "study.seed", minimum=0,
                            maximum=2**63 - 1)
        self.chunk_size = (None if "chunk_size" not in study
                           else integer(study["chunk_size"], "study.chunk_size", minimum=1,
                                        maximum=MAX_SAMPLES))

    def _check_overlap(self, axial_low, axial_high):
        """No contact the study can draw puts the ball into a tapered bat elsewhere: every
        value of a ``choice``, else the whole range."""
        key = f"contact.{self._axial_key}"
        dist = self.inputs[key]
        if isinstance(dist, Choice):
            values = [p.si for p in dist.points()]
            if self._axial_key != "axial":
                values = [self.bat.axial_from_barrel_end(v) for v in values]
            spans = [(v, v) for v in values]
        elif math.isfinite(axial_low) and math.isfinite(axial_high):
            spans = [(axial_low, axial_high)]
        else:
            spans = []
        for low, high in spans:
            self.bat.check_no_overlap(self.ball.radius, low, high, name=key)

    def _check_ranges(self):
        inputs = self.inputs
        check_range(inputs["friction.mu"], minimum=0.0, what="mu")
        for key in ("restitution.e", "restitution.loss_fraction", "restitution.e_x"):
            if key in inputs:
                check_range(inputs[key], minimum=0.0, maximum=1.0, what=key.split(".")[1])

        bounds = self.bat.axial_bounds()
        if self._axial_key == "axial":
            axial = inputs["contact.axial"]
            if bounds is not None:  # (1e-12 m of slack for rounding in unit conversions)
                check_range(axial, minimum=bounds[0] - 1e-12, maximum=bounds[1] + 1e-12,
                            what="the contact's axial position (m from the bat CM)")
            axial_low, axial_high = axial.support()
        else:
            distance = inputs["contact.from_barrel_end"]
            if self.bat.cm_from_barrel_end is None:
                raise InputError("contact.from_barrel_end",
                                 "needs bat.cm_from_barrel_end (or a bat preset) to place "
                                 "the contact; give contact.axial instead")
            check_range(distance, minimum=0.0,
                        maximum=None if self.bat.length is None else self.bat.length + 1e-12,
                        what="the contact's distance from the barrel end")
            d_low, d_high = distance.support()
            axial_low = self.bat.axial_from_barrel_end(d_high)
            axial_high = self.bat.axial_from_barrel_end(d_low)

        self._check_overlap(axial_low, axial_high)
        if self._angle_key == "impact_parameter":
            if not (math.isfinite(axial_low) and math.isfinite(axial_high)):
                axial_low = axial_high = 0.0  # unbounded: only for a cylinder (checked)
            reach = self.bat.min_reach(self.ball.radius, axial_low, axial_high)
            where = ("" if self.bat.profile is None else
                     f" for contacts between {axial_low:.6g} and {axial_high:.6g} m from "
                     "the bat CM")
            check_range(inputs["contact.impact_parameter"], minimum=-reach, maximum=reach,
                        what=f"the impact parameter (within the reach r + R of bat and "
                             f"ball{where}; beyond it the ball misses)")
        # With an angle, approach_azimuth only sets the impact-parameter column: any value.

    def _plan(self):
        """Group the inputs by how they are sampled."""
        families = {"fixed": [], "random": [], "grid": [], "sobol": [], "lhs": []}
        for name, dist in self.inputs.items():
            families[dist.family].append((name, dist))
        self._families = families
        grids = families["grid"]
        self.grid_size = int(np.prod([d.num for _, d in grids])) if grids else None

    @property
    def solver(self) -> dict:
        """``{"steps", "tolerance", "max_steps"}`` (a copy) for the kernel."""
        return dict(self._solver)

    # ------------------------------------------------------------ overrides and config

    def with_overrides(self, *, samples=None, seed=None, chunk_size=None,
                       columns=None, tolerance=None) -> Study:
        """A copy with the run's sample count, seed, chunk size, stored columns
        (``[output] columns``) or solver tolerance (``[solver] tolerance``) replacing the
        defaults (``None`` keeps the study's), validated like the file's values."""
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        if columns is not None:
            new.output = replace(self.output, columns=parse_columns(columns, "columns"))
            new.output_field = "columns"
        if tolerance is not None:
            new._solver = {**self._solver, "tolerance": check_tolerance(tolerance, "tolerance")}
        if samples is not None:
            new.samples = integer(samples, "samples", minimum=1, maximum=MAX_SAMPLES)
        if seed is not None:
            new.seed = integer(seed, "seed", minimum=0, maximum=2**63 - 1)
        if chunk_size is not None:
            new.chunk_size = integer(chunk_size, "chunk_size", minimum=1,
                                     maximum=MAX_SAMPLES)
        new.check_sample_count(new.samples, "samples")
        return new

    def check_sample_count(self, samples: int, field: str) -> None:
        """Refuse ``samples`` beyond what this study's samplers can draw (before anything
        runs): :data:`MAX_SAMPLES`, and ``2**SOBOL_BITS`` with a ``sobol`` input."""
        if samples > MAX_SAMPLES:
            raise InputError(field, f"must be <= {MAX_SAMPLES:,}, got {samples:,}")
        if self._families["sobol"] and samples > 2**SOBOL_BITS:
            sobol = ", ".join(name for name, _ in self._families["sobol"])
            raise InputError(field, f"a study with sobol inputs ({sobol}) draws at most "
                             f"2**{SOBOL_BITS} = {2**SOBOL_BITS:,} samples, got {samples:,}")

    def definition(self) -> dict:
        """The study as plain data (the dict ``tomllib`` returns): ``from_dict`` of it
        rebuilds an equal study, with the same :meth:`config`.

        It is what a remote worker needs to rebuild the study (``mcbat.engines.dask``):
        a deep copy of the validated input with the current sample count, seed and chunk
        size (:meth:`with_overrides`) written into its ``[study]`` table, and an overridden
        solver tolerance into its ``[solver]`` table.
        """
        data = copy.deepcopy(self._data)
        if self.output != OutputSpec():  # (a --columns override travels with the study)
            data["output"] = {k: v for k, v in self.output.config().items() if v is not None}
        if self._solver != check_solver(data.get("solver", {})):  # (so does a --tolerance)
            data["solver"] = dict(self._solver)
        table = data["study"]
        table["samples"], table["seed"] = self.samples, self.seed
        if self.chunk_size is None:
            table.pop("chunk_size", None)
        else:
            table["chunk_size"] = self.chunk_size
        return data

    def config(self) -> dict:
        """Canonical, JSON-serialisable description of the validated study, units resolved
        to SI (what the samples depend on, plus name, description and defaults)."""
        restitution = next((k.split(".")[1] for k in ("restitution.e",
                                                      "restitution.loss_fraction")
                            if k in self.inputs), None)
        return {
            "format": "mcbat.study",
            "version": FORMAT_VERSION,
            "sampling": {
                "random": "Philox4x32-10, key = seed, counter = (sample index, "
                          "CRC-32 of the input's name); inverse-CDF normals (AS241)",
                "sobol": f"scipy.stats.qmc.Sobol(scramble=True, bits={SOBOL_BITS}), "
                         f"SeedSequence(seed, spawn_key=({SOBOL_SPAWN_KEY},))",
                "lhs": f"scipy.stats.qmc.LatinHypercube per block of {LHS_BLOCK}, "
                       f"SeedSequence(seed, spawn_key=({LHS_SPAWN_KEY}, block))",
            },
            "study": {"name": self.name, "description": self.description,
                      "samples": self.samples, "seed": self.seed,
                      "chunk_size": self.chunk_size},
            "ball": self.ball.config(),
            "bat": self.bat.config(),
            "contact": {"position": self._axial_key, "azimuth": self._angle_key},
            "restitution": restitution,
            "inputs": [{"name": name, "quantity": dist.quantity,
                        "unit": u.SI_UNITS[dist.quantity], **dist.config()}
                       for name, dist in self.inputs.items()],
            "solver": self.solver,
            "noise": dict(self.noise),
            "output": self.output.config(),
            "summary": None if self.summary is None else self.summary.config(),
        }

    def config_json(self) -> str:
        """:meth:`config` as canonical JSON (sorted keys, no whitespace)."""
        return json.dumps(self.config(), sort_keys=True, separators=(",", ":"),
                          allow_nan=False)

    def config_hash(self) -> str:
        """SHA-256 (hex) of :meth:`config_json`."""
        return hashlib.sha256(self.config_json().encode("utf-8")).hexdigest()

    def __repr__(self):
        return (f"Study(name={self.name!r}, samples={self.samples}, seed={self.seed}, "
                f"inputs={len(self.inputs)}, source={self.source!r})")

    # ------------------------------------------------------------ sampling

    def _draw(self, start, stop, seed, table, rows):
        """Write the values of every declared input for samples ``[start, stop)`` into
        row ``rows[name]`` of ``table`` (float64, ``stop - start`` columns)."""
        n = stop - start
        fam = self._families
        for name, dist in fam["fixed"]:
            table[rows[name]] = dist.value

        if fam["random"]:
            program = compile_program(fam["random"], rows)
            draw(program, seed, start, table)

        if fam["grid"]:
            g = np.arange(start, stop, dtype=np.int64) % self.grid_size
            stride = self.grid_size
            for name, dist in fam["grid"]:
                stride //= dist.num
                np.take(dist.values(), (g // stride) % dist.num, out=table[rows[name]])

        if fam["sobol"]:
            if stop > 2**SOBOL_BITS:
                raise ValueError(f"sobol inputs support at most 2**{SOBOL_BITS} samples, "
                                 f"asked for sample {stop - 1}")
            rng = np.random.default_rng(np.random.SeedSequence(seed,
                                                               spawn_key=(SOBOL_SPAWN_KEY,)))
            engine = _qmc("Sobol", len(fam["sobol"]), rng, scramble=True, bits=SOBOL_BITS)
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message=".*balance properties.*")
                if start:  # (scipy's fast_forward(0) on a fresh engine fails)
                    engine.fast_forward(start)
                points = engine.random(n)
            for j, (name, dist) in enumerate(fam["sobol"]):
                table[rows[name]] = dist.from_unit(points[:, j])

        if fam["lhs"]:
            B = LHS_BLOCK
            for k in range(start // B, (stop - 1) // B + 1):
                rng = np.random.default_rng(np.random.SeedSequence(
                    seed, spawn_key=(LHS_SPAWN_KEY, k)))
                design = _qmc("LatinHypercube", len(fam["lhs"]), rng).random(B)
                lo, hi = max(start, k * B), min(stop, (k + 1) * B)
                for j, (name, dist) in enumerate(fam["lhs"]):
                    table[rows[name], lo - start:hi - start] = dist.from_unit(
                        design[lo - k * B:hi - k * B, j])

    def measurement_noise(self, start, stop, seed=None) -> dict[str, np.ndarray]:
        """Gaussian measurement errors for the ``[noise]`` outputs of samples
        ``start .. stop - 1`` (same units as the columns; deterministic in the index:
        Philox stream ``noise.<name>``, see :mod:`mcbat.core.sampling`)."""
        seed = self.seed if seed is None else seed
        names = list(self.noise)
        table = np.empty((len(names), max(stop - start, 0)))
        if names and stop > start:
            draws = [(f"noise.{name}", Normal(f"noise.{name}", "noise", None, mean=0.0,
                                              std=self.noise[name]))
                     for name in names]
            rows = {f"noise.{name}": i for i, name in enumerate(names)}
            draw(compile_program(draws, rows, NOISE), seed, start, table)
        return {name: table[i] for i, name in enumerate(names)}

    def sample(self, start=0, stop=None, seed=None) -> dict[str, np.ndarray]:
        """Solver inputs of samples ``start .. stop - 1``.

        Parameters
        ----------
        start, stop : int
            Sample indices, ``0 <= start <= stop`` (``stop`` defaults to :attr:`samples`;
            indices past it are defined too).
        seed : int, optional
            Default :attr:`seed`.

        Returns
        -------
        dict
            float64 arrays of length ``stop - start`` (SI units) for every name in
            :data:`COLUMNS`: :data:`mcbat.core.batch.INPUT_FIELDS` in order, then
            ``"impact_parameter"`` (m, for the study's approach azimuth). They are the
            rows of one C-contiguous ``(len(COLUMNS), n)`` array, so
            ``np.stack([cols[f] for f in INPUT_FIELDS])`` is a plain copy.
        """
        start, stop, seed = _sample_range(start, self.samples if stop is None else stop,
                                          self.seed if seed is None else seed)
        n = stop - start
        # Inputs are drawn straight into their columns (from_barrel_end into "axial" and
        # loss_fraction into "e", converted in place below); an input with no column of
        # its own (approach_azimuth) into an extra row after them.
        extra = [name for name in self.inputs if name not in _TARGETS]
        table = np.empty((len(COLUMNS) + len(extra), n))
        cols = {name: table[i] for i, name in enumerate(COLUMNS)}
        if n == 0:
            return cols
        rows = {name: (_COLUMN_ROWS[_TARGETS[name]] if name in _TARGETS
                       else len(COLUMNS) + extra.index(name)) for name in self.inputs}
        self._draw(start, stop, seed, table, rows)
        _fill_defaults(cols, rows)

        ball, bat = self.ball, self.bat
        fill_bodies(cols, ball, bat)

        axial = cols["axial"]
        if self._axial_key == "from_barrel_end":
            np.subtract(bat.cm_from_barrel_end, axial, out=axial)
        if bat.profile is None:
            cols["bat_radius"][:] = bat.radius
            cols["bat_slope"][:] = 0.0
        else:
            np.clip(axial, *bat.axial_bounds(), out=axial)  # rounding in unit conversions
            bat.profile.surfaces(axial, out=(cols["bat_radius"], cols["bat_slope"]))

        azimuth = (table[rows["contact.approach_azimuth"]]
                   if "contact.approach_azimuth" in rows else np.zeros(n))
        if self._angle_key == "angle":
            impact_parameters_from_angles(cols["angle"], cols["ball_radius"],
                                          cols["bat_radius"], cols["bat_slope"], azimuth,
                                          cols["impact_parameter"])
        else:
            angles_from_impact_parameters(cols["impact_parameter"], cols["ball_radius"],
                                          cols["bat_radius"], cols["bat_slope"], azimuth,
                                          cols["angle"])
        return cols


#: Row of each column in the table :meth:`Study.sample` fills.
_COLUMN_ROWS = {name: i for i, name in enumerate(COLUMNS)}
# Input → the column it is drawn into.
_TARGETS = {
    "contact.axial": "axial", "contact.from_barrel_end": "axial",
    "contact.angle": "angle", "contact.impact_parameter": "impact_parameter",
    "friction.mu": "mu", "restitution.e": "e", "restitution.loss_fraction": "e",
    "restitution.e_x": "e_x",
    **{f"{section}.{axis}": f"{prefix}{axis}_in"
       for section, (prefix, _) in _VECTORS.items() for axis in "xyz"},
}


def check_study_name(name: str) -> None:
    """A study name is the default output directory's name (``results/<name>``): one
    plain directory name, never a path that leads elsewhere."""
    # Every control, format and line/paragraph separator character: C0 and C1 controls
    # (U+0085 ends a line in some tools), U+2028/2029, and the bidirectional overrides
    # (U+202E shows the name reversed in a listing).
    bad = next((c for c in name if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp")),
               None)
    if bad is not None:
        raise InputError("study.name", f"must not contain control characters, got "
                         f"{name!r}")
    if not name.strip():
        raise InputError("study.name", "must not be empty")
    if "/" in name or "\\" in name or name.strip() in (".", "..") or len(name) > 120:
        raise InputError("study.name", f"must be a plain directory name (no '/' or '\\', "
                         f"not '.' or '..', at most 120 characters), got {name!r}")


def _sample_range(start, stop, seed) -> tuple[int, int, int]:
    """Validated ``(start, stop, seed)`` of :meth:`Study.sample`, as ints."""
    for label, value in (("start", start), ("stop", stop), ("seed", seed)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise TypeError(f"{label} must be an integer, got {value!r}")
    if not 0 <= start <= stop:
        raise ValueError(f"need 0 <= start <= stop, got start={start}, stop={stop}")
    if seed < 0:
        raise ValueError(f"seed must be >= 0, got {seed}")
    return int(start), int(stop), int(seed)


def _fill_defaults(cols, drawn) -> None:
    """Columns of inputs the study leaves out (zero vectors, ``e* = 1``, ``e_x = 0``), and
    ``e*`` from a drawn loss fraction (in place)."""
    for section, (prefix, _) in _VECTORS.items():
        for axis in "xyz":
            if f"{section}.{axis}" not in drawn:
                cols[f"{prefix}{axis}_in"][:] = 0.0
    if "restitution.loss_fraction" in drawn:
        e = cols["e"]
        np.subtract(1.0, e, out=e)
        np.sqrt(e, out=e)
    elif "restitution.e" not in drawn:
        cols["e"][:] = 1.0
    if "restitution.e_x" not in drawn:
        cols["e_x"][:] = 0.0


def _qmc(name, d, rng, **kwargs):
    """The scipy.stats.qmc engine ``name`` seeded with a Generator (``rng=`` from scipy
    1.15 on). Imported here, not with the module: scipy.stats costs ~0.3 s of start-up,
    and only studies with sobol or lhs inputs need it."""
    from scipy.stats import qmc

    engine = getattr(qmc, name)
    try:
        return engine(d, rng=rng, **kwargs)
    except TypeError:  # scipy < 1.15
        return engine(d, seed=rng, **kwargs)


def fill_bodies(cols, ball, bat) -> None:
    """Fill the ball's and the bat's mass and inertia columns of ``cols`` in place."""
    cols["ball_mass"][:] = ball.mass
    cols["ball_radius"][:] = ball.radius
    cols["ball_inertia_factor"][:] = ball.inertia_factor
    cols["bat_mass"][:] = bat.mass
    cols["bat_transverse_inertia"][:] = bat.transverse_inertia
    cols["bat_axial_inertia"][:] = bat.axial_inertia


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
