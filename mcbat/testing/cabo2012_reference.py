"""Slow, independent reference integrator for one rigid ball-bat impact (tests only).

This module re-solves the impact of :func:`mcbat.core.cabo2012.solve_impact` in a
deliberately different formulation, so that the two can check each other:

* the state is the twelve body velocities ``(v_p, w_p, v_b, w_b)`` plus the normal and
  friction works ``W_n``, ``W_fr`` (not the impulse in the contact basis);
* the impulse rate ``dP/dI`` on the ball is applied through the masses and inertias directly
  (no Delassus matrix in the equations of motion);
* the stick rate and the re-slip direction use an impulse-to-velocity map ``K`` obtained
  numerically, by applying unit impulses to the bodies;
* the integration is adaptive (``scipy.integrate.solve_ivp``, DOP853) with event location,
  in the normal impulse ``I`` (kg m/s), and in the slip-scaled time ``tau`` only for the
  last ``1e-10`` of the slip speed before it stops.

It imports nothing from the kernel (``contact``, ``rigid_bodies``, ``geometry``) and uses only
numpy and scipy. Production code never calls it; it is far too slow for sampling.

The model is the matrix form of ``docs/physics.md``: Coulomb friction, stick when the holding rate
``|f| <= mu``, re-slip along ``u*`` otherwise, and Stronge's energetic restitution
``W_n(I_f) = (1 - e*^2) W_c``.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = ["MAX_SEGMENTS", "RESLIP_SAMPLES", "SLIP_STOP_FRACTION", "TAU_STOP_RATIO",
           "reference_impact"]

# Slip speed (relative to |v(0)|) at which the integration in I stops. |v_t| falls linearly
# into the stick point, so a threshold event finds it without touching the singular rate
# (a second event on minima of |v_t| catches steps that jump over the threshold). It is
# also the definition of a stop shared with the kernel (its SLIP_RESOLUTION): slip that
# starts below it, or whose speed has a minimum below it, has stopped there.
SLIP_STOP_FRACTION = 1e-10
# From there the approach to stick goes on in the slip-scaled time tau (dI = |v_t| dtau),
# where |v_t| decays smoothly (exponentially), down to this fraction of the threshold; only
# the rest is extrapolated linearly. The slip direction still turns at the threshold, so a
# linear extrapolation from it alone would err by ~1e-10 of I_s (it did: 3.6e-10).
TAU_STOP_RATIO = 1e-6
# Samples of the azimuth scan that brackets the re-slip directions before brentq.
RESLIP_SAMPLES = 3600
# Safety cap on the number of chained solve_ivp segments (phase changes + events).
MAX_SEGMENTS = 50


def _cross(a, b):
    """Cross product of two 3-vectors (np.cross is ~10x slower on tiny arrays)."""
    return np.array([a[1] * b[2] - a[2] * b[1],
                     a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _frame(axial, angle, radius, slope):
    """Contact basis and contact point, re-derived with numpy.

    Parameters
    ----------
    axial : float
        Axial position of the contact from the bat CM, m.
    angle : float
        Azimuth of the contact point, rad.
    radius : float
        Bat radius at the contact, m.
    slope : float
        Profile slope dr/dz (dimensionless).

    Returns
    -------
    t1, t2, t3, r_c : numpy.ndarray
        Azimuthal tangent, meridional tangent, outward normal (unit), contact point (m).
    """
    e_r = np.array([math.cos(angle), math.sin(angle), 0.0])
    k = np.array([0.0, 0.0, 1.0])
    # Surface point (r(z) e_r, z): the tangent along z is r' e_r + k, the azimuthal one
    # e_phi = k x e_r; the outward normal is perpendicular to both.
    t1 = _cross(k, e_r)
    meridian = slope * e_r + k
    t2 = meridian / np.linalg.norm(meridian)
    t3 = _cross(t1, t2)
    r_c = radius * e_r + axial * k
    return t1, t2, t3, r_c


class _Bodies:
    """Masses, inertias and contact geometry; maps impulse rates to velocity rates."""

    def __init__(self, ball_mass, ball_radius, ball_inertia_factor, bat_mass,
                 bat_transverse_inertia, bat_axial_inertia, t3, r_c):
        self.m_p = float(ball_mass)
        self.i_p = float(ball_inertia_factor) * self.m_p * float(ball_radius) ** 2
        self.m_b = float(bat_mass)
        # Bat inertia is diagonal in the lab frame (z along the bat axis).
        self.i_b_inv = 1.0 / np.array(
            [bat_transverse_inertia, bat_transverse_inertia, bat_axial_inertia], dtype=float)
        self.rho = -float(ball_radius) * t3  # contact point from the ball centre
        self.r_c = r_c

    def velocity_rates(self, p_rate):
        """Rates of ``(v_p, w_p, v_b, w_b)`` (12,) for impulse rate ``p_rate`` on the ball."""
        out = np.empty(12)
        out[0:3] = p_rate / self.m_p
        out[3:6] = _cross(self.rho, p_rate) / self.i_p
        out[6:9] = -p_rate / self.m_b
        out[9:12] = -self.i_b_inv * _cross(self.r_c, p_rate)
        return out

    def relative_velocity(self, y):
        """Relative velocity (m/s) of the ball's contact point with respect to the bat's."""
        return (y[0:3] + _cross(y[3:6], self.rho)
                - y[6:9] - _cross(y[9:12], self.r_c))

    def energy(self, y):
        """Kinetic energy (J) of both bodies."""
        return 0.5 * (self.m_p * y[0:3] @ y[0:3] + self.i_p * y[3:6] @ y[3:6]
                      + self.m_b * y[6:9] @ y[6:9] + (y[9:12] ** 2 / self.i_b_inv).sum())


def _numerical_k(bodies, basis):
    """Impulse-to-velocity map in the contact basis, from unit impulses.

    The relative velocity is linear in the body velocities, which are linear in the
    impulse, so applying each unit impulse to zero velocities gives the column of ``K``
    exactly (no difference of large numbers).

    Returns
    -------
    numpy.ndarray
        (3, 3) matrix, rows and columns in the basis ``(t1, t2, t3)``, units 1/kg.
    """
    k = np.empty((3, 3))
    for j in range(3):
        y = np.zeros(14)
        y[:12] = bodies.velocity_rates(basis[j])
        k[:, j] = basis @ bodies.relative_velocity(y)
    return k


def _reslip_direction(k, mu):
    """Unit direction ``u*`` (2,) with ``K_tn - mu K_tt u* = lambda u*``, largest lambda > 0.

    Scans the azimuth of ``u`` for sign changes of the 2D cross product ``u x g(u)``,
    ``g = K_tn - mu K_tt u``, refines each with brentq and keeps the roots with
    ``u . g > 0``. Returns None if there is none.
    """
    k_tt = k[:2, :2]
    k_tn = k[:2, 2]

    def g(phi):
        return k_tn - mu * k_tt @ np.array([math.cos(phi), math.sin(phi)])

    def cross(phi):
        gv = g(phi)
        return math.cos(phi) * gv[1] - math.sin(phi) * gv[0]

    phis = np.linspace(0.0, 2.0 * math.pi, RESLIP_SAMPLES + 1)
    u_all = np.array([np.cos(phis), np.sin(phis)])
    g_all = k_tn[:, None] - mu * (k_tt @ u_all)
    values = u_all[0] * g_all[1] - u_all[1] * g_all[0]
    roots = []
    for a, b, fa, fb in zip(phis[:-1], phis[1:], values[:-1], values[1:]):
        if fa == 0.0:
            roots.append(a)
        elif fa * fb < 0.0:
            roots.append(brentq(cross, a, b, xtol=1e-15, rtol=4.0 * np.finfo(float).eps,
                                 maxiter=200))
    best, best_lambda = None, 0.0
    for phi in roots:
        u = np.array([math.cos(phi), math.sin(phi)])
        lam = float(u @ g(phi))
        if lam > best_lambda:
            best, best_lambda = u, lam
    return best


def _integrate(rhs, span, y, events, rtol, atol):
    """``solve_ivp`` (DOP853) over ``span`` with terminal ``events``: ``(t, y, name)`` at the
    earliest event that fired, or at the end of the span with ``name`` None."""
    sol = solve_ivp(rhs, span, y, method="DOP853", events=events, rtol=rtol, atol=atol)
    if sol.status == -1:
        raise RuntimeError(f"solve_ivp failed: {sol.message}")
    if sol.status == 0:
        return sol.t[-1], sol.y[:, -1], None
    fired = [(te[0], j) for j, te in enumerate(sol.t_events) if len(te)]
    t, j = min(fired)
    return t, sol.y_events[j][0], events[j].__name__


def reference_impact(ball_mass, ball_radius, ball_inertia_factor, bat_mass,
                     bat_transverse_inertia, bat_axial_inertia, axial, angle, radius, slope,
                     ball_v, ball_w, bat_v, bat_w, mu, e, e_x=0.0, rtol=1e-12, atol=1e-15,
                     slip_stop_fraction=None, stop_definition_fraction=None):
    """Solve one rigid ball-bat impact by adaptive integration of the body velocities.

    Parameters
    ----------
    ball_mass, ball_radius, ball_inertia_factor : float
        Ball mass (kg), radius (m) and ``f`` in ``I_p = f m_p R^2``.
    bat_mass, bat_transverse_inertia, bat_axial_inertia : float
        Bat mass (kg) and principal moments about its CM (kg m^2).
    axial, angle, radius, slope : float
        Contact point: axial position from the bat CM (m), azimuth (rad), bat radius
        there (m), profile slope dr/dz (dimensionless).
    ball_v, ball_w, bat_v, bat_w : sequence of 3 floats
        Initial velocities (m/s) and spins (rad/s), lab frame.
    mu : float
        Coulomb friction coefficient (>= 0).
    e : float
        Energetic coefficient of restitution ``e*`` in [0, 1].
    e_x : float
        Tangential restitution (Cross & Nathan 2006) in [0, 1]; applied within the stick
        phase of a contact that ends stuck by :func:`_tangential_rebound` (see
        ``mcbat/core/cross_nathan2006/README.md``).
    rtol, atol : float
        Tolerances of ``solve_ivp`` (DOP853).
    slip_stop_fraction : float, optional
        Slip speed, relative to ``|v(0)|``, at which the integration in ``I`` ends; the
        approach to stick goes on in ``tau`` (``dI = |v_t| dtau``) down to
        :data:`TAU_STOP_RATIO` times it, and only the rest is extrapolated linearly;
        default :data:`SLIP_STOP_FRACTION`. Varying it shows how much the switch
        contributes to ``I_s``. At most ``stop_definition_fraction``.
    stop_definition_fraction : float, optional
        Slip speed, relative to ``|v(0)|``, below which slip that starts there, or whose
        speed passes a minimum there, has stopped (then stick or re-slip); above it a
        minimum is a near miss and slip goes on. Default :data:`SLIP_STOP_FRACTION`, the
        kernel's definition (``SLIP_RESOLUTION``).

    Returns
    -------
    dict
        ``status`` ("ok" or "not_approaching"), ``end_state`` ("stuck" or "sliding"),
        ``ball_v``, ``ball_w``, ``bat_v``, ``bat_w`` (numpy arrays, m/s and rad/s),
        ``normal_impulse`` ``I_f`` (kg m/s), ``stick_impulse`` (kg m/s, 0.0 when the impact
        starts with no slip, None if slip never stops), ``compression_impulse`` ``I_c``
        (kg m/s), ``compression_work`` ``W_c``, ``normal_work`` ``W_n(I_f)``,
        ``friction_work`` ``W_fr(I_f)``, ``normal_work_at_stick`` ``W_n(I_s)`` (NaN when
        slip never stops; the paper's stick criterion is ``C = -W_n(I_s)``), ``energy_in``,
        ``energy_out`` (J), and ``phases``
        (list of "slip", "stick", "reslip", "frictionless", in order); for diagnostics,
        ``slip_near_misses`` lists ``(I, |v_t|)`` at minima of the slip speed that stay
        above the stick threshold.
    """
    t1, t2, t3, r_c = _frame(axial, angle, radius, slope)
    basis = np.array([t1, t2, t3])
    bodies = _Bodies(ball_mass, ball_radius, ball_inertia_factor, bat_mass,
                     bat_transverse_inertia, bat_axial_inertia, t3, r_c)
    mu = float(mu)
    e = float(e)

    # State: ball and bat velocities (12), W_n, W_fr, and the slip v_t in (t1, t2) (2).
    # The slip is also carried as its own state so that the error control holds it to
    # rtol *relative to |v_t|*: recomputed from the body velocities it would be a
    # difference of numbers ~|v| with an absolute error ~rtol |v|, and its direction noise
    # near the stick point (the rate is singular there) would decide I_s.
    y0 = np.zeros(16)
    y0[0:3], y0[3:6], y0[6:9], y0[9:12] = ball_v, ball_w, bat_v, bat_w
    v0 = bodies.relative_velocity(y0)
    y0[14:16] = basis[:2] @ v0
    speed0 = float(np.linalg.norm(v0))
    energy_in = bodies.energy(y0)
    if not v0 @ t3 < 0.0:
        return dict(status="not_approaching", end_state="sliding", ball_v=y0[0:3].copy(),
                    ball_w=y0[3:6].copy(), bat_v=y0[6:9].copy(), bat_w=y0[9:12].copy(),
                    normal_impulse=0.0, stick_impulse=None, compression_impulse=0.0,
                    compression_work=0.0, normal_work=0.0, friction_work=0.0,
                    normal_work_at_stick=math.nan, energy_in=energy_in,
                    energy_out=energy_in, phases=[], slip_near_misses=[])

    k = _numerical_k(bodies, basis)
    # Generous bound on the impulse of one segment; segments are chained until separation.
    span = 1e3 * speed0 / np.linalg.eigvalsh(0.5 * (k + k.T))[0]
    if slip_stop_fraction is None:
        slip_stop_fraction = SLIP_STOP_FRACTION
    if stop_definition_fraction is None:
        stop_definition_fraction = SLIP_STOP_FRACTION
    if not slip_stop_fraction <= stop_definition_fraction:
        raise ValueError("slip_stop_fraction must be at most stop_definition_fraction "
                         "(minima below the hand-over to tau are stops)")
    slip_stop = slip_stop_fraction * speed0  # hand-over to tau
    stopped = stop_definition_fraction * speed0  # the definition of a stop
    atol_all = np.full(16, atol)
    atol_all[14:16] = min(atol, 1e-3 * slip_stop)

    def velocity_change(p):
        """Change of the relative velocity (m/s) for an impulse ``p`` (lab, kg m/s)."""
        yy = np.zeros(14)
        yy[:12] = bodies.velocity_rates(p)
        return bodies.relative_velocity(yy)

    def tangential(y):
        return bodies.relative_velocity(y), y[14] * t1 + y[15] * t2

    def make_rhs(rate_fn):
        """Rhs of the 14-state for a tangential impulse rate ``rate_fn(v_t)`` (lab, 3,)."""
        def rhs(_, y):
            v, v_t = tangential(y)
            q = rate_fn(v_t)
            out = np.empty(16)
            out[:12] = bodies.velocity_rates(t3 + q)
            out[12] = v @ t3        # dW_n/dI = v_n
            out[13] = v_t @ q       # dW_fr/dI = v_t . (tangential rate)
            out[14:16] = basis[:2] @ velocity_change(t3 + q)
            return out
        return rhs

    def slip_rate(v_t):
        return -mu * v_t / np.linalg.norm(v_t)

    def constant_rate(q):
        return lambda _v_t: q

    def stick_or_reslip():
        """Phase and tangential rate (lab) once |v_t| = 0."""
        f = -np.linalg.solve(k[:2, :2], k[:2, 2])
        if np.linalg.norm(f) <= mu:
            return "stick", f[0] * t1 + f[1] * t2
        u = _reslip_direction(k, mu)
        if u is None:
            raise RuntimeError("no re-slip direction")
        return "reslip", -mu * (u[0] * t1 + u[1] * t2)

    # Initial phase.
    _, vt0 = tangential(y0)
    stick_impulse = None
    work_at_stick = math.nan  # W_n (J) where slip stops
    y_stick = None  # the state where slip stops (the start of the stick phase)
    if mu == 0.0:
        phase, rate = "frictionless", constant_rate(np.zeros(3))
    elif np.linalg.norm(vt0) <= stopped:
        stick_impulse, work_at_stick, y_stick = 0.0, 0.0, y0
        phase, q = stick_or_reslip()
        rate = constant_rate(q)
    else:
        phase, rate = "slip", slip_rate
    phases = [phase]

    # Rate of change of |v_t| during slip (1/kg * kg m/s -> m/s per kg m/s).
    def slip_speed_rate(yy):
        _, v_t = tangential(yy)
        u = v_t / np.linalg.norm(v_t)
        return u @ velocity_change(t3 - mu * u)

    def approach_in_tau(imp, y, compressed, i_c, w_c):
        """Slip from the threshold to TAU_STOP_RATIO times it, in tau, where every rate is
        ``|v_t|`` times its rate in ``I`` and ``I`` itself is a state. Returns
        ``(I, y, compressed, I_c, W_c, outcome)``, outcome "stop" (at the final speed: the
        rest is linear), "minimum" (of ``|v_t|``: slip stops there) or "separated".

        The states are the changes since the threshold (of ``I``, the body velocities and
        the works) plus the slip itself: the error control is then relative to how much
        each of them moves here, not to its whole size (``I`` and the velocities change by
        ~1e-10 of themselves in this stretch, less than rtol would resolve).
        """
        rate = slip_speed_rate(y)  # d|v_t|/dI = d ln|v_t| / dtau
        if not rate < 0.0:
            return imp, y, compressed, i_c, w_c, "minimum"
        final = TAU_STOP_RATIO * math.hypot(y[14], y[15])
        slip_rhs = make_rhs(slip_rate)
        base = y.copy()
        base[14:16] = 0.0  # the slip is carried whole

        def whole(zz):
            return base + zz[:16], imp + zz[16]

        def rhs(_, zz):
            yy, ii = whole(zz)
            s = math.hypot(zz[14], zz[15])
            out = np.empty(17)
            out[:16] = s * slip_rhs(ii, yy)
            out[16] = s
            return out

        def ev_stop(_, zz):
            return math.hypot(zz[14], zz[15]) - final
        ev_stop.terminal, ev_stop.direction = True, -1.0

        def ev_min(_, zz):
            return slip_speed_rate(whole(zz)[0])
        ev_min.terminal, ev_min.direction = True, 1.0

        def ev_compression(_, zz):
            return bodies.relative_velocity(whole(zz)[0]) @ t3
        ev_compression.terminal, ev_compression.direction = True, 1.0

        # Error control relative to the changes: atol rtol times a thousandth of what each
        # state changes by over the stretch (~|v_t| / -rate of impulse at the start's rates),
        # at least a hundredth of the largest change (states that barely move would
        # otherwise ask for steps at the rounding level).
        d_imp = math.hypot(y[14], y[15]) / -rate
        change = np.abs(np.append(slip_rhs(imp, y), 1.0)) * d_imp
        atol_tau = 1e-3 * rtol * np.maximum(change, 1e-2 * change.max())
        atol_tau[14:16] = 1e-3 * final
        # Exponential decay at about ``rate``: ten times the tau it takes is ample (if the
        # decay slows down, further segments follow).
        span = 10.0 * math.log(1.0 / TAU_STOP_RATIO) / -rate
        zz = np.zeros(17)
        zz[14:16] = y[14:16]
        outcome = "stop"
        for _ in range(MAX_SEGMENTS):
            # A minimum of |v_t| below the threshold is where slip stops, as in I: in tau
            # the slip cannot pass through zero, and where stick fails (re-slip) it turns
            # there into the re-slip direction and grows again.
            events = [ev_stop, ev_min]
            if not compressed:
                events.append(ev_compression)
            else:
                target = (1.0 - e * e) * w_c

                def ev_separation(_, zz):
                    return whole(zz)[0][12] - target
                ev_separation.terminal, ev_separation.direction = True, 1.0
                events.append(ev_separation)
            _, zz, name = _integrate(rhs, (0.0, span), zz, events, rtol, atol_tau)
            if name is None:  # not yet at the final speed (the decay slowed): go on
                continue
            if name == "ev_compression":
                yy, ii = whole(zz)
                compressed, i_c, w_c = True, ii, yy[12]
                if e == 0.0:
                    outcome = "separated"
                    break
                continue
            outcome = dict(ev_stop="stop", ev_min="minimum", ev_separation="separated")[name]
            break
        else:
            raise RuntimeError("too many integration segments in tau")
        yy, ii = whole(zz)
        return ii, yy, compressed, i_c, w_c, outcome

    imp, y = 0.0, y0
    compressed, i_c, w_c = False, None, None
    near_misses = []  # (I, |v_t|) of slip minima that stay clear of zero
    push_until = None  # end of a short segment without the minimum event
    for _ in range(MAX_SEGMENTS):
        events = []
        if not compressed:
            def ev_compression(_, yy):
                return bodies.relative_velocity(yy) @ t3
            ev_compression.terminal, ev_compression.direction = True, 1.0
            events.append(ev_compression)
        else:
            target = (1.0 - e * e) * w_c

            def ev_separation(_, yy):
                return yy[12] - target
            ev_separation.terminal, ev_separation.direction = True, 1.0
            events.append(ev_separation)
        if phase == "slip":
            def ev_slip_stop(_, yy):
                return np.linalg.norm(tangential(yy)[1]) - slip_stop
            ev_slip_stop.terminal, ev_slip_stop.direction = True, -1.0
            events.append(ev_slip_stop)
            if push_until is None:
                # solve_ivp only compares event signs at step ends, so a step can straddle
                # the V of |v_t| passing through zero (re-slip region) with both ends above
                # the threshold. A minimum of |v_t| is a +1 crossing of d|v_t|/dI.
                def ev_slip_min(_, yy):
                    return slip_speed_rate(yy)
                ev_slip_min.terminal, ev_slip_min.direction = True, 1.0
                events.append(ev_slip_min)

        end = imp + span if push_until is None else push_until
        push_until = None
        imp, y, name = _integrate(make_rhs(rate), (imp, end), y, events, rtol, atol_all)
        if name is None:  # no event inside the span: continue from its end
            continue
        if name == "ev_compression":
            compressed, i_c, w_c = True, imp, y[12]
            if e == 0.0:  # all stored energy lost: separation at I_c
                break
        elif name == "ev_separation":
            break
        elif name == "ev_slip_min":
            speed_t = np.linalg.norm(tangential(y)[1])
            if speed_t > stopped:
                # Near miss: slip goes on. Step past the minimum without this event (it
                # would fire again at once); |v_t| cannot reach zero within
                # speed_t / max|dv/dI|, and max|dv/dI| <= ||K|| sqrt(1 + mu^2).
                near_misses.append((float(imp), float(speed_t)))
                max_rate = np.linalg.norm(k, 2) * math.hypot(1.0, mu)
                push_until = imp + 0.5 * speed_t / max_rate
                continue
            # |v_t| went through zero in a step
            stick_impulse, work_at_stick, y_stick = imp, y[12], y
            phase, q = stick_or_reslip()
            rate = constant_rate(q)
            phases.append(phase)
        else:  # slip reached the threshold: the rest of the approach in tau
            imp, y, compressed, i_c, w_c, outcome = approach_in_tau(
                imp, y, compressed, i_c, w_c)
            if outcome == "separated":
                break
            v, v_t = tangential(y)
            speed_t = np.linalg.norm(v_t)
            u = v_t / speed_t
            dv = velocity_change(t3 - mu * u)
            d_speed = u @ dv  # d|v_t|/dI (u is tangential)
            if outcome == "stop" and d_speed < 0.0:
                # Linear extrapolation over the last stretch of slip: the impulse rate is
                # constant there, so the velocities are linear in I.
                d_imp = speed_t / -d_speed
                rhs = make_rhs(slip_rate)(imp, y)
                rhs[13] *= 0.5  # |v_t| falls linearly to zero: the mean of -mu |v_t|
                y_end = y + d_imp * rhs
                # v_n is linear too: W_n gains the mean of its two ends. (Its value at the
                # start alone is off by ~K_33 d_imp^2 / 2, which reached 1e-8 E_in when slip
                # creeps to a stop: d_imp = 1e-10 |v(0)| / |d|v_t|/dI| is then not small.)
                vn_start, vn_end = v @ t3, bodies.relative_velocity(y_end) @ t3
                y_end[12] = y[12] + 0.5 * d_imp * (vn_start + vn_end)
                ends_compression = not compressed and vn_end >= 0.0
                if ends_compression:
                    # Compression ended inside the extrapolated stretch, where v_n = 0.
                    d_c = (d_imp * -vn_start / (vn_end - vn_start) if vn_end > vn_start
                           else 0.0)
                    compressed, i_c, w_c = True, imp + d_c, y[12] + 0.5 * d_c * vn_start
                y = y_end
                imp += d_imp
                if ends_compression and e == 0.0:
                    stick_impulse, work_at_stick, y_stick = imp, y[12], y
                    break
            stick_impulse, work_at_stick, y_stick = imp, y[12], y
            phase, q = stick_or_reslip()
            rate = constant_rate(q)
            phases.append(phase)
    else:
        raise RuntimeError("too many integration segments")

    end_state = "stuck" if phase == "stick" else "sliding"
    if e_x > 0.0 and end_state == "stuck":
        y = _tangential_rebound(bodies, basis, y0, y_stick, y, mu, e_x)
    return dict(
        status="ok",
        end_state=end_state,
        ball_v=y[0:3].copy(), ball_w=y[3:6].copy(), bat_v=y[6:9].copy(),
        bat_w=y[9:12].copy(),
        normal_impulse=float(imp), stick_impulse=stick_impulse,
        compression_impulse=float(i_c), compression_work=float(w_c),
        normal_work=float(y[12]), friction_work=float(y[13]),
        normal_work_at_stick=float(work_at_stick),
        energy_in=float(energy_in), energy_out=float(bodies.energy(y)),
        phases=phases, slip_near_misses=near_misses,
    )


def _tangential_rebound(bodies, basis, y0, y_stick, y, mu, e_x):
    """Reverse the incoming slip by ``e_x`` with a tangential impulse of the stick phase.

    ``y0``, ``y_stick`` and ``y`` are the states at incidence, where slip stopped (``I_s``)
    and at separation (``I_f``). Independent of the kernel's closed forms: the impulse comes
    from a 2x2 solve with the numerical ``K``, the stick phase's impulse from the ball's
    momentum change between ``y_stick`` and ``y``, and the scale ``s`` from root finding on
    the constraints evaluated on the bodies themselves: the rebound within the friction the
    stick phase leaves unused (``|P_stick,t| + s |dP| <= mu P_stick,n``), net friction work
    (integrated ``W_fr`` plus the energy given back) not positive, kinetic energy not above
    the initial, normal relative velocity not negative.
    """
    t1, t2, t3 = basis
    v_in = bodies.relative_velocity(y0)
    target = -e_x * np.array([v_in @ t1, v_in @ t2])
    now = bodies.relative_velocity(y)
    k = _numerical_k(bodies, basis)
    dp = np.linalg.solve(k[:2, :2], target - np.array([now @ t1, now @ t2]))
    dp_lab = dp[0] * t1 + dp[1] * t2

    def moved(s):
        out = y.copy()
        out[:12] += bodies.velocity_rates(s * dp_lab)
        out[13] += bodies.energy(out) - bodies.energy(y)
        return out

    stick = bodies.m_p * (y[0:3] - y_stick[0:3])  # impulse on the ball while stuck
    stick_normal = stick @ t3
    stick_tangential = np.linalg.norm(stick - stick_normal * t3)
    energy_in = bodies.energy(y0)

    def spare_friction(s):
        return stick_tangential + s * np.linalg.norm(dp_lab) - mu * stick_normal

    def friction(s):
        return moved(s)[13]

    def energy(s):
        return bodies.energy(moved(s)) - energy_in

    def receding(s):
        return -(bodies.relative_velocity(moved(s)) @ t3)

    s = 1.0
    for g in (spare_friction, friction, energy, receding):
        if g(s) > 0.0:
            s = brentq(g, 0.0, s, xtol=1e-15) if g(0.0) < 0.0 else 0.0
    return moved(s)
