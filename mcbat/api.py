"""Python API for single impacts: build a case, solve it, read the result.

Example
-------
>>> from mcbat.api import Ball, Bat, Contact, ImpactCase, solve
>>> case = ImpactCase(
...     ball=Ball(mass=0.145, radius=0.036),
...     bat=Bat(mass=0.989, radius=0.03335, transverse_inertia=0.046, axial_inertia=4.39e-4),
...     contact=Contact(axial=0.115, angle=0.0),
...     ball_velocity=(-4.0, 0.0, 0.0), mu=0.5, e=0.618)
>>> result = solve(case)
>>> result.end_state
'stuck'

All quantities are SI, in the lab frame of ``docs/physics.md``: the bat CM at the origin, ``z``
along the bat axis towards the barrel end.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from mcbat.bodies import BALL_PRESETS, BAT_PRESETS, Ball, Bat, bat_preset
from mcbat.bodies.game import DEFAULT_PIVOT, GAME_RESTITUTION, Restitution
from mcbat.core import status as st
from mcbat.core.batch import OUTPUT_FIELDS
from mcbat.core.cabo2012 import IMPACT_FIELDS, solve_impact
from mcbat.core.cabo2012.contact import (
    DEFAULT_MAX_STEPS,
    DEFAULT_STEPS,
    DEFAULT_TOLERANCE,
    Accuracy,
)
from mcbat.core.cabo2012.impact import (
    INERTIA_RANGE,
    LENGTH_RANGE,
    MASS_RANGE,
    MAX_AXIAL,
    MAX_MU,
    MAX_SPEED,
    MAX_SPIN,
    ImpactInputs,
)
from mcbat.core.cabo2012.trajectory import contact_history
from mcbat.core.flight import fly as flight_kernel
from mcbat.core.flight.trajectory import integrate as integrate_flight
from mcbat.core.geometry import (
    angle_from_impact_parameter,
    contact_frame,
    impact_parameter_from_angle,
)
from mcbat.core.rigid_bodies import delassus_matrix, kinetic_energy, relative_contact_velocity
from mcbat.core.swing import (
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    SWEET_SPOT_FROM_BARREL_END,
    allocate_game_outputs,
    bat_frame_columns,
    incoming_state,
    solve_game_batch,
)
from mcbat.dataset.schema import derive, derive_game
from mcbat.errors import InputError
from mcbat.errors import check_real as _real
from mcbat.errors import check_vector as _vector
from mcbat.study.distributions import parse
from mcbat.study.flight import FLIGHT_KEYS, FlightSettings, launch_vectors, parse_flight
from mcbat.study.game import KEYS as GAME_KEYS
from mcbat.study.game import check_swing_angles, is_game, parse_handedness
from mcbat.study.spec import check_tolerance, parse_ball

__all__ = ["Ball", "Bat", "Contact", "FlightCase", "FlightResult", "GameCase", "GameResult",
           "ImpactCase", "ImpactResult", "Restitution", "SolverSettings", "case_from_dict",
           "contact_problem", "flight_case_from_dict", "history", "solve", "solve_any",
           "solve_flight", "solve_game"]

Vector = tuple[float, float, float]



#: The largest contact azimuth (rad) taken: beyond it the rounding of the angle itself
#: (above 1e-10 rad) moves the contact point more than the solver's tolerance.
MAX_AZIMUTH = 1e6


def _attr(case, dotted):
    """The value at a dotted name of a case (``bat.radius``: at the contact)."""
    if dotted == "bat.radius":
        return case.contact_surface()[0]
    value = case
    for part in dotted.split("."):
        value = getattr(value, part)
    return value


@dataclass(frozen=True)
class Contact:
    """Contact point on the bat surface: axial position (m from the CM) and azimuth (rad)."""

    axial: float
    angle: float

    def __post_init__(self):
        object.__setattr__(self, "axial", _real(self.axial, "axial"))
        object.__setattr__(self, "angle", _real(self.angle, "angle"))

    @classmethod
    def from_impact_parameter(cls, axial, impact_parameter, ball: Ball, bat: Bat,
                              approach_azimuth=0.0) -> Contact:
        """Contact of a ball arriving perpendicular to the bat along an offset line.

        ``impact_parameter`` (m) is the offset of the ball's line from the bat axis;
        ``approach_azimuth`` (rad) the side it comes from (0: from ``+x``, moving along
        ``-x``). For a cylinder, ``b = (R + r_b) sin(theta - approach_azimuth)``.
        """
        radius, slope = bat.surface_at(axial)
        angle = angle_from_impact_parameter(
            _real(impact_parameter, "impact_parameter"), ball.radius, radius, slope,
            _real(approach_azimuth, "approach_azimuth"))
        if math.isnan(angle):
            reach = radius + ball.radius / math.sqrt(1.0 + slope * slope)
            raise InputError("impact_parameter",
                             f"|b| must be <= {reach:.6g} m (the ball misses), "
                             f"got {impact_parameter!r}")
        return cls(axial=axial, angle=angle)


@dataclass(frozen=True)
class SolverSettings:
    """Accuracy settings of the kernel (see ``mcbat.core.cabo2012.contact``).

    ``tolerance`` is the local error allowed per slip step, relative to ``|v0|`` in the slip
    velocity and to ``I_scale`` in the impulse (default 5e-9; ``solve_contact``); it must
    be finite with ``0 < tolerance < 1``, as a study's ``[solver] tolerance``:
    :class:`~mcbat.errors.InputError` names ``tolerance`` otherwise.
    """

    steps: int = DEFAULT_STEPS
    tolerance: float = DEFAULT_TOLERANCE
    max_steps: int = DEFAULT_MAX_STEPS

    def __post_init__(self):
        object.__setattr__(self, "tolerance",
                           check_tolerance(_real(self.tolerance, "tolerance"), "tolerance"))


@dataclass(frozen=True)
class ImpactCase:
    """One impact: bodies, contact point, initial velocities (lab frame), friction, e*.

    ``e`` is Stronge's energetic coefficient ``e*`` in [0, 1]; the paper's loss fraction
    ``e^2`` corresponds to ``e* = sqrt(1 - e^2)`` (:meth:`e_from_loss_fraction`). ``e_x``
    is the tangential restitution in [0, 1] of Cross & Nathan (2006): 0, the default, is
    the rigid model (see ``mcbat/core/cross_nathan2006/README.md``).
    """

    ball: Ball
    bat: Bat
    contact: Contact
    ball_velocity: Vector
    ball_spin: Vector = (0.0, 0.0, 0.0)
    bat_velocity: Vector = (0.0, 0.0, 0.0)
    bat_spin: Vector = (0.0, 0.0, 0.0)
    mu: float = 0.0
    e: float = 1.0
    e_x: float = 0.0

    def __post_init__(self):
        for name in ("ball_velocity", "ball_spin", "bat_velocity", "bat_spin"):
            object.__setattr__(self, name, _vector(getattr(self, name), name))
        object.__setattr__(self, "mu", _real(self.mu, "mu", minimum=0.0))
        object.__setattr__(self, "e", _real(self.e, "e", minimum=0.0, maximum=1.0))
        object.__setattr__(self, "e_x", _real(self.e_x, "e_x", minimum=0.0, maximum=1.0))
        self.contact_surface()  # the contact must lie on the bat

    @staticmethod
    def e_from_loss_fraction(loss_fraction: float) -> float:
        """``e*`` from the paper's fraction ``e^2`` of the peak stored energy that is lost."""
        return math.sqrt(1.0 - _real(loss_fraction, "loss_fraction", minimum=0.0, maximum=1.0))

    def contact_surface(self) -> tuple[float, float]:
        """Bat radius and slope at the contact point (which must lie on the bat, and where
        the touching ball must not reach into a tapered bat elsewhere)."""
        try:
            surface = self.bat.surface_at(self.contact.axial)
            self.bat.check_no_overlap(self.ball.radius, self.contact.axial,
                                      self.contact.axial)
            return surface
        except InputError as err:
            raise err.within("contact") from None

    def normal_approach_speed(self) -> float:
        """Initial normal relative contact velocity ``v_n`` (m/s); negative if approaching."""
        radius, slope = self.contact_surface()
        t1, t2, t3, r_c = contact_frame(self.contact.axial, self.contact.angle, radius, slope)
        v = relative_contact_velocity(self.ball.radius, t3, r_c, self.ball_velocity,
                                      self.ball_spin, self.bat_velocity, self.bat_spin)
        return float(np.dot(v, t3))

    def impact_parameter(self, approach_azimuth: float = 0.0) -> float:
        """Offset (m) of a line perpendicular to the bat through the ball centre, from the axis."""
        radius, slope = self.contact_surface()
        return float(impact_parameter_from_angle(self.contact.angle, self.ball.radius,
                                                 radius, slope, approach_azimuth))

    def check_solver_ranges(self) -> None:
        """Raise :class:`InputError` naming the first input outside the range the solver
        works in (``docs/physics.md``, "Valid inputs"): beyond it energies and impulses
        under- or overflow, and the kernel could only answer ``invalid_input``."""
        radius, _ = self.contact_surface()
        for name, value, (low, high), unit in (
                ("ball.mass", self.ball.mass, MASS_RANGE, "kg"),
                ("ball.radius", self.ball.radius, LENGTH_RANGE, "m"),
                ("bat.mass", self.bat.mass, MASS_RANGE, "kg"),
                ("bat.radius", radius, LENGTH_RANGE, "m"),
                ("bat.transverse_inertia", self.bat.transverse_inertia, INERTIA_RANGE,
                 "kg m^2"),
                ("bat.axial_inertia", self.bat.axial_inertia, INERTIA_RANGE, "kg m^2"),
                ("contact.axial", abs(self.contact.axial), (0.0, MAX_AXIAL), "m"),
                ("contact.angle", abs(self.contact.angle), (0.0, MAX_AZIMUTH), "rad"),
                ("mu", self.mu, (0.0, MAX_MU), "")):
            if not low <= value <= high:
                shown = f"+-{high:g}" if low == 0.0 and name.startswith("contact") else \
                    f"{low:g}..{high:g}"
                raise InputError(name, f"must be within {shown}{' ' + unit if unit else ''} "
                                 f"(the range the solver works in, docs/physics.md), got "
                                 f"{_attr(self, name):.6g}")
        if not 0.0 < self.ball.inertia_factor <= 1.0:
            raise InputError("ball.inertia_factor", f"must be in (0, 1], got "
                             f"{self.ball.inertia_factor:.6g}")
        for name, high, unit in (("ball_velocity", MAX_SPEED, "m/s"),
                                 ("ball_spin", MAX_SPIN, "rad/s"),
                                 ("bat_velocity", MAX_SPEED, "m/s"),
                                 ("bat_spin", MAX_SPIN, "rad/s")):
            vector = getattr(self, name)
            if not max(abs(x) for x in vector) <= high:
                raise InputError(name, f"every component must be within +-{high:g} {unit} "
                                 "(the range the solver works in, docs/physics.md), got "
                                 f"[{', '.join(f'{x:.6g}' for x in vector)}]")

    def validate_approach(self) -> None:
        """Raise :class:`InputError` unless the contact points approach (``v_n < 0``)."""
        vn = self.normal_approach_speed()
        if not vn < 0.0:
            raise InputError("ball_velocity",
                             f"the bodies are not approaching at the contact "
                             f"(normal relative velocity v_n = {vn:.6g} m/s >= 0)")

    @classmethod
    def from_dict(cls, data) -> ImpactCase:
        """Build a case from the JSON contract of ``mcbat impact`` (docs/impact.md)."""
        return _case_from_dict(data)


