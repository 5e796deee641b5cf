"""Headline numbers of the Sec. V reproduction, and the noise-free model curves.

The paper (Cabo, Soler & Gonzalez, Sec. V) compares a rigid Coulomb impact with Cross &
Nathan's drop test: exit speed against scattering angle for the incoming spins
``w0 = +79, 0, -72`` rad/s (its Figs. 6, 7) and outgoing spin against impact parameter (its
Fig. 8). This module holds what both the figures (``mcbat.papers.cabo2012.figures``)
and the terminal summary need:

``model_curves``
    noise-free single impacts along the impact parameter, one curve per incoming spin;
``nominal_spin``
    the nominal incoming spin (79, 0 or -72 rad/s) of every Monte Carlo row;
``summarize``
    per nominal spin: exit speed near ``alpha = 0``, slope of the outgoing spin against the
    impact parameter (rad/s per inch), range of scattering angles, end-state fractions and
    row counts, for the Monte Carlo rows and for the model curve (JSON-serialisable);
``format_table``
    that summary as a small aligned text table.

>>> from mcbat.papers.cabo2012.calibration import calibrate_restitution
>>> cal = calibrate_restitution()
>>> model = model_curves(cal.e_star)
>>> s = summarize(df, model, cal.to_dict())     # df = mcbat.load(...)
>>> print(format_table(s))

Units: SI in the data frames, except ``impact_parameter_in`` (inches) and the scattering
angle (degrees, ``atan2(v_y, v_x)`` of the outgoing ball, ``docs/physics.md``, printing error 3).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from mcbat.api import solve
from mcbat.papers.cabo2012 import sec5
from mcbat.stats.analysis import ok_rows

__all__ = ["ALPHA0_WINDOW", "INCH", "MEASURED", "format_table", "model_curves",
           "model_speed_at_zero_angle", "nominal_spin", "solved", "spin_label", "summarize"]

INCH = 0.0254  # m
ALPHA0_WINDOW = 2.0  # deg: Monte Carlo rows with |alpha| below this count as "alpha = 0"

#: Measured-noise columns a dataset may carry besides the noise-free model values.
MEASURED = {"exit_speed": "exit_speed_measured",
            "scattering_angle": "scattering_angle_measured",
            "spin_axial": "spin_axial_measured",
            "impact_parameter": "impact_parameter_measured"}


def spin_label(w0: float) -> str:
    """``"+79"``, ``"0"``, ``"-72"``: the key of a nominal spin in ``summarize``."""
    return "0" if w0 == 0 else f"{w0:+g}"


# ---------------------------------------------------------------- model curves

def model_curves(e_star: float, spins=sec5.SPINS, n: int = 121, *, reach_fraction=0.98,
                 mu: float = sec5.MU, e_x: float = 0.0) -> pd.DataFrame:
    """Noise-free Sec. V impacts along the impact parameter, one curve per incoming spin.

    Parameters
    ----------
    e_star : float
        Stronge's energetic coefficient (e.g. ``calibrate_restitution().e_star``).
    spins : sequence of float
        Incoming spins ``w0`` about the bat axis, rad/s.
    n : int
        Points per curve, evenly spaced in ``b`` from ``-reach_fraction`` to
        ``+reach_fraction`` times the reach ``R + r_b`` (an odd ``n`` includes ``b = 0``).
    mu, e_x : float
        Friction coefficient and tangential restitution (0: the rigid model).

    Returns
    -------
    DataFrame
        One row per impact, in order of ``w0`` (as given) then ``b``: ``w0`` (rad/s),
        ``impact_parameter`` (m), ``impact_parameter_in`` (in), ``theta`` (contact angle,
        rad), ``exit_speed`` (m/s), ``scattering_angle`` (deg), ``spin_axial`` (outgoing
        ball ``w_z``, rad/s), ``end_state`` (``"stuck"``, ``"sliding"`` or ``"re-slip"``:
        sliding after a stick that did not hold) and ``stick_impulse`` (kg m/s, NaN if
        sliding never stopped). ``attrs`` holds ``e_star`` and ``mu``. Each row is exactly
        ``solve(sec5.case_at_impact_parameter(b, w0, e=e_star, mu=mu))``.
    """
    n = int(n)
    if n < 2:
        raise ValueError(f"n must be >= 2, got {n}")
    bs = np.linspace(-reach_fraction, reach_fraction, n) * sec5.REACH
    rows = []
    for w0 in spins:
        for b in bs:
            b = float(b)
            case = sec5.case_at_impact_parameter(b, float(w0), e=e_star, mu=mu, e_x=e_x)
            r = solve(case)
            end = r.end_state
            if end == "sliding" and r.stick_impulse is not None:
                end = "re-slip"
            rows.append({"w0": float(w0), "impact_parameter": b,
                         "impact_parameter_in": b / INCH, "theta": case.contact.angle,
                         "exit_speed": r.exit_speed, "scattering_angle": r.scattering_angle,
                         "spin_axial": r.ball_spin[2], "end_state": end,
                         "stick_impulse": (math.nan if r.stick_impulse is None
                                           else r.stick_impulse)})
    frame = pd.DataFrame(rows)
    frame.attrs["e_star"] = float(e_star)
    frame.attrs["mu"] = float(mu)
    frame.attrs["e_x"] = float(e_x)
    return frame


# ---------------------------------------------------------------- Monte Carlo rows

def nominal_spin(df: pd.DataFrame, spins=sec5.SPINS) -> np.ndarray:
    """The nominal spin (rad/s) nearest to each row's incoming ``ball_wz_in``."""
    spins = np.asarray(spins, float)
    wz = df["ball_wz_in"].to_numpy(float)
    return spins[np.argmin(np.abs(wz[:, None] - spins[None, :]), axis=1)]


