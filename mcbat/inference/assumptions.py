"""What an inference assumes (``SpinAssumptions``: what the measurements leave open)
and how it iterates (``InferenceOptions``)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from mcbat.bodies import BALL_PRESETS, Ball, Bat, bat_preset
from mcbat.bodies.restitution import GAME_RESTITUTION, Restitution
from mcbat.bodies.swing import DEFAULT_PIVOT
from mcbat.checks import check_real as _real
from mcbat.core.units import M_S_PER_MPH, RAD_PER_DEG
from mcbat.errors import InputError
from mcbat.solving import SolverSettings
from mcbat.solving.inference import InferenceSettings
from mcbat.solving.names import SWEET_SPOT_FROM_BARREL_END

__all__ = ["InferenceOptions", "SpinAssumptions"]

_INCH = 0.0254


@dataclass(frozen=True)
class SpinAssumptions:
    """What the measurements leave open, assumed (SI: m, rad; defaults: the game
    presets, ``docs/batting.md``; their effect on the spin: ``docs/spin_inference.md``).

    ``attack_angle`` (rad) is used where the table has no measured one;
    ``vertical_bat_angle`` (rad, < 0 barrel below the hands) and ``pivot`` (m from the
    knob) always; ``from_barrel_end`` (m) where the bat speed is inferred: FITTED, the
    position at which the bat speeds inferred without a measured swing have the measured
    swings' median on tracked balls in play (10.9 in from the barrel end, toward the
    handle from the sweet spot: ``docs/spin_inference.md``, *Without a measured swing*).
    ``mu``,
    ``restitution`` (``e*`` and ``e_x``), the bat and ball; the pitch's
    ``spin_efficiency`` and ``gyro_sign``, and its ``spin_axis`` (rad, Statcast's
    convention) where the table has none. ``contact_side``: where the bat speed is
    measured, the launch speed has two contact positions, one on each side of its
    maximum along the bat: ``"handle"`` (default) or ``"end"``.

    The swing the data leave open is not one value but a distribution (the game presets'
    population, ``docs/spin_inference.md``): the reported spin is its mean over the
    attack angles that give the ball. ``attack_angle`` and ``attack_angle_sd`` (rad) are
    the population's mean and sd of the true attack angle (Statcast's bat-tracking mean,
    the presets' fitted sd); ``attack_angle_error`` (rad) the sd of a measured attack
    angle's error (2025 on), so that the true one given the measured ``m`` is
    ``N(mean + k (m - mean), k error^2)``, ``k = sd^2 / (sd^2 + error^2)``;
    ``undercut_mean`` and ``undercut_sd`` (m) the presets' fitted undercut, which weighs
    each attack angle by how likely the undercut it needs is, with the attack direction's
    ``attack_direction_sd`` and, where the bat speed is inferred, its ``bat_speed_mean``
    and ``bat_speed_sd``, else the contact position's ``from_barrel_end_mean`` and
    ``from_barrel_end_sd`` (the presets' population about the sweet spot). With
    ``InferenceOptions.attack_angle_nodes = 1`` the attack angle is taken as exact
    (measured, else ``attack_angle``) and these are not used.
    """

    bat: Bat = dataclasses.field(default_factory=lambda: bat_preset("r161"))
    ball: Ball = BALL_PRESETS["baseball"]
    attack_angle: float = 10.0 * RAD_PER_DEG
    vertical_bat_angle: float = -30.0 * RAD_PER_DEG
    pivot: float = DEFAULT_PIVOT
    from_barrel_end: float = 10.9 * _INCH
    mu: float = 0.5
    restitution: Restitution = GAME_RESTITUTION
    spin_efficiency: float = 1.0
    gyro_sign: float = 1.0
    spin_axis: float = math.pi
    contact_side: str = "handle"
    attack_angle_sd: float = 8.2 * RAD_PER_DEG
    attack_angle_error: float = 5.0 * RAD_PER_DEG
    undercut_mean: float = 0.24 * _INCH
    undercut_sd: float = 0.94 * _INCH
    attack_direction_sd: float = 8.0 * RAD_PER_DEG
    bat_speed_mean: float = 69.5 * M_S_PER_MPH
    bat_speed_sd: float = 6.3 * M_S_PER_MPH
    from_barrel_end_sd: float = 4.6 * _INCH
    from_barrel_end_mean: float = SWEET_SPOT_FROM_BARREL_END

    def __post_init__(self):
        bat = self.bat
        if bat.length is None or bat.cm_from_barrel_end is None:
            raise InputError("bat", "needs the bat's length and CM (cm_from_knob), or a "
                             "bat preset")
        for name in ("attack_angle", "vertical_bat_angle"):
            value = _real(getattr(self, name), name)
            if not abs(value) < math.pi / 2:
                raise InputError(name, f"must lie within (-90, 90) deg, got "
                                 f"{math.degrees(value):.6g} deg (angles are in rad)")
        sweet = bat.length - SWEET_SPOT_FROM_BARREL_END
        if not 0.0 <= _real(self.pivot, "pivot") < sweet:
            raise InputError("pivot", f"must lie between the knob and the sweet spot "
                             f"([0, {sweet:.4g}) m from the knob), got {self.pivot!r}")
        for name in ("from_barrel_end", "from_barrel_end_mean"):
            if not 0.0 <= _real(getattr(self, name), name) <= sweet:
                raise InputError(name, f"must lie within [0, {sweet:.4g}] m, got "
                                 f"{getattr(self, name)!r}")
        _real(self.mu, "mu", minimum=0.0)
        _real(self.spin_efficiency, "spin_efficiency", minimum=0.0, maximum=1.0)
        if self.gyro_sign not in (1, -1):
            raise InputError("gyro_sign", f"must be +1 or -1, got {self.gyro_sign!r}")
        _real(self.spin_axis, "spin_axis")
        _real(self.attack_angle_sd, "attack_angle_sd", minimum=0.0)
        _real(self.attack_angle_error, "attack_angle_error", minimum=0.0)
        _real(self.undercut_mean, "undercut_mean")
        _real(self.undercut_sd, "undercut_sd", positive=True)
        _real(self.attack_direction_sd, "attack_direction_sd", positive=True)
        _real(self.bat_speed_mean, "bat_speed_mean", positive=True)
        _real(self.bat_speed_sd, "bat_speed_sd", positive=True)
        _real(self.from_barrel_end_sd, "from_barrel_end_sd", positive=True)
        if self.contact_side not in ("handle", "end"):
            raise InputError("contact_side", f'must be "handle" or "end", got '
                             f"{self.contact_side!r}")

    def config(self) -> dict:
        """As plain data (for ``df.attrs``): angles in deg, lengths in m."""
        return {"bat": self.bat.preset or "custom", "ball": "custom" if self.ball !=
                BALL_PRESETS["baseball"] else "baseball",
                "attack_angle_deg": math.degrees(self.attack_angle),
                "vertical_bat_angle_deg": math.degrees(self.vertical_bat_angle),
                "pivot_m": self.pivot, "from_barrel_end_m": self.from_barrel_end,
                "mu": self.mu, "restitution": self.restitution.config(),
                "spin_efficiency": self.spin_efficiency, "gyro_sign": self.gyro_sign,
                "spin_axis_deg": math.degrees(self.spin_axis),
                "contact_side": self.contact_side,
                "attack_angle_sd_deg": math.degrees(self.attack_angle_sd),
                "attack_angle_error_deg": math.degrees(self.attack_angle_error),
                "undercut_mean_m": self.undercut_mean, "undercut_sd_m": self.undercut_sd,
                "attack_direction_sd_deg": math.degrees(self.attack_direction_sd),
                "bat_speed_mean_mph": self.bat_speed_mean / M_S_PER_MPH,
                "bat_speed_sd_mph": self.bat_speed_sd / M_S_PER_MPH,
                "from_barrel_end_sd_m": self.from_barrel_end_sd,
                "from_barrel_end_mean_m": self.from_barrel_end_mean}


@dataclass(frozen=True)
class InferenceOptions:
    """The Newton iteration (``mcbat/core/contact_inference/README.md``): at most
    ``max_iterations``; converged when the launch speed is matched to ``tolerance``
    (relative) and the angles to ``tolerance`` rad; the impact kernel's accuracy,
    ``solver`` (``mcbat.SolverSettings``, the one type every caller of the kernels uses);
    the unknowns' bounds: bat speed (mph), attack direction (deg), contact position (m
    from the barrel end), and the contact azimuth ``|theta|`` (deg; the undercut is
    ``reach sin(theta)``).

    Measured swings: ``bat_speed_floor`` (mph): a measured bat speed below it is no full
    swing (a bunt, a check swing) and the row gets ``unusable_swing``;
    ``bat_speed_error`` (mph): how far the bat speed may be moved from the measured one
    when no contact position along the bat gives the ball at the measured speed (the
    nearest bat speed that does is taken, and the move reported as
    ``bat_speed_adjustment``); beyond it the ball is ``bat_speed_inconsistent``. 0: the
    measured bat speed is taken as exact (``docs/spin_inference.md``).

    ``attack_angle_nodes``: Gauss-Hermite nodes of the attack angle's distribution
    (``SpinAssumptions``) over which the spin is averaged; 1: the attack angle taken
    as exact (the measured one, else the assumed one), as a round trip needs."""

    max_iterations: int = 30
    tolerance: float = 1e-9
    solver: SolverSettings = SolverSettings()
    bat_speed_range: tuple[float, float] = (25.0, 110.0)
    attack_direction_max: float = 80.0
    from_barrel_end_range: tuple[float, float] = (0.0, 0.55)
    contact_angle_max: float = 60.0
    bat_speed_floor: float = 40.0
    bat_speed_error: float = 5.0
    attack_angle_nodes: int = 5

    def __post_init__(self):
        if not isinstance(self.solver, SolverSettings):
            raise InputError("solver", f"must be a SolverSettings, got "
                             f"{type(self.solver).__name__}")
        if not (isinstance(self.max_iterations, int) and 1 <= self.max_iterations <= 1000):
            raise InputError("max_iterations", f"must be an integer in [1, 1000], got "
                             f"{self.max_iterations!r}")
        if not 0.0 < _real(self.tolerance, "tolerance") < 1e-3:
            raise InputError("tolerance", f"must lie in (0, 1e-3), got {self.tolerance!r}")
        lo, hi = (_real(v, "bat_speed_range") for v in self.bat_speed_range)
        if not 0.0 < lo < hi:
            raise InputError("bat_speed_range", f"must be 0 < low < high mph, got "
                             f"{self.bat_speed_range!r}")
        lo, hi = (_real(v, "from_barrel_end_range") for v in self.from_barrel_end_range)
        if not 0.0 <= lo < hi:
            raise InputError("from_barrel_end_range", f"must be 0 <= low < high m, got "
                             f"{self.from_barrel_end_range!r}")
        if not 0.0 < _real(self.attack_direction_max, "attack_direction_max") < 90.0:
            raise InputError("attack_direction_max", "must lie in (0, 90) deg")
        if not 0.0 < _real(self.contact_angle_max, "contact_angle_max") < 90.0:
            raise InputError("contact_angle_max", "must lie in (0, 90) deg")
        _real(self.bat_speed_floor, "bat_speed_floor", minimum=0.0)
        _real(self.bat_speed_error, "bat_speed_error", minimum=0.0)
        if not (isinstance(self.attack_angle_nodes, int)
                and 1 <= self.attack_angle_nodes <= 21):
            raise InputError("attack_angle_nodes", f"must be an integer in [1, 21], got "
                             f"{self.attack_angle_nodes!r}")

    def kernel_settings(self, contact_side: str) -> InferenceSettings:
        """As the jitted kernel's named tuple (SI)."""
        return InferenceSettings(
            int(self.max_iterations), float(self.tolerance), int(self.solver.steps),
            float(self.solver.tolerance), int(self.solver.max_steps),
            1.0 if contact_side == "handle" else -1.0,
            float(self.bat_speed_range[0]) * M_S_PER_MPH,
            float(self.bat_speed_range[1]) * M_S_PER_MPH,
            float(self.attack_direction_max) * RAD_PER_DEG, float(self.from_barrel_end_range[0]),
            float(self.from_barrel_end_range[1]), float(self.contact_angle_max) * RAD_PER_DEG)