@dataclass(frozen=True)
class ImpactResult:
    """Outcome of one impact (SI units, lab frame).

    ``stick_impulse`` is None when sliding never stopped (0 for an impact that starts
    stuck); ``status`` and ``end_state`` are strings (``"ok"``, ``"stuck"``/``"sliding"``).
    """

    case: ImpactCase
    status: str
    end_state: str
    ball_velocity: Vector
    ball_spin: Vector
    bat_velocity: Vector
    bat_spin: Vector
    normal_impulse: float
    stick_impulse: float | None
    compression_impulse: float
    tangential_impulse: tuple[float, float]
    compression_work: float
    normal_work: float
    friction_work: float
    stick_criterion: float | None
    energy_in: float
    energy_out: float
    rk4_steps: int

    @property
    def exit_speed(self) -> float:
        """Speed of the outgoing ball, m/s."""
        return derive(self.ball_velocity, self.ball_spin)["exit_speed"]

    @property
    def scattering_angle(self) -> float:
        """``atan2(v_y, v_x)`` of the outgoing ball, degrees (0 = straight back along ``+x``)."""
        return derive(self.ball_velocity, self.ball_spin)["scattering_angle"]

    def __repr__(self) -> str:
        v = ", ".join(f"{c:.6g}" for c in self.ball_velocity)
        w = ", ".join(f"{c:.6g}" for c in self.ball_spin)
        stick = "never" if self.stick_impulse is None else f"{self.stick_impulse:.6g} kg m/s"
        return (f"ImpactResult(status={self.status!r}, end_state={self.end_state!r},\n"
                f"  ball_velocity=({v}) m/s, ball_spin=({w}) rad/s,\n"
                f"  exit_speed={self.exit_speed:.6g} m/s, "
                f"scattering_angle={self.scattering_angle:.4g} deg,\n"
                f"  normal_impulse={self.normal_impulse:.6g} kg m/s, stick_impulse={stick}, "
                f"energy {self.energy_in:.6g} -> {self.energy_out:.6g} J)")

    @property
    def restitution_loss(self) -> float:
        """Energy lost besides friction, ``-W_n(I_f)`` (J): the paper's extra loss."""
        return -self.normal_work

    def to_dict(self) -> dict:
        """JSON-ready dictionary (the output contract of ``mcbat impact``)."""
        return {
            "status": self.status,
            "end_state": self.end_state,
            "ball_velocity": list(self.ball_velocity),
            "ball_spin": list(self.ball_spin),
            "bat_velocity": list(self.bat_velocity),
            "bat_spin": list(self.bat_spin),
            "normal_impulse": self.normal_impulse,
            "stick_impulse": self.stick_impulse,
            "compression_impulse": self.compression_impulse,
            "tangential_impulse": list(self.tangential_impulse),
            "compression_work": self.compression_work,
            "normal_work": self.normal_work,
            "friction_work": self.friction_work,
            "restitution_loss": self.restitution_loss,
            "energy_in": self.energy_in,
            "energy_out": self.energy_out,
            "stick_criterion": self.stick_criterion,
            "exit_speed": self.exit_speed,
            "scattering_angle": self.scattering_angle,
            "impact_parameter": self.case.impact_parameter(),
            "rk4_steps": self.rk4_steps,
        }