def solved(df: pd.DataFrame) -> pd.DataFrame:
    """Rows the solver solved (``status`` 0 / ``"ok"``)."""
    return ok_rows(df)


def _kinds(df: pd.DataFrame) -> pd.Series:
    """``stuck`` / ``sliding`` (never stuck) / ``re-slip`` for solved rows."""
    end = df["end_state"].astype(str).map({"1": "stuck", "0": "sliding", "stuck": "stuck",
                                           "sliding": "sliding"})
    kind = np.where(end == "stuck", "stuck",
                    np.where(df["stick_impulse"].notna(), "re-slip", "sliding"))
    return pd.Series(kind, index=df.index)


def _line(x, y) -> tuple[float, float]:
    """Least-squares slope and intercept of ``y`` against ``x`` (NaN with < 2 points)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() < 2 or np.ptp(x[keep]) == 0:
        return math.nan, math.nan
    slope, intercept = np.polyfit(x[keep], y[keep], 1)
    return float(slope), float(intercept)


def model_speed_at_zero_angle(curve: pd.DataFrame) -> float:
    """Exit speed of a model curve interpolated at ``alpha = 0``.

    Finds the first sign change of the scattering angle along ``b`` and fits a cubic in
    ``alpha`` through the (up to) four curve points around it; NaN if the curve never
    crosses ``alpha = 0``.
    """
    curve = curve.sort_values("impact_parameter")
    alpha = curve["scattering_angle"].to_numpy(float)
    speed = curve["exit_speed"].to_numpy(float)
    exact = np.flatnonzero(alpha == 0.0)
    if exact.size:
        return float(speed[exact[0]])
    cross = np.flatnonzero(np.sign(alpha[:-1]) * np.sign(alpha[1:]) < 0)
    if not cross.size:
        return math.nan
    k = int(cross[0])
    lo, hi = max(k - 1, 0), min(k + 3, alpha.size)
    a, v = alpha[lo:hi], speed[lo:hi]
    if np.any(np.diff(a) <= 0) and np.any(np.diff(a) >= 0):  # not monotone: linear only
        a, v = alpha[k:k + 2], speed[k:k + 2]
    coef = np.polyfit(a, v, min(a.size - 1, 3))
    return float(np.polyval(coef, 0.0))


def _f(x) -> float | None:
    """A plain float for JSON (None for NaN)."""
    x = float(x)
    return None if math.isnan(x) else x


def summarize(df: pd.DataFrame, model: pd.DataFrame, calibration=None,
              spins=sec5.SPINS) -> dict:
    """Headline numbers per nominal incoming spin (JSON-serialisable).

    Parameters
    ----------
    df : DataFrame
        Monte Carlo rows (``mcbat.load``); each row is assigned to the nominal spin
        nearest to its ``ball_wz_in``.
    model : DataFrame
        ``model_curves`` for the same spins.
    calibration : dict or Calibration, optional
        Included as given (``Calibration.to_dict()`` if it has one).

    Returns
    -------
    dict
        ``rows``, ``rows_ok``, ``e_star`` (from ``model.attrs``, if any), ``calibration``
        and ``spins``: a dict keyed by ``spin_label`` (``"+79"``, ``"0"``, ``"-72"``),
        each with

        - ``w0``, ``rows``, ``rows_ok``, ``rows_failed``;
        - ``exit_speed_alpha0_mc``: median exit speed (m/s) of the solved rows with
          ``|alpha| < 2 deg`` (noise-free model values), ``rows_alpha0`` how many;
          ``exit_speed_alpha0_measured`` the same from the measured-noise columns when the
          dataset has them; ``exit_speed_alpha0_model``: the model curve at ``alpha = 0``;
        - ``spin_slope_mc``, ``spin_intercept_mc``: least-squares line of ``spin_axial``
          (rad/s) against the impact parameter in inches over the solved rows;
          ``spin_slope_model``, ``spin_intercept_model``: the same over the model-curve
          points inside the rows' impact-parameter range (the whole curve without rows);
        - ``angle_min``, ``angle_max``, ``angle_p01``, ``angle_p99``: scattering angles
          (deg) of the solved rows;
        - ``frac_stuck``, ``frac_sliding`` (never stuck), ``frac_reslip`` (stuck, then
          slipped again): fractions of the solved rows (they sum to 1).

        Missing values are None.
    """
    data = solved(df)
    nominal_all = nominal_spin(df, spins) if len(df) else np.array([])
    nominal_ok = nominal_spin(data, spins) if len(data) else np.array([])
    kinds = _kinds(data) if len(data) else pd.Series([], dtype=object)
    out = {"rows": int(len(df)), "rows_ok": int(len(data)),
           "e_star": _f(model.attrs.get("e_star", math.nan)), "spins": {}}
    for w0 in spins:
        w0 = float(w0)
        rows = data[nominal_ok == w0]
        kind = kinds[nominal_ok == w0]
        curve = model[model["w0"] == w0]
        n_all = int(np.sum(nominal_all == w0))
        entry = {"w0": w0, "rows": n_all, "rows_ok": int(len(rows)),
                 "rows_failed": n_all - int(len(rows))}
        alpha = rows["scattering_angle"].to_numpy(float)
        near = np.abs(alpha) < ALPHA0_WINDOW
        entry["rows_alpha0"] = int(near.sum())
        entry["exit_speed_alpha0_mc"] = _f(np.median(rows["exit_speed"].to_numpy(float)[near])
                                           if near.any() else math.nan)
        if MEASURED["exit_speed"] in rows and MEASURED["scattering_angle"] in rows:
            near_m = np.abs(rows[MEASURED["scattering_angle"]].to_numpy(float)) < ALPHA0_WINDOW
            entry["exit_speed_alpha0_measured"] = _f(
                np.median(rows[MEASURED["exit_speed"]].to_numpy(float)[near_m])
                if near_m.any() else math.nan)
        entry["exit_speed_alpha0_model"] = _f(model_speed_at_zero_angle(curve)
                                              if len(curve) else math.nan)
        b_in = rows["impact_parameter"].to_numpy(float) / INCH
        slope, intercept = _line(b_in, rows["spin_axial"])
        entry["spin_slope_mc"], entry["spin_intercept_mc"] = _f(slope), _f(intercept)
        inside = curve
        if len(rows):
            inside = curve[(curve["impact_parameter_in"] >= b_in.min())
                           & (curve["impact_parameter_in"] <= b_in.max())]
        slope, intercept = _line(inside["impact_parameter_in"], inside["spin_axial"])
        entry["spin_slope_model"], entry["spin_intercept_model"] = _f(slope), _f(intercept)
        if len(rows):
            p01, p99 = np.percentile(alpha, [1, 99])
            entry.update(angle_min=_f(alpha.min()), angle_max=_f(alpha.max()),
                         angle_p01=_f(p01), angle_p99=_f(p99))
            counts = kind.value_counts()
            total = float(len(kind))
            entry.update(frac_stuck=float(counts.get("stuck", 0) / total),
                         frac_sliding=float(counts.get("sliding", 0) / total),
                         frac_reslip=float(counts.get("re-slip", 0) / total))
        else:
            entry.update(angle_min=None, angle_max=None, angle_p01=None, angle_p99=None,
                         frac_stuck=None, frac_sliding=None, frac_reslip=None)
        out["spins"][spin_label(w0)] = entry
    if calibration is not None:
        cal = calibration.to_dict() if hasattr(calibration, "to_dict") else dict(calibration)
        out["calibration"] = {k: (float(v) if isinstance(v, (float, np.floating)) else
                                  int(v) if isinstance(v, (int, np.integer)) else v)
                              for k, v in cal.items()}
    return out


# ---------------------------------------------------------------- text table

_ROWS = [
    ("rows (solved / all)", None, None),
    ("exit speed at alpha=0, MC median", "exit_speed_alpha0_mc", "{:.4f} m/s"),
    ("  MC rows with |alpha| < 2 deg", "rows_alpha0", "{:d}"),
    ("  measured-noise median", "exit_speed_alpha0_measured", "{:.4f} m/s"),
    ("exit speed at alpha=0, model", "exit_speed_alpha0_model", "{:.4f} m/s"),
    ("spin slope, MC fit", "spin_slope_mc", "{:.2f} rad/s/in"),
    ("spin slope, model", "spin_slope_model", "{:.2f} rad/s/in"),
    ("spin at b=0, MC fit", "spin_intercept_mc", "{:.2f} rad/s"),
    ("spin at b=0, model", "spin_intercept_model", "{:.2f} rad/s"),
    ("scattering angle min / max", ("angle_min", "angle_max"), "{:.1f} / {:.1f} deg"),
    ("scattering angle 1% / 99%", ("angle_p01", "angle_p99"), "{:.1f} / {:.1f} deg"),
    ("stuck / sliding / re-slip", ("frac_stuck", "frac_sliding", "frac_reslip"),
     "{:.3f} / {:.3f} / {:.3f}"),
]


def _cell(entry: dict, key, fmt) -> str:
    if key is None:
        return f"{entry['rows_ok']:,} / {entry['rows']:,}"
    keys = key if isinstance(key, tuple) else (key,)
    if any(k not in entry for k in keys):
        return ""
    values = [entry[k] for k in keys]
    if any(v is None for v in values):
        return "-"
    return fmt.format(*values)


def format_table(summary: dict) -> str:
    """The summary of ``summarize`` as an aligned text table (one column per spin)."""
    spins = summary["spins"]
    labels = list(spins)
    header = ["w0 (rad/s)"] + labels
    table = [header]
    for name, key, fmt in _ROWS:
        cells = [_cell(spins[s], key, fmt) for s in labels]
        if all(c == "" for c in cells):
            continue  # e.g. no measured-noise columns in this dataset
        table.append([name] + cells)
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    lines = []
    for j, row in enumerate(table):
        lines.append("  ".join([row[0].ljust(widths[0])]
                               + [c.rjust(w) for c, w in zip(row[1:], widths[1:])]))
        if j == 0:
            lines.append("-" * len(lines[0]))
    foot = [f"rows: {summary['rows']:,} ({summary['rows_ok']:,} solved)"]
    if summary.get("e_star") is not None:
        foot.append(f"e* = {summary['e_star']:.7f} (loss fraction e^2 = "
                    f"{1 - summary['e_star'] ** 2:.7f}): the restitution of the dataset and "
                    "the model curves")
    cal = summary.get("calibration")
    if cal:
        # The root finder's e* differs from the paper's in the fourth digit: it is reported
        # as the paper reports it (e^2), labelled as a check, so that one e* is printed.
        foot.append("check of the paper's calibration: e^2 = {:.7f} gives the target exit "
                    "speed {:.5f} m/s at theta = {:.5f} rad, w0 = {:g} (calibration.json)"
                    .format(cal.get("loss_fraction", math.nan),
                            cal.get("target_speed", math.nan), cal.get("theta", math.nan),
                            cal.get("w0", math.nan)))
    return "\n".join(lines + [""] + foot)
