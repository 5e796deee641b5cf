"""Slow, independent reference integrator for one rigid ball-bat impact (tests only).

This module re-solves the impact of ``mcbat.core.cabo2012.solve_impact`` in a
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
numpy and scipy (its pieces are in ``mcbat.testing.reference_parts``). Production code
never calls it; it is far too slow for sampling.

The model is the matrix form of ``docs/physics.md``: Coulomb friction, stick when the holding rate
``|f| <= mu``, re-slip along ``u*`` otherwise, and Stronge's energetic restitution
``W_n(I_f) = (1 - e*^2) W_c``.
"""

import math

import numpy as np

from mcbat.testing.reference_parts import (
    RESLIP_SAMPLES,
    Bodies,
    contact_basis,
    integrate,
    numerical_k,
    reslip_direction,
    tangential_rebound,
)

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
# Safety cap on the number of chained solve_ivp segments (phase changes + events).
MAX_SEGMENTS = 50


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
        phase of a contact that ends stuck by ``tangential_rebound`` (see
        ``mcbat/core/cross_nathan2006/README.md``).
    rtol, atol : float
        Tolerances of ``solve_ivp`` (DOP853).
    slip_stop_fraction : float, optional
        Slip speed, relative to ``|v(0)|``, at which the integration in ``I`` ends; the
        approach to stick goes on in ``tau`` (``dI = |v_t| dtau``) down to
        ``TAU_STOP_RATIO`` times it, and only the rest is extrapolated linearly;
        default ``SLIP_STOP_FRACTION``. Varying it shows how much the switch
        contributes to ``I_s``. At most ``stop_definition_fraction``.
    stop_definition_fraction : float, optional
        Slip speed, relative to ``|v(0)|``, below which slip that starts there, or whose
        speed passes a minimum there, has stopped (then stick or re-slip); above it a
        minimum is a near miss and slip goes on. Default ``SLIP_STOP_FRACTION``, the
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
    t1, t2, t3, r_c = contact_basis(axial, angle, radius, slope)
    basis = np.array([t1, t2, t3])
    bodies = Bodies(ball_mass, ball_radius, ball_inertia_factor, bat_mass,
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

    k = numerical_k(bodies, basis)
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
        u = reslip_direction(k, mu)
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
            _, zz, name = integrate(rhs, (0.0, span), zz, events, rtol, atol_tau)
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
        imp, y, name = integrate(make_rhs(rate), (imp, end), y, events, rtol, atol_all)
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
        y = tangential_rebound(bodies, basis, y0, y_stick, y, mu, e_x)
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