def solve(case: ImpactCase, settings: SolverSettings = SolverSettings()) -> ImpactResult:
    """Solve one impact with the jitted kernel.

    Raises
    ------
    InputError
        If the bodies are not approaching at the contact.
        Also if the kernel reports a failure status (inputs whose magnitudes make the
        arithmetic meaningless, non-convergence, degenerate mechanics), naming the status.
    """
    case.check_solver_ranges()
    case.validate_approach()
    radius, slope = case.contact_surface()
    # Floats only: a Python int reaching the jitted kernel would compile (and cache) an
    # integer specialisation, and overflow it with the next big integer.
    physics = tuple(float(x) for x in (
        case.ball.mass, case.ball.radius, case.ball.inertia_factor,
        case.bat.mass, case.bat.transverse_inertia, case.bat.axial_inertia,
        case.contact.axial, case.contact.angle, radius, slope,
        *case.ball_velocity, *case.ball_spin, *case.bat_velocity, *case.bat_spin,
        case.mu, case.e, case.e_x))
    out = dict(zip(IMPACT_FIELDS, solve_impact(ImpactInputs(*physics), Accuracy(
        int(settings.steps), float(settings.tolerance), int(settings.max_steps)))))
    code = int(out["status"])
    if code != st.OK:
        raise InputError(None, f"the solver cannot solve this impact (status "
                         f"{st.STATUS_NAMES[code]!r}: docs/errors.md lists what each status "
                         "means)")

    def vec(prefix):
        return tuple(float(out[f"{prefix}{c}"]) for c in "xyz")

    def optional(value):
        return None if math.isnan(value) else float(value)

    return ImpactResult(
        case=case,
        status=st.STATUS_NAMES[code],
        end_state=st.END_STATE_NAMES[int(out["end_state"])],
        ball_velocity=vec("ball_v"), ball_spin=vec("ball_w"),
        bat_velocity=vec("bat_v"), bat_spin=vec("bat_w"),
        normal_impulse=float(out["normal_impulse"]),
        stick_impulse=optional(out["stick_impulse"]),
        compression_impulse=float(out["compression_impulse"]),
        tangential_impulse=(float(out["tangential_impulse_1"]),
                            float(out["tangential_impulse_2"])),
        compression_work=float(out["compression_work"]),
        normal_work=float(out["normal_work"]),
        friction_work=float(out["friction_work"]),
        stick_criterion=optional(out["stick_criterion"]),
        energy_in=float(out["energy_in"]),
        energy_out=float(out["energy_out"]),
        rk4_steps=int(out["rk4_steps"]),
    )


def contact_problem(case: ImpactCase) -> dict:
    """The impact in its contact basis: the Delassus matrix and the initial slip.

    Returns a dict with ``K`` (3x3, 1/kg, basis ``t1, t2, t3``), ``v0`` (initial relative
    contact velocity in that basis, m/s), ``t1, t2, t3, r_c`` (lab frame) and the paper's
    ``s1 = mu K11``, ``s2 = mu K22``, ``s0 = K23``.
    """
    radius, slope = case.contact_surface()
    t1, t2, t3, r_c = contact_frame(case.contact.axial, case.contact.angle, radius, slope)
    k11, k12, k13, k22, k23, k33 = delassus_matrix(
        case.ball.mass, case.ball.radius, case.ball.inertia_factor, case.bat.mass,
        case.bat.transverse_inertia, case.bat.axial_inertia, t1, t2, t3, r_c)
    v = relative_contact_velocity(case.ball.radius, t3, r_c, case.ball_velocity,
                                  case.ball_spin, case.bat_velocity, case.bat_spin)
    K = np.array([[k11, k12, k13], [k12, k22, k23], [k13, k23, k33]])
    v0 = np.array([np.dot(v, t1), np.dot(v, t2), np.dot(v, t3)])
    return {"K": K, "v0": v0, "t1": np.array(t1), "t2": np.array(t2), "t3": np.array(t3),
            "r_c": np.array(r_c), "s1": case.mu * k11, "s2": case.mu * k22, "s0": k23}


