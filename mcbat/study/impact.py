"""Bat-frame studies: a validated ``Study`` and the solver input columns it samples.

A study is a Monte Carlo scan: every numeric input of the impact solver is either fixed
or drawn from a distribution, and ``Study.sample`` turns sample indices into the
float64 input columns of ``mcbat.core.batch.solve_batch``. ``Study`` is also the
base of ``mcbat.study.game.GameStudy``, which shares its ``[study]``, ``[output]`` and
``[summary]`` sections, overrides, config and drawing. The file format (sections, keys,
units, validation) is described in ``docs/study-format.md``; how samples are drawn in
``mcbat.study.drawing``.
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
from dataclasses import replace
from types import MappingProxyType

import numpy as np

from mcbat.checks import check_keys, check_string, check_tolerance, integer
from mcbat.core.geometry import angles_from_impact_parameters, impact_parameters_from_angles
from mcbat.errors import InputError
from mcbat.solving import INPUT_FIELDS, SolverSettings
from mcbat.study import units as u
from mcbat.study.distributions import Choice, Normal, check_range
from mcbat.study.drawing import (
    SOBOL_BITS,
    check_sample_range,
    draw_families,
    plan_families,
    sampling_scheme,
)
from mcbat.study.impact_inputs import INPUT_COLUMNS, fill_defaults, parse_inputs, parse_noise
from mcbat.study.output import OutputSpec, parse_columns, parse_output, parse_summary
from mcbat.study.random_program import NOISE, compile_program, draw
from mcbat.study.sections import (
    check_solver,
    check_study_name,
    exactly_one,
    fill_bodies,
    parse_ball,
    parse_bat,
)

__all__ = ["COLUMNS", "FORMAT_VERSION", "MAX_DESCRIPTION", "MAX_SAMPLES", "Study"]

#: Most samples of one run: 10^12 (11 days at 10^6 impacts/s). Beyond it a sample count is
#: a typo, and sample indices would near the range the seeding scheme is laid out for.
MAX_SAMPLES = 10**12
#: Longest ``study.description`` (characters): it is stored in every chunk file's Parquet
#: footer, which a reader refuses beyond ~100 MB.
MAX_DESCRIPTION = 10_000
#: Version of the study format and sampling scheme, recorded in ``Study.config``.
FORMAT_VERSION = 2

#: Columns returned by ``Study.sample``: the solver inputs, then the impact parameter.
COLUMNS = INPUT_FIELDS + ("impact_parameter",)

_REQUIRED_SECTIONS = ("study", "ball", "bat", "contact", "ball_velocity", "friction")
_OPTIONAL_SECTIONS = ("ball_spin", "bat_velocity", "bat_spin", "restitution", "solver",
                      "noise", "output", "summary")


class Study:
    """A validated study: bodies, input distributions, sampling defaults, solver settings.

    Build it with ``mcbat.study.load_study`` (a TOML file) or ``from_dict``
    (parsed TOML). Everything is validated on construction; ``sample`` then never
    raises for input reasons.

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
        ``{"steps", "tolerance", "max_steps"}`` for ``mcbat.core.batch.solve_batch``.
    ball : mcbat.bodies.Ball
    bat : mcbat.bodies.Bat
    inputs : mapping
        Declared numeric inputs, dotted key → ``mcbat.study.distributions.Dist``,
        in declaration order.
    grid_size : int or None
        ``G``, the number of points of the grid inputs' outer product (None: no grid).
    source : str or None
        The file the study came from.
    source_text : str or None
        The raw TOML text.
    """

    #: ``"impact"`` (the bat frame) or ``"game"`` (``mcbat.study.game.GameStudy``).
    kind = "impact"
    #: Sections whose presence makes ``from_dict`` build this subclass of Study.
    marker_sections: tuple[str, ...] = ()
    # The subclasses that declare marker sections, registered as they are defined (a
    # registry, so that this module need not import the kinds of study built on it).
    # mcbat.study's __init__ imports every kind (through mcbat.study.spec), and it runs
    # before any module of the package, so the registry is complete whenever Study is.
    _variants: list[type[Study]] = []

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("marker_sections"):
            Study._variants.append(cls)

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
            The study, as in the file format (``docs/study-format.md``).
        source : str, optional
            Where it came from (for error messages).
        text : str, optional
            The raw TOML text, kept as ``source_text``.

        Returns
        -------
        Study
            A ``mcbat.study.game.GameStudy`` when ``data`` has a ``[pitch]``,
            ``[swing]`` or ``[pitches]`` section.

        Raises
        ------
        InputError
            Naming ``source``, the dotted key and the offending value.
        """
        if cls is Study and isinstance(data, dict):
            for variant in Study._variants:
                if any(k in data for k in variant.marker_sections):
                    return variant(data, source=source, text=text)
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
        self.noise = parse_noise(data.get("noise", {}))
        self._parse_output(data)
        inputs = parse_inputs(data)
        contact = data["contact"]
        self._axial_key = exactly_one(contact, "contact", "axial", "from_barrel_end")
        self._angle_key = exactly_one(contact, "contact", "angle", "impact_parameter")
        self.inputs = MappingProxyType(inputs)
        self._check_ranges()
        self._plan()

    def _parse_output(self, data):
        """``[output]`` and ``[summary]`` (``mcbat.study.output``; the runner checks
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
        """Group the inputs by how they are sampled (``mcbat.study.drawing``)."""
        self._families, self.grid_size = plan_families(self.inputs)

    @property
    def solver(self) -> dict:
        """``{"steps", "tolerance", "max_steps"}`` (a copy) for the kernel."""
        return dict(self._solver)

    @property
    def solver_settings(self) -> SolverSettings:
        """The ``[solver]`` table as the kernels take it (``mcbat.solving``)."""
        return SolverSettings.from_config(self._solver)

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
        runs): ``MAX_SAMPLES``, and ``2**SOBOL_BITS`` with a ``sobol`` input."""
        if samples > MAX_SAMPLES:
            raise InputError(field, f"must be <= {MAX_SAMPLES:,}, got {samples:,}")
        if self._families["sobol"] and samples > 2**SOBOL_BITS:
            sobol = ", ".join(name for name, _ in self._families["sobol"])
            raise InputError(field, f"a study with sobol inputs ({sobol}) draws at most "
                             f"2**{SOBOL_BITS} = {2**SOBOL_BITS:,} samples, got {samples:,}")

    def definition(self) -> dict:
        """The study as plain data (the dict ``tomllib`` returns): ``from_dict`` of it
        rebuilds an equal study, with the same ``config``.

        It is what a remote worker needs to rebuild the study (``mcbat.engines.dask``):
        a deep copy of the validated input with the current sample count, seed and chunk
        size (``with_overrides``) written into its ``[study]`` table, and an overridden
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
            "sampling": sampling_scheme(),
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
        """``config`` as canonical JSON (sorted keys, no whitespace)."""
        return json.dumps(self.config(), sort_keys=True, separators=(",", ":"),
                          allow_nan=False)

    def config_hash(self) -> str:
        """SHA-256 (hex) of ``config_json``."""
        return hashlib.sha256(self.config_json().encode("utf-8")).hexdigest()

    def __repr__(self):
        return (f"Study(name={self.name!r}, samples={self.samples}, seed={self.seed}, "
                f"inputs={len(self.inputs)}, source={self.source!r})")

    # ------------------------------------------------------------ sampling

    def _draw(self, start, stop, seed, table, rows):
        """Write the values of every declared input for samples ``[start, stop)`` into
        row ``rows[name]`` of ``table`` (float64, ``stop - start`` columns)."""
        draw_families(self._families, self.grid_size, start, stop, seed, table, rows)

    def measurement_noise(self, start, stop, seed=None) -> dict[str, np.ndarray]:
        """Gaussian measurement errors for the ``[noise]`` outputs of samples
        ``start .. stop - 1`` (same units as the columns; deterministic in the index:
        Philox stream ``noise.<name>``, see ``mcbat.core.sampling``)."""
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
            Sample indices, ``0 <= start <= stop`` (``stop`` defaults to ``samples``;
            indices past it are defined too).
        seed : int, optional
            Default ``seed``.

        Returns
        -------
        dict
            float64 arrays of length ``stop - start`` (SI units) for every name in
            ``COLUMNS``: ``mcbat.core.batch.INPUT_FIELDS`` in order, then
            ``"impact_parameter"`` (m, for the study's approach azimuth). They are the
            rows of one C-contiguous ``(len(COLUMNS), n)`` array, so
            ``np.stack([cols[f] for f in INPUT_FIELDS])`` is a plain copy.
        """
        start, stop, seed = check_sample_range(start, self.samples if stop is None else stop,
                                          self.seed if seed is None else seed)
        n = stop - start
        # Inputs are drawn straight into their columns (from_barrel_end into "axial" and
        # loss_fraction into "e", converted in place below); an input with no column of
        # its own (approach_azimuth) into an extra row after them.
        extra = [name for name in self.inputs if name not in INPUT_COLUMNS]
        table = np.empty((len(COLUMNS) + len(extra), n))
        cols = {name: table[i] for i, name in enumerate(COLUMNS)}
        if n == 0:
            return cols
        rows = {name: (_COLUMN_ROWS[INPUT_COLUMNS[name]] if name in INPUT_COLUMNS
                       else len(COLUMNS) + extra.index(name)) for name in self.inputs}
        self._draw(start, stop, seed, table, rows)
        fill_defaults(cols, rows)

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


#: Row of each column in the table ``Study.sample`` fills.
_COLUMN_ROWS = {name: i for i, name in enumerate(COLUMNS)}
