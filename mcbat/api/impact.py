"""One impact in the bat frame: build a case, solve it, read the result.

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
>>> result.to_dict()["units"]["normal_impulse"]
'kg m/s'

All quantities are SI (m, kg, s, rad), in the lab frame of ``docs/physics.md``: the bat CM
at the origin, ``z`` along the bat axis towards the barrel end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mcbat.api.contract import (
    bat_from_dict,
    check_object,
    impact_result_to_dict,
    located,
)
from mcbat.bodies import Ball, Bat
from mcbat.checks import check_real as _real
from mcbat.checks import check_vector as _vector
from mcbat.core import status as st
from mcbat.core.geometry import (
    angle_from_impact_parameter,
    contact_frame,
    impact_parameter_from_angle,
)
from mcbat.core.rigid_bodies import delassus_matrix, kinetic_energy, relative_contact_velocity
from mcbat.errors import InputError
from mcbat.solving import SolverSettings, impact_history, solve_one_impact
from mcbat.solving.derived import derive
from mcbat.solving.names import (
    INERTIA_RANGE,
    LENGTH_RANGE,
    MASS_RANGE,
    MAX_AXIAL,
    MAX_MU,
    MAX_SPEED,
    MAX_SPIN,
)

__all__ = ["MAX_AZIMUTH", "Contact", "ImpactCase", "ImpactResult", "SolverSettings",
           "Vector", "contact_problem", "history", "impact_case_from_dict", "solve"]

# SolverSettings is frozen: one default instance shared by every call is safe.
_DEFAULT_SETTINGS = SolverSettings()

Vector = tuple[float, float, float]
"""Three components ``(x, y, z)`` of a velocity (m/s) or a spin (rad/s)."""

#: The largest contact azimuth (rad) taken: beyond it the rounding of the angle itself
#: (above 1e-10 rad) moves the contact point more than the solver's tolerance.
MAX_AZIMUTH = 1e6


def _attr(case: ImpactCase, dotted: str) -> Any:
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

    def __post_init__(self) -> None:
        object.__setattr__(self, "axial", _real(self.axial, "axial"))
        object.__setattr__(self, "angle", _real(self.angle, "angle"))

    @classmethod
    def from_impact_parameter(cls, axial: float, impact_parameter: float, ball: Ball, bat: Bat,
                              approach_azimuth: float = 0.0) -> Contact:
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
class ImpactCase:
    """One impact: bodies, contact point, initial velocities (lab frame), friction, e*.

    ``e`` is Stronge's energetic coefficient ``e*`` in [0, 1]; the paper's loss fraction
    ``e^2`` corresponds to ``e* = sqrt(1 - e^2)`` (``e_from_loss_fraction``). ``e_x``
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

    def __post_init__(self) -> None:
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
        """Raise ``InputError`` naming the first input outside the range the solver
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
        """Raise ``InputError`` unless the contact points approach (``v_n < 0``)."""
        vn = self.normal_approach_speed()
        if not vn < 0.0:
            raise InputError("ball_velocity",
                             f"the bodies are not approaching at the contact "
                             f"(normal relative velocity v_n = {vn:.6g} m/s >= 0)")

    @classmethod
    def from_dict(cls, data: Any) -> ImpactCase:
        """Build a case from the JSON contract of ``mcbat impact`` (docs/impact.md): see
        ``impact_case_from_dict``."""
        return impact_case_from_dict(data)


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
        speed: float = derive(self.ball_velocity, self.ball_spin)["exit_speed"]
        return speed

    @property
    def scattering_angle(self) -> float:
        """``atan2(v_y, v_x)`` of the outgoing ball, degrees (0 = straight back along ``+x``)."""
        angle: float = derive(self.ball_velocity, self.ball_spin)["scattering_angle"]
        return angle

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

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (the output contract of ``mcbat impact``), with a ``units``
        block naming the unit of every quantity: see
        ``mcbat.api.contract.impact_result_to_dict``."""
        return impact_result_to_dict(self)


def solve(case: ImpactCase, settings: SolverSettings = _DEFAULT_SETTINGS) -> ImpactResult:
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
    out = solve_one_impact(physics, settings)
    code = int(out["status"])
    if code != st.OK:
        raise InputError(None, f"the solver cannot solve this impact (status "
                         f"{st.STATUS_NAMES[code]!r}: docs/errors.md lists what each status "
                         "means)")

    def vec(prefix: str) -> Vector:
        x, y, z = (float(out[f"{prefix}{c}"]) for c in "xyz")
        return x, y, z

    def optional(value: float) -> float | None:
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