def history(case: ImpactCase, impulses, settings: SolverSettings = SolverSettings()) -> dict:
    """The impact as a function of the normal impulse (for plots and checks).

    Parameters
    ----------
    case : ImpactCase
    impulses : array_like
        Sorted normal impulses ``I >= 0`` (kg m/s). The curves continue past separation.

    Returns
    -------
    dict
        Arrays ``I``, ``v1``, ``v2`` (tangential relative velocity along ``t1``, ``t2``),
        ``slip_speed``, ``v_n`` (m/s), ``normal_work``, ``friction_work``, ``energy``
        (kinetic energy ``E_in + W_n + W_fr``, J), ``phase`` (0 slip, 1 stick,
        2 re-slip), and the scalars ``stick_impulse`` (NaN if none) and ``energy_in``.
    """
    impulses = np.asarray(impulses, dtype=np.float64)
    if impulses.ndim != 1 or np.any(np.diff(impulses) < 0) or np.any(impulses < 0):
        raise InputError("impulses", "must be a sorted 1-D array of impulses >= 0")
    case.validate_approach()
    prob = contact_problem(case)
    K, v0 = prob["K"], prob["v0"]
    out, i_s = contact_history(K[0, 0], K[0, 1], K[0, 2], K[1, 1], K[1, 2], K[2, 2],
                               v0[0], v0[1], v0[2], case.mu, impulses, settings.tolerance)
    e_in = kinetic_energy(case.ball.mass, case.ball.radius, case.ball.inertia_factor,
                          case.bat.mass, case.bat.transverse_inertia, case.bat.axial_inertia,
                          case.ball_velocity, case.ball_spin, case.bat_velocity,
                          case.bat_spin)
    return {"I": impulses, "v1": out[:, 0], "v2": out[:, 1],
            "slip_speed": np.hypot(out[:, 0], out[:, 1]), "v_n": out[:, 2],
            "normal_work": out[:, 3], "friction_work": out[:, 4],
            "energy": e_in + out[:, 3] + out[:, 4], "phase": out[:, 5].astype(int),
            "stick_impulse": float(i_s), "energy_in": float(e_in)}


# ---- the JSON contract of `mcbat impact` ----

_CASE_KEYS = {"ball", "bat", "contact", "ball_velocity", "ball_spin", "bat_velocity",
              "bat_spin", "mu", "restitution"}
_REQUIRED = ("ball", "bat", "contact", "ball_velocity", "mu")


def _mapping(data, name, allowed, required):
    if not isinstance(data, dict):
        raise InputError(name, f"must be an object, got {type(data).__name__}")
    unknown = sorted(set(data) - set(allowed))
    if unknown:
        where = f"{name}." if name else ""
        raise InputError(f"{where}{unknown[0]}",
                         f"unknown key (expected one of: {', '.join(sorted(allowed))})")
    for key in required:
        if key not in data:
            where = f"{name}." if name else ""
            raise InputError(f"{where}{key}", "missing required key")
    return data


def _build(prefix, builder, *args, **kwargs):
    """``builder(*args, **kwargs)``, with input errors located inside ``prefix``."""
    try:
        return builder(*args, **kwargs)
    except InputError as err:
        raise err.within(prefix) from None


def _case_from_dict(data) -> ImpactCase:
    _mapping(data, "", _CASE_KEYS, _REQUIRED)
    ball_d = _mapping(data["ball"], "ball", {"mass", "radius", "inertia_factor"},
                      ("mass", "radius"))
    ball = _build("ball", Ball, **ball_d)
    if isinstance(data["bat"], dict) and "preset" in data["bat"]:
        bat = _build("bat", _bat_from_dict, data["bat"])
    else:
        bat_d = _mapping(data["bat"], "bat",
                         {"mass", "radius", "transverse_inertia", "axial_inertia"},
                         ("mass", "radius", "transverse_inertia", "axial_inertia"))
        bat = _build("bat", Bat, **bat_d)
    contact_d = _mapping(data["contact"], "contact",
                         {"axial", "angle", "impact_parameter", "approach_azimuth"}, ("axial",))
    if ("angle" in contact_d) == ("impact_parameter" in contact_d):
        raise InputError("contact", "give exactly one of 'angle' or 'impact_parameter'")
    if "angle" in contact_d:
        if "approach_azimuth" in contact_d:
            raise InputError("contact.approach_azimuth", "only valid with 'impact_parameter'")
        contact = _build("contact", Contact, **contact_d)
    else:
        axial = _build("contact", _real, contact_d["axial"], "axial")
        contact = _build("contact", Contact.from_impact_parameter, axial=axial,
                         impact_parameter=contact_d["impact_parameter"], ball=ball, bat=bat,
                         approach_azimuth=contact_d.get("approach_azimuth", 0.0))
    e, e_x = 1.0, 0.0
    if "restitution" in data:
        rest = dict(_mapping(data["restitution"], "restitution",
                             {"e", "loss_fraction", "e_x"}, ()))
        if "e_x" in rest:  # tangential restitution (optional; alone it keeps e* = 1)
            e_x = _build("restitution", _real, rest.pop("e_x"), "e_x", minimum=0.0,
                         maximum=1.0)
        elif len(rest) != 1:
            raise InputError("restitution", "give exactly one of 'e' or 'loss_fraction'")
        if len(rest) > 1:
            raise InputError("restitution", "give exactly one of 'e' or 'loss_fraction'")
        if "e" in rest:
            e = _build("restitution", _real, rest["e"], "e", minimum=0.0, maximum=1.0)
        elif "loss_fraction" in rest:
            e = _build("restitution", ImpactCase.e_from_loss_fraction,
                       loss_fraction=rest["loss_fraction"])
    vectors = {k: data[k] for k in ("ball_velocity", "ball_spin", "bat_velocity", "bat_spin")
               if k in data}
    case = ImpactCase(ball=ball, bat=bat, contact=contact, mu=data["mu"], e=e, e_x=e_x,
                        **vectors)
    case.check_solver_ranges()
    case.validate_approach()
    return case


# ---- the game situation: pitch, swing and contact in the field frame ----

_GAME_KEYS = {  # Python parameter -> (JSON section, key)
    "pitch_speed": ("pitch", "speed"),
    "vertical_approach_angle": ("pitch", "vertical_approach_angle"),
    "horizontal_approach_angle": ("pitch", "horizontal_approach_angle"),
    "spin_rate": ("pitch", "spin_rate"), "spin_axis": ("pitch", "spin_axis"),
    "spin_efficiency": ("pitch", "spin_efficiency"), "gyro_sign": ("pitch", "gyro_sign"),
    "bat_speed": ("swing", "bat_speed"), "attack_angle": ("swing", "attack_angle"),
    "attack_direction": ("swing", "attack_direction"),
    "vertical_bat_angle": ("swing", "vertical_bat_angle"), "pivot": ("swing", "pivot"),
    "from_barrel_end": ("contact", "from_barrel_end"), "undercut": ("contact", "undercut"),
}
_RIGHT_ANGLE = math.pi / 2


def _solver_range(value, name, high, unit):
    """A game input beyond the solver's range (``docs/physics.md``, "Valid inputs"): the
    impact's velocities and spins scale with it."""
    if not value <= high:
        raise InputError(name, f"must be at most {high:g}{' ' + unit if unit else ''} (the "
                         f"range the solver works in, docs/physics.md), got {value:.6g}"
                         f"{' ' + unit if unit else ''}")


