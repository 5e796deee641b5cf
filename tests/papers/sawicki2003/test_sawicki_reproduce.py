"""``mcbat reproduce sawicki2003`` end to end, on a small scan."""

import json
import math

import numpy as np
import pytest

from mcbat.papers.sawicki2003.carry import fly
from mcbat.papers.sawicki2003.reproduce import cell_means, optimum, reproduce
from mcbat.papers.sawicki2003.scan import ATTACK_ANGLES_DEG, UNDERCUTS_IN, run_scan


def test_every_cell_of_the_grid_gets_its_samples():
    scan = run_scan("fastball", "rigid", fly, per_cell=3)
    means = cell_means(scan)
    assert means["count"].shape == (ATTACK_ANGLES_DEG[2] * UNDERCUTS_IN[2],)
    assert (means["count"] == 3).all()
    np.testing.assert_allclose(np.unique(scan.undercut), np.linspace(*UNDERCUTS_IN))
    best = optimum(means)
    assert best["distance"] == np.nanmax(means["distance"])


def test_compliance_changes_the_spin_not_the_draws():
    rigid = run_scan("curveball", "rigid", fly, per_cell=2)
    compliant = run_scan("curveball", "compliant", fly, per_cell=2)
    np.testing.assert_array_equal(rigid.undercut, compliant.undercut)  # same draws
    assert not np.array_equal(rigid.batted["backspin"], compliant.batted["backspin"])


def test_reproduce_writes_summary_table_and_figures(tmp_path):
    lines = []
    paths = reproduce(tmp_path, per_cell=4, echo=lines.append)
    summary = json.loads(paths["summary"].read_text(),
                         parse_constant=lambda c: pytest.fail(f"non-strict JSON {c}"))
    for pitch in ("fastball", "curveball"):
        for model in ("rigid", "compliant"):
            best = summary["optimum"][pitch][model]
            assert 250 < best["distance"] < 550 and math.isfinite(best["undercut"])
    assert set(summary["curveball_vs_fastball"]) == {"rigid", "compliant"}
    assert paths["table"].read_text().startswith("pitch")
    for path in paths["figures"]:
        assert path.stat().st_size > 20_000
    assert any("curveball carries" in line for line in lines[-12:] + [paths["table"]
                                                                       .read_text()])


def test_cli_refuses_dataset_options_for_sawicki2003(tmp_path):
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-m", "mcbat", "reproduce", "sawicki2003",
                           "--samples", "10", "--out", str(tmp_path)], capture_output=True,
                          text=True)
    assert proc.returncode == 2 and "--samples" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "sawicki2003").exists()
