"""Sensitivities of the carry with the default flight model (docs/flight.md).

Run:  .venv/bin/python -m validation flight_sensitivities

At 103 mph, 27 deg, 2000 rpm of backspin (no sidespin), standard conditions (70 degF,
29.92 inHg, 50 % RH, sea level), from (0, 2, 3) ft, Nathan's model with 30 s spin decay:
ft per mph of launch speed, per 10 degF, per 1000 ft of elevation (central differences);
and the launch angle of greatest carry at 90, 100 and 110 mph with the calculator's
average spin model (backspin = -763 + 120 LA rpm, sidespin = -849 rpm at spray 0).
"""

import argparse
import dataclasses
import math

import numpy as np
from scipy.optimize import minimize_scalar

from mcbat.api import FlightCase, solve_flight
from mcbat.study.flight import FlightSettings

MPH, DEG, RPM = 0.44704, math.pi / 180, 2 * math.pi / 60
BASE = FlightSettings()


def carry(speed_mph, angle_deg, back_rpm, side_rpm=0.0, settings=BASE):
    case = FlightCase(launch_speed=speed_mph * MPH, launch_angle=angle_deg * DEG,
                      backspin=back_rpm * RPM, sidespin=side_rpm * RPM, settings=settings)
    return solve_flight(case).hit_distance


def with_(**kw):
    return dataclasses.replace(BASE, **kw)


def main(argv=None):
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    base = carry(103, 27, 2000)
    per_mph = (carry(104, 27, 2000) - carry(102, 27, 2000)) / 2
    t = BASE.temperature
    per_10f = (carry(103, 27, 2000, settings=with_(temperature=t + 25 / 9))  # +-5 degF
               - carry(103, 27, 2000, settings=with_(temperature=t - 25 / 9)))
    per_1000ft = (carry(103, 27, 2000, settings=with_(elevation=0.3048 * 1000))
                  - carry(103, 27, 2000, settings=with_(elevation=0.0)))
    print(f"carry at 103 mph, 27 deg, 2000 rpm: {base:.1f} ft")
    print(f"  {per_mph:.2f} ft per mph, {per_10f:.2f} ft per 10 degF, "
          f"{per_1000ft:.2f} ft per 1000 ft of elevation (from sea level)")
    print("launch angle of greatest carry (average spin model; no spin):")
    for speed in (90, 100, 110):
        best = minimize_scalar(lambda a, s=speed: -carry(s, a, -763 + 120 * a, -849),
                               bounds=(10, 45), method="bounded", options={"xatol": 0.05})
        none = minimize_scalar(lambda a, s=speed: -carry(s, a, 0.0), bounds=(20, 55),
                               method="bounded", options={"xatol": 0.05})
        print(f"  {speed} mph: {best.x:.1f} deg ({-best.fun:.1f} ft); without spin "
              f"{none.x:.1f} deg ({-none.fun:.1f} ft)")
    print("backspin at 103 mph, 27 deg:", ", ".join(
        f"{b} rpm {carry(103, 27, b):.1f} ft" for b in np.arange(0, 4001, 500)))


if __name__ == "__main__":
    main()