@dataclass(frozen=True)
class GameCase:
    """One game situation (SI units: m, m/s, rad, rad/s; ``docs/batting.md``).

    The pitch (field frame: ``x`` to first base, ``y`` to the pitcher, ``z`` up): speed,
    approach angles (vertical < 0 descending; horizontal > 0 moving towards ``+x``),
    spin rate, Statcast spin axis (pi = pure backspin, 0 = topspin, pi/2 = Magnus
    movement towards ``+x``), spin efficiency (transverse fraction) and the sense of the
    gyro part. The swing: sweet-spot speed, attack angle, attack direction (positive
    towards the batter's opposite field), vertical bat angle, and the pivot's distance
    from the knob. The contact: distance from the barrel end and undercut (positive:
    the ball's centre above the bat axis). ``handedness`` "R" or "L" (mirror image in
    ``x``). ``restitution`` gives ``e*`` and ``e_x``
    (:class:`mcbat.bodies.game.Restitution`; default the game preset).
    """

    ball: Ball
    bat: Bat
    pitch_speed: float
    bat_speed: float
    mu: float
    handedness: str = "R"
    vertical_approach_angle: float = 0.0
    horizontal_approach_angle: float = 0.0
    spin_rate: float = 0.0
    spin_axis: float = math.pi
    spin_efficiency: float = 1.0
    gyro_sign: float = 1.0
    attack_angle: float = 0.0
    attack_direction: float = 0.0
    vertical_bat_angle: float = 0.0
    pivot: float = DEFAULT_PIVOT
    from_barrel_end: float = SWEET_SPOT_FROM_BARREL_END
    undercut: float = 0.0
    restitution: Restitution = GAME_RESTITUTION

    def __post_init__(self):  # noqa: C901 - one check per key, in the contract's order
        bat = self.bat
        if bat.length is None or bat.cm_from_barrel_end is None:
            raise InputError("bat", "a game needs the bat's length and CM (cm_from_knob), "
                             "or a bat preset")
        parse_handedness(self.handedness)
        object.__setattr__(self, "pitch_speed",
                           _real(self.pitch_speed, "pitch_speed", positive=True))
        for name in ("vertical_approach_angle", "horizontal_approach_angle"):
            value = _real(getattr(self, name), name)
            if not abs(value) < _RIGHT_ANGLE:
                raise InputError(name, f"must lie within (-90, 90) deg for a pitch moving "
                                 f"towards the plate, got {math.degrees(value):.6g} deg")
        object.__setattr__(self, "spin_rate", _real(self.spin_rate, "spin_rate", minimum=0.0))
        _solver_range(self.pitch_speed, "pitch_speed", MAX_SPEED, "m/s")
        _solver_range(self.spin_rate, "spin_rate", MAX_SPIN, "rad/s")
        object.__setattr__(self, "spin_axis", _real(self.spin_axis, "spin_axis"))
        object.__setattr__(self, "spin_efficiency",
                           _real(self.spin_efficiency, "spin_efficiency", minimum=0.0, maximum=1.0))
        if self.gyro_sign not in (1, -1):
            raise InputError("gyro_sign", f"must be +1 or -1, got {self.gyro_sign!r}")
        object.__setattr__(self, "bat_speed", _real(self.bat_speed, "bat_speed", minimum=0.0))
        _solver_range(self.bat_speed, "bat_speed", MAX_SPEED, "m/s")
        for name in ("attack_angle", "attack_direction", "vertical_bat_angle"):
            value = _real(getattr(self, name), name)
            if not abs(value) < _RIGHT_ANGLE:
                raise InputError(name, f"must lie within (-90, 90) deg, "
                                 f"got {math.degrees(value):.6g} deg")
        check_swing_angles(self.attack_angle, self.vertical_bat_angle, "vertical_bat_angle")
        sweet = bat.length - SWEET_SPOT_FROM_BARREL_END
        object.__setattr__(self, "pivot", _real(self.pivot, "pivot", minimum=0.0))
        if not self.pivot < sweet:
            raise InputError("pivot", f"must lie between the knob and the sweet spot "
                             f"(< {sweet:.4g} m from the knob), got {self.pivot!r}")
        object.__setattr__(self, "from_barrel_end",
                           _real(self.from_barrel_end, "from_barrel_end", minimum=0.0,
                                 maximum=bat.length))
        object.__setattr__(self, "mu", _real(self.mu, "mu", minimum=0.0))
        _solver_range(self.mu, "mu", MAX_MU, "")
        radius, slope = self.contact_surface()
        reach = radius + self.ball.radius / math.sqrt(1.0 + slope * slope)
        if not abs(_real(self.undercut, "undercut")) <= reach:
            raise InputError("undercut", f"|undercut| must be <= {reach:.6g} m, the reach of "
                             f"barrel and ball there (the ball misses), got {self.undercut!r}")

    @property
    def axial(self) -> float:
        """The contact's axial position from the bat CM (m)."""
        return self.bat.cm_from_barrel_end - self.from_barrel_end

    def contact_surface(self) -> tuple[float, float]:
        """Bat radius and slope at the contact."""
        return self.bat.surface_at(float(self.bat.clip_axial(self.axial)))

    def kernel_inputs(self) -> np.ndarray:
        """The case as one column of :data:`mcbat.core.swing.GAME_INPUT_FIELDS`."""
        radius, slope = self.contact_surface()
        rest = self.restitution
        row = {name: getattr(self, name) for name in _GAME_KEYS}
        row.update(
            ball_mass=self.ball.mass, ball_radius=self.ball.radius,
            ball_inertia_factor=self.ball.inertia_factor, bat_mass=self.bat.mass,
            bat_transverse_inertia=self.bat.transverse_inertia,
            bat_axial_inertia=self.bat.axial_inertia, bat_length=self.bat.length,
            bat_cm_from_knob=self.bat.length - self.bat.cm_from_barrel_end,
            bat_radius=radius, bat_slope=slope,
            handedness=parse_handedness(self.handedness), mu=self.mu, e_ref=rest.e_ref,
            e_slope=rest.e_slope, e_speed_ref=rest.e_speed_ref,
            e_location_factor=rest.location_factor(self.from_barrel_end), e_x=rest.e_x)
        row = {("pitch_" + k if k in _PITCH_COLUMNS else k): v for k, v in row.items()}
        return np.array([[float(row[name])] for name in GAME_INPUT_FIELDS])

    def mirrored(self) -> GameCase:
        """The mirror image in ``x``: the other handedness, and the pitch mirrored
        (horizontal approach angle and spin axis negated, gyro sense reversed)."""
        return dataclasses.replace(
            self, handedness="L" if self.handedness == "R" else "R",
            horizontal_approach_angle=-self.horizontal_approach_angle,
            spin_axis=2.0 * math.pi - self.spin_axis, gyro_sign=-self.gyro_sign)

    @classmethod
    def from_dict(cls, data) -> GameCase:
        """Build a game case from the JSON contract of ``mcbat impact`` (``docs/batting.md``)."""
        return _game_from_dict(data)


