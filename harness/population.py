"""The population fit's injected truth, shared by the injection check
(``python -m validation population_injection``) and the fit's timing
(``python -m benchmarks population_timing``), so that both fit the same problem."""

TRUTH = {"swing.bat_speed.mean": 69.0, "swing.bat_speed.std": 6.0,
         "swing.attack_angle.mean": 12.0, "swing.attack_angle.std": 7.0,
         "contact.undercut.std": 0.9, "swing.attack_direction.std": 12.0}
"""The injected values (the study's units: mph, deg, in)."""

SETS = {
    "spread": (("swing.bat_speed.mean", "swing.bat_speed.std", "swing.attack_angle.mean",
                "contact.undercut.std", "swing.attack_direction.std"),
               ("launch_speed", "launch_angle", "spray_angle")),
    "widths": (("swing.bat_speed.mean", "swing.bat_speed.std", "swing.attack_angle.mean",
                "swing.attack_angle.std", "contact.undercut.std"),
               ("launch_speed", "launch_angle")),
}
"""Free parameters and observables of each ``--set`` of the injection check."""

__all__ = ["SETS", "TRUTH"]