def contact_problem(case: ImpactCase) -> dict[str, Any]:
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


def history(case: ImpactCase, impulses: ArrayLike,
            settings: SolverSettings = _DEFAULT_SETTINGS) -> dict[str, Any]:
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
    out, i_s = impact_history(K, v0, case.mu, impulses, settings)
    e_in = kinetic_energy(case.ball.mass, case.ball.radius, case.ball.inertia_factor,
                          case.bat.mass, case.bat.transverse_inertia, case.bat.axial_inertia,
                          case.ball_velocity, case.ball_spin, case.bat_velocity,
                          case.bat_spin)
    return {"I": impulses, "v1": out[:, 0], "v2": out[:, 1],
            "slip_speed": np.hypot(out[:, 0], out[:, 1]), "v_n": out[:, 2],
            "normal_work": out[:, 3], "friction_work": out[:, 4],
            "energy": e_in + out[:, 3] + out[:, 4], "phase": out[:, 5].astype(int),
            "stick_impulse": float(i_s), "energy_in": float(e_in)}


# ---- the JSON case of `mcbat impact` ----

_CASE_KEYS = {"ball", "bat", "contact", "ball_velocity", "ball_spin", "bat_velocity",
              "bat_spin", "mu", "restitution"}
_REQUIRED = ("ball", "bat", "contact", "ball_velocity", "mu")


def impact_case_from_dict(data: Any) -> ImpactCase:
    """A bat-frame case of ``mcbat impact`` (``docs/impact.md``; SI), checked against the
    solver's ranges and for bodies approaching at the contact."""
    check_object(data, "", _CASE_KEYS, _REQUIRED)
    ball_d = check_object(data["ball"], "ball", {"mass", "radius", "inertia_factor"},
                          ("mass", "radius"))
    ball = located("ball", Ball, **ball_d)
    if isinstance(data["bat"], dict) and "preset" in data["bat"]:
        bat = located("bat", bat_from_dict, data["bat"])
    else:
        bat_d = check_object(data["bat"], "bat",
                             {"mass", "radius", "transverse_inertia", "axial_inertia"},
                             ("mass", "radius", "transverse_inertia", "axial_inertia"))
        bat = located("bat", Bat, **bat_d)
    contact_d = check_object(data["contact"], "contact",
                             {"axial", "angle", "impact_parameter", "approach_azimuth"}, ("axial",))
    if ("angle" in contact_d) == ("impact_parameter" in contact_d):
        raise InputError("contact", "give exactly one of 'angle' or 'impact_parameter'")
    if "angle" in contact_d:
        if "approach_azimuth" in contact_d:
            raise InputError("contact.approach_azimuth", "only valid with 'impact_parameter'")
        contact = located("contact", Contact, **contact_d)
    else:
        axial = located("contact", _real, contact_d["axial"], "axial")
        contact = located("contact", Contact.from_impact_parameter, axial=axial,
                          impact_parameter=contact_d["impact_parameter"], ball=ball, bat=bat,
                          approach_azimuth=contact_d.get("approach_azimuth", 0.0))
    e, e_x = 1.0, 0.0
    if "restitution" in data:
        rest = dict(check_object(data["restitution"], "restitution",
                                 {"e", "loss_fraction", "e_x"}, ()))
        if "e_x" in rest:  # tangential restitution (optional; alone it keeps e* = 1)
            e_x = located("restitution", _real, rest.pop("e_x"), "e_x", minimum=0.0,
                          maximum=1.0)
        elif len(rest) != 1:
            raise InputError("restitution", "give exactly one of 'e' or 'loss_fraction'")
        if len(rest) > 1:
            raise InputError("restitution", "give exactly one of 'e' or 'loss_fraction'")
        if "e" in rest:
            e = located("restitution", _real, rest["e"], "e", minimum=0.0, maximum=1.0)
        elif "loss_fraction" in rest:
            e = located("restitution", ImpactCase.e_from_loss_fraction,
                        loss_fraction=rest["loss_fraction"])
    vectors = {k: data[k] for k in ("ball_velocity", "ball_spin", "bat_velocity", "bat_spin")
               if k in data}
    case = ImpactCase(ball=ball, bat=bat, contact=contact, mu=data["mu"], e=e, e_x=e_x,
                        **vectors)
    case.check_solver_ranges()
    case.validate_approach()
    return case