_PITCH_COLUMNS = ("speed", "vertical_approach_angle", "horizontal_approach_angle",
                  "spin_rate", "spin_axis", "spin_efficiency", "gyro_sign")


@dataclass(frozen=True)
class GameResult:
    """A solved game case: the batted ball in the field's conventions, the field-frame
    velocities and spins, and the bat-frame impact (``impact``, an :class:`ImpactResult`
    whose ``case`` re-solves in the bat frame alone)."""

    case: GameCase
    impact: ImpactResult
    collision_efficiency: float
    ball_velocity: Vector
    ball_spin: Vector
    bat_velocity: Vector
    bat_spin: Vector
    pitch_velocity: Vector
    pitch_spin: Vector
    bat_velocity_in: Vector
    bat_spin_in: Vector
    undercut_impact_parameter: float

    @property
    def batted_ball(self) -> dict:
        """``launch_speed`` (mph), ``launch_angle``, ``spray_angle`` (deg), ``spin_rate``,
        ``backspin``, ``sidespin``, ``gyrospin`` (rpm)."""
        return derive_game(self.ball_velocity, self.ball_spin)

    def __getattr__(self, name):
        if name in ("launch_speed", "launch_angle", "spray_angle", "spin_rate", "backspin",
                    "sidespin", "gyrospin"):
            return self.batted_ball[name]
        raise AttributeError(name)

    def to_dict(self) -> dict:
        """JSON-ready dictionary (the output of ``mcbat impact`` for a game case)."""
        return {
            "status": self.impact.status, "end_state": self.impact.end_state,
            **self.batted_ball,
            "collision_efficiency": self.collision_efficiency,
            "field": {"ball_velocity": list(self.ball_velocity),
                      "ball_spin": list(self.ball_spin),
                      "bat_velocity": list(self.bat_velocity), "bat_spin": list(self.bat_spin),
                      "pitch_velocity": list(self.pitch_velocity),
                      "pitch_spin": list(self.pitch_spin),
                      "bat_velocity_in": list(self.bat_velocity_in),
                      "bat_spin_in": list(self.bat_spin_in)},
            "bat_frame_case": _impact_case_dict(self.impact.case),
            "bat_frame": self.impact.to_dict(),
        }


def solve_game(case: GameCase, settings: SolverSettings = SolverSettings()) -> GameResult:
    """Solve one game situation with the game kernel (the one ``mcbat run`` uses).

    Raises
    ------
    InputError
        Naming ``pitch_speed`` if the ball does not approach the bat at the contact.
        Also if the kernel reports another failure status, naming it.
    """
    g = case.kernel_inputs()
    frame, out, game_out, status, end_state = allocate_game_outputs(1)
    solve_game_batch(g, settings.steps, settings.tolerance, settings.max_steps, frame, out,
                     game_out, status, end_state)
    code = int(status[0])
    if code == st.NOT_APPROACHING:
        raise InputError("pitch_speed", "the ball does not approach the bat at the contact "
                         "(a pitch moving away from the swing)")
    if code != st.OK:
        raise InputError(None, f"the solver cannot solve this impact (status "
                         f"{st.STATUS_NAMES[code]!r}: docs/errors.md lists what each status "
                         "means)")
    b = {name: column[0] for name, column in bat_frame_columns(g, frame).items()}
    o = dict(zip(OUTPUT_FIELDS, out[:, 0]))
    go = dict(zip(GAME_OUTPUT_FIELDS, game_out[:, 0]))

    def vec(d, fmt):
        return tuple(float(d[fmt.format(c)]) for c in "xyz")

    pitch_v, pitch_w, bat_v, bat_w = (tuple(float(x) for x in v)
                                      for v in incoming_state(g, 0))

    impact_case = ImpactCase(
        ball=case.ball, bat=case.bat, contact=Contact(axial=float(b["axial"]),
                                                      angle=float(b["angle"])),
        ball_velocity=vec(b, "ball_v{}_in"), ball_spin=vec(b, "ball_w{}_in"),
        bat_velocity=vec(b, "bat_v{}_in"), bat_spin=vec(b, "bat_w{}_in"),
        mu=float(b["mu"]), e=float(b["e"]), e_x=float(b["e_x"]))
    stick = float(o["stick_impulse"])
    crit = float(o["stick_criterion"])
    impact = ImpactResult(
        case=impact_case, status="ok", end_state=st.END_STATE_NAMES[int(end_state[0])],
        ball_velocity=vec(o, "ball_v{}"), ball_spin=vec(o, "ball_w{}"),
        bat_velocity=vec(o, "bat_v{}"), bat_spin=vec(o, "bat_w{}"),
        normal_impulse=float(o["normal_impulse"]),
        stick_impulse=None if math.isnan(stick) else stick,
        compression_impulse=float(o["compression_impulse"]),
        tangential_impulse=(float(o["tangential_impulse_1"]), float(o["tangential_impulse_2"])),
        compression_work=float(o["compression_work"]), normal_work=float(o["normal_work"]),
        friction_work=float(o["friction_work"]),
        stick_criterion=None if math.isnan(crit) else crit,
        energy_in=float(o["energy_in"]), energy_out=float(o["energy_out"]),
        rk4_steps=int(o["rk4_steps"]))
    return GameResult(
        case=case, impact=impact, collision_efficiency=float(go["collision_efficiency"]),
        ball_velocity=vec(go, "field_ball_v{}"), ball_spin=vec(go, "field_ball_w{}"),
        bat_velocity=vec(go, "field_bat_v{}"), bat_spin=vec(go, "field_bat_w{}"),
        pitch_velocity=pitch_v, pitch_spin=pitch_w, bat_velocity_in=bat_v, bat_spin_in=bat_w,
        undercut_impact_parameter=float(go["impact_parameter"]))


def _impact_case_dict(case: ImpactCase) -> dict:
    """An :class:`ImpactCase` as a bat-frame JSON case of ``mcbat impact``."""
    bat = case.bat
    bat_d = ({"preset": bat.preset} if bat.profile is not None else
             {"mass": bat.mass, "radius": bat.radius,
              "transverse_inertia": bat.transverse_inertia,
              "axial_inertia": bat.axial_inertia})
    return {"ball": {"mass": case.ball.mass, "radius": case.ball.radius,
                     "inertia_factor": case.ball.inertia_factor},
            "bat": bat_d, "contact": {"axial": case.contact.axial, "angle": case.contact.angle},
            "ball_velocity": list(case.ball_velocity), "ball_spin": list(case.ball_spin),
            "bat_velocity": list(case.bat_velocity), "bat_spin": list(case.bat_spin),
            "mu": case.mu, "restitution": {"e": case.e, "e_x": case.e_x}}


def _game_value(spec, field, quantity):
    return parse(spec, field, quantity, kinds=("fixed",)).value


def _game_from_dict(data) -> GameCase:
    allowed = {"handedness", "ball", "bat", "pitch", "swing", "contact", "mu", "restitution"}
    _mapping(data, "", allowed, ("bat", "pitch", "swing", "mu"))
    ball = (BALL_PRESETS["baseball"] if "ball" not in data
            else _build("ball", _ball_from_dict, data["ball"]))
    bat = _build("bat", _bat_from_dict, data["bat"], game=True)
    values = {}
    for section in ("pitch", "swing", "contact"):
        keys = GAME_KEYS[section]
        table = _mapping(data.get(section, {}), section, set(keys),
                         [k for k, spec in keys.items() if spec[1] is None])
        for key, spec in table.items():
            values[keys[key][2].removeprefix("pitch_") if section == "pitch" else
                   keys[key][2]] = _game_value(spec, f"{section}.{key}", keys[key][0])
    values["pitch_speed"] = values.pop("speed")
    mu = _game_value(data["mu"], "mu", "dimensionless")
    restitution = GAME_RESTITUTION
    if "restitution" in data:
        keys = GAME_KEYS["restitution"]
        rest = _mapping(data["restitution"], "restitution", set(keys) | {"location"}, ())
        if ("e" in rest) == ("e_ref" in rest):
            raise InputError("restitution", "give exactly one of 'e' (a constant e*) or "
                             "'e_ref' (with e_slope and e_speed_ref)")
        kw = {("e_ref" if k == "e" else k): (_game_value(v, f"restitution.{k}", keys[k][0])
                                             if k != "location" else v)
              for k, v in rest.items()}
        restitution = _build("restitution", Restitution, **kw)
    handedness = data.get("handedness", "R")
    try:
        return GameCase(ball=ball, bat=bat, mu=mu, handedness=handedness,
                        restitution=restitution, **values)
    except InputError as err:
        if err.field in _GAME_KEYS:
            section, key = _GAME_KEYS[err.field]
            raise InputError(f"{section}.{key}", err.message) from None
        raise


def _ball_from_dict(data) -> Ball:
    if isinstance(data, dict) and "preset" in data:
        _mapping(data, "", {"preset"}, ())
        if data["preset"] not in BALL_PRESETS:
            raise InputError("preset", f"unknown ball preset {data['preset']!r}")
        return BALL_PRESETS[data["preset"]]
    _mapping(data, "", {"mass", "radius", "inertia_factor"}, ("mass", "radius"))
    return Ball(**data)


def _bat_from_dict(data, game=False) -> Bat:
    """A bat from ``{"preset": name}`` or a cylinder's values (a game bat also needs
    ``length`` and ``cm_from_knob``)."""
    if isinstance(data, dict) and "preset" in data:
        _mapping(data, "", {"preset"}, ())
        if data["preset"] not in BAT_PRESETS:
            raise InputError("preset", f"unknown bat preset {data['preset']!r} (expected one "
                             f"of: {', '.join(BAT_PRESETS)})")
        return bat_preset(data["preset"])
    keys = {"mass", "radius", "transverse_inertia", "axial_inertia"}
    required = ["mass", "radius", "transverse_inertia", "axial_inertia"]
    if game:
        keys |= {"length", "cm_from_knob"}
        required += ["length", "cm_from_knob"]
    _mapping(data, "", keys, required)
    values = {k: _game_value(v, k, _BAT_QUANTITIES[k]) for k, v in data.items()}
    if game:
        length = values["length"]
        cm = values.pop("cm_from_knob")
        if not 0.0 <= cm <= length:
            raise InputError("cm_from_knob", f"must lie on the bat, within [0, {length:.6g}] "
                             f"m, got {cm!r}")
        values["cm_from_barrel_end"] = length - cm
    return Bat(**values)


_BAT_QUANTITIES = {"mass": "mass", "radius": "length", "transverse_inertia": "inertia",
                   "axial_inertia": "inertia", "length": "length", "cm_from_knob": "length"}


def solve_any(case, settings: SolverSettings = SolverSettings(), *, json_keys=False):
    """:func:`solve` for an :class:`ImpactCase`, :func:`solve_game` for a :class:`GameCase`
    (with ``json_keys``, a game's errors name the JSON keys, ``pitch.speed``)."""
    if isinstance(case, GameCase):
        try:
            return solve_game(case, settings)
        except InputError as err:
            if json_keys and err.field in _GAME_KEYS:
                raise InputError(".".join(_GAME_KEYS[err.field]), err.message) from None
            raise
    return solve(case, settings)


def case_from_dict(data):
    """A :class:`GameCase` for a JSON case with ``pitch``/``swing`` keys, else an
    :class:`ImpactCase`."""
    return GameCase.from_dict(data) if is_game(data) else ImpactCase.from_dict(data)


# ---------------------------------------------------------------- batted-ball flight

_FT = 0.3048
_LAUNCH_KEYS = {"launch_speed": ("speed", None), "launch_angle": ("angle", None),
                "spray_angle": ("angle", 0.0), "backspin": ("spin", 0.0),
                "sidespin": ("spin", 0.0), "gyrospin": ("spin", 0.0)}


@dataclasses.dataclass(frozen=True)
class FlightCase:
    """One batted ball to fly: launch numbers (SI: m/s, rad, rad/s), the ball, and the
    flight settings (:class:`mcbat.study.flight.FlightSettings`: atmosphere, model, launch
    point, wind, scheme)."""

    launch_speed: float
    launch_angle: float
    spray_angle: float = 0.0
    backspin: float = 0.0
    sidespin: float = 0.0
    gyrospin: float = 0.0
    ball: Ball = BALL_PRESETS["baseball"]
    settings: FlightSettings = FlightSettings()

    def vectors(self):
        """Field-frame velocity (m/s) and spin (rad/s) at launch."""
        v, w = launch_vectors(self.launch_speed, self.launch_angle, self.spray_angle,
                              self.backspin, self.sidespin, self.gyrospin)
        return tuple(float(x) for x in v), tuple(float(x) for x in w)


@dataclasses.dataclass(frozen=True)
class FlightResult:
    """Where and when the ball lands (``hit_distance``, ``landing_x``, ``landing_y``,
    ``apex`` in ft as Statcast gives them; ``*_m`` in m; ``hang_time`` in s), and the
    sampled trajectory if asked for (t in s, x, y, z in m)."""

    hit_distance_m: float
    landing_x_m: float
    landing_y_m: float
    hang_time: float
    apex_m: float
    steps: int
    trajectory: dict | None = None

    @property
    def hit_distance(self) -> float:
        """Horizontal distance of the landing point from home plate (ft)."""
        return self.hit_distance_m / _FT

    def to_dict(self) -> dict:
        """JSON-ready dictionary (the output of ``mcbat flight``)."""
        out = {"hit_distance": self.hit_distance, "hang_time": self.hang_time,
               "apex": self.apex_m / _FT, "landing_x": self.landing_x_m / _FT,
               "landing_y": self.landing_y_m / _FT, "hit_distance_m": self.hit_distance_m,
               "apex_m": self.apex_m, "landing_x_m": self.landing_x_m,
               "landing_y_m": self.landing_y_m, "flight_steps": self.steps,
               "units": {"hit_distance": "ft", "hang_time": "s", "apex": "ft",
                         "landing_x": "ft", "landing_y": "ft", "hit_distance_m": "m",
                         "apex_m": "m", "landing_x_m": "m", "landing_y_m": "m"}}
        if self.trajectory is not None:
            out["trajectory"] = self.trajectory
        return out


def flight_case_from_dict(data) -> FlightCase:
    """A :class:`FlightCase` from a ``mcbat flight`` JSON object (values in SI or as
    ``{"value": ..., "unit": ...}``).

    Raises
    ------
    InputError
        Naming the key.
    """
    _mapping(data, "", set(_LAUNCH_KEYS) | {"ball"} | set(FLIGHT_KEYS), ("launch_speed",
                                                                        "launch_angle"))
    launch = {}
    for key, (quantity, default) in _LAUNCH_KEYS.items():
        value = _game_value(data[key], key, quantity) if key in data else default
        if not math.isfinite(value):
            raise InputError(key, f"must be a finite number, got {data[key]!r}")
        launch[key] = value
    if not launch["launch_speed"] > 0.0:
        raise InputError("launch_speed", f"must be > 0, got {data['launch_speed']!r}")
    if not abs(launch["launch_angle"]) <= math.pi / 2:
        raise InputError("launch_angle", "must be within [-90, 90] deg")
    ball = (BALL_PRESETS["baseball"] if "ball" not in data
            else parse_ball(data["ball"]))
    settings = parse_flight({k: v for k, v in data.items() if k in FLIGHT_KEYS}, field="")
    return FlightCase(ball=ball, settings=settings, **launch)


#: Most points of a sampled trajectory (``mcbat flight --trajectory DT``); a flight is also
#: sampled over at most its first 120 s.
MAX_TRAJECTORY_POINTS = 100_000


def solve_flight(case: FlightCase, trajectory: float | None = None) -> FlightResult:
    """Fly one ball with the flight kernel (the one studies use).

    ``trajectory`` (a time step, s, > 0): also sample the flight every that many seconds (and at the
    landing).

    Raises
    ------
    InputError
        Naming ``trajectory``, ``position`` for a launch that cannot fly, or
        ``landing_height`` for a ball that never rises to it.
    """
    v, w = case.vectors()
    params = case.settings.params(case.ball.mass, case.ball.radius)
    x = tuple(float(c) for c in case.settings.start)
    if trajectory is None:
        f, count, samples = flight_kernel(params, x, v, w), 0, None
    else:
        dt = _real(trajectory, "trajectory")
        if not dt > 0.0:
            raise InputError("trajectory", f"must be > 0 s, got {trajectory!r}")
        if case.settings.scheme == "sheet":
            raise InputError("trajectory", "not available with scheme = \"sheet\"")
        samples = np.empty((4, int(min(120.0 / dt, MAX_TRAJECTORY_POINTS)) + 2))
        f, count = integrate_flight(params, x, v, w, samples, dt)
    if f.status == 3:
        raise InputError("landing_height", "the ball never rises to the landing height: it "
                         "reaches the ground first")
    if f.status == 1:  # the launch point: below the ground, or not finite
        raise InputError("position", "the ball cannot fly from there (below the ground)")
    landing = (f.distance, f.landing_x, f.landing_y, f.hang_time, f.apex)
    if f.status != 0 or not all(math.isfinite(value) for value in landing):
        # A successful answer holds numbers only: a ball the model cannot carry (a
        # feather's mass, a balloon's radius, a launch near the speed of light) is the
        # input's fault, said so, not a null in the output. A ball that hovers (a 36 km
        # radius: drag far above its weight) runs out of steps before it lands: the same.
        raise InputError("launch_speed", f"the flight model has no finite landing for a "
                         f"{case.ball.mass:.3g} kg ball of radius {case.ball.radius:.3g} m "
                         f"launched at {case.launch_speed:.3g} m/s (ball.mass, ball.radius, "
                         "launch_speed): outside the range the model is made for")
    trajectory = None
    if samples is not None:
        if count and samples[0, count - 1] + dt < f.hang_time and count >= samples.shape[1]:
            needed = f.hang_time / dt
            raise InputError("trajectory", f"a {f.hang_time:.3g} s flight sampled every "
                             f"{dt:g} s needs {needed:,.0f} points, at most "
                             f"{MAX_TRAJECTORY_POINTS:,} (and 120 s of flight): choose a "
                             f"step of at least {f.hang_time / MAX_TRAJECTORY_POINTS:.2g} s")
        t, px, py, pz = (samples[i, :count].tolist() for i in range(4))
        if not t or t[-1] < f.hang_time:
            t, px, py, pz = (t + [f.hang_time], px + [f.landing_x], py + [f.landing_y],
                             pz + [0.0])
        trajectory = {"t": t, "x": px, "y": py, "z": pz}
    return FlightResult(hit_distance_m=float(f.distance), landing_x_m=float(f.landing_x),
                        landing_y_m=float(f.landing_y), hang_time=float(f.hang_time),
                        apex_m=float(f.apex), steps=int(f.steps), trajectory=trajectory)
