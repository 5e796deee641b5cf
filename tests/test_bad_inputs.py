"""Every bad input exits 2 with one line naming the key or option,
without a traceback and without leaving a directory that blocks the corrected rerun.

The commands run in this process (the ``cli`` fixture); the real command runs where a
process is the point: its exit status, a pipe closed by its reader, its peak memory."""

import json
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

import mcbat

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "studies" / "example.toml"
CASE = json.loads((ROOT / "examples" / "cabo2012_sec5.json").read_text())


def mcbat_cli(*args, stdin=None, cwd=None):
    """The real command in a subprocess."""
    return subprocess.run([sys.executable, "-m", "mcbat", *map(str, args)], input=stdin,
                          capture_output=True, cwd=cwd or ROOT)


def assert_one_line_error(proc, *needles):
    err = proc.stderr
    if isinstance(err, bytes):
        err = err.decode("utf-8", "replace")
    assert proc.returncode == 2, err
    assert "Traceback" not in err
    line, = err.strip().splitlines()
    assert line.startswith("mcbat: error: ")
    for needle in needles:
        assert needle in line, line
    return line


def _edit(text, old, new):
    assert old in text
    return text.replace(old, new)


STUDY = EXAMPLE.read_text()
SPIN = 'z = { dist = "choice", values = [79, 0, -72] }'
IMPACT = 'impact_parameter = { dist = "uniform", low = -1.5, high = 1.5, unit = "in" }'
BAD_STUDIES = {
    "400-digit integer": (_edit(STUDY, "samples = 20000", "samples = " + "9" * 400),
                          ["study.samples", "must be <= 1,000,000,000,000"]),
    "1e308 rps": (_edit(STUDY, SPIN, 'z = { value = 1e308, unit = "rps" }'),
                  ["ball_spin.z.value", "too large", "rps"]),
    "max_steps beyond int64": (STUDY + "\n[solver]\nmax_steps = 100000000000000000000000\n",
                               ["solver.max_steps", "must be <="]),
    "grid num 1e13": (_edit(STUDY, IMPACT, 'impact_parameter = { dist = "grid", start = -1.5, '
                            'stop = 1.5, num = 10000000000000, unit = "in" }'),
                      ["contact.impact_parameter.num", "must be <= 10,000,000"]),
    "NUL in the name": (_edit(STUDY, 'name = "example"', 'name = "ex\\u0000ample"'),
                        ["study.name", "control characters"]),
    "name escaping results/": (_edit(STUDY, 'name = "example"', 'name = "../../evil"'),
                               ["study.name", "plain directory name"]),
    "absolute name": (_edit(STUDY, 'name = "example"', 'name = "/tmp/x"'),
                      ["study.name", "plain directory name"]),
    "nested too deeply": ("a = " + "[" * 50_000 + "]" * 50_000 + "\n" + STUDY,
                          ["nested too deeply"]),
}


@pytest.mark.parametrize("name", list(BAD_STUDIES))
def test_bad_study_exits_2_and_leaves_nothing(tmp_path, cli, name):
    text, needles = BAD_STUDIES[name]
    (tmp_path / "s.toml").write_bytes(text.encode("utf-8"))
    proc = cli("run", tmp_path / "s.toml", "--quiet", cwd=tmp_path)
    assert_one_line_error(proc, *needles)
    assert proc.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]  # no results/ at all


def test_the_real_command_refuses_a_bad_study_with_exit_status_2(tmp_path):
    text, needles = BAD_STUDIES["400-digit integer"]
    (tmp_path / "s.toml").write_text(text)
    proc = mcbat_cli("run", tmp_path / "s.toml", "--quiet", cwd=tmp_path)
    assert_one_line_error(proc, *needles)
    assert proc.stdout == b""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_utf16_and_bom_files(tmp_path, cli):
    (tmp_path / "u16.toml").write_text(STUDY, encoding="utf-16")
    assert_one_line_error(cli("run", tmp_path / "u16.toml", cwd=tmp_path), "not UTF-8 text")
    assert not (tmp_path / "results").exists()
    (tmp_path / "u16.json").write_text(json.dumps(CASE), encoding="utf-16")
    assert_one_line_error(cli("impact", tmp_path / "u16.json"), "not UTF-8 text")
    # a UTF-8 byte-order mark is harmless: accepted in both
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + STUDY.encode())
    proc = cli("run", tmp_path / "bom.toml", "--out", tmp_path / "ds", "--samples", 500,
               "--quiet")
    assert proc.returncode == 0, proc.stderr
    proc = cli("impact", "-", stdin=b"\xef\xbb\xbf" + json.dumps(CASE).encode())
    assert proc.returncode == 0 and json.loads(proc.stdout)["status"] == "ok"


def test_deep_json_is_a_clear_error(cli):
    proc = cli("impact", "-", stdin=b"[" * 100_000 + b"]" * 100_000)
    assert_one_line_error(proc, "<stdin>", "nested too deeply")


def test_one_unsolvable_case_fails_the_call_naming_its_index(cli):
    # Documented choice (docs/errors.md): the whole call fails cleanly (exit 2, nothing on
    # stdout), naming the case; never an internal error.
    # An approach slower than the rounding of the contact velocity (1e-13 m/s): every
    # input within its range, and still nothing the solver can answer.
    bad = json.loads(json.dumps(CASE))
    bad["ball_velocity"] = [-1e-13, 0.0, 0.0]
    proc = cli("impact", "-", stdin=json.dumps([CASE, bad, CASE]))
    assert_one_line_error(proc, "case 1", "status 'invalid_input'")
    assert proc.stdout == ""
    # a speed beyond the solver's range is named as such
    bad["ball_velocity"] = [-1e300, 0.0, 0.0]
    proc = cli("impact", "-", stdin=json.dumps([CASE, bad, CASE]))
    assert_one_line_error(proc, "case 1", "ball_velocity: every component must be within "
                          "+-100000 m/s")
    assert proc.stdout == ""


def test_a_reader_that_goes_away_is_not_an_error(tmp_path):
    cases = json.dumps([CASE] * 3000).encode()
    proc = subprocess.run(f"{sys.executable} -m mcbat impact - | head -c 10", shell=True,
                          input=cases, capture_output=True, cwd=ROOT)
    assert proc.stdout == b"[\n  {\n    \""[:10]
    assert proc.stderr == b""


@pytest.mark.parametrize("args,needles", [
    (["--samples", "1000000000000000"], ["--samples", "must be <= 1,000,000,000,000"]),
    (["--samples", "100000000", "--chunk-size", "100"],
     ["--chunk-size", "at most 100,000", "choose --chunk-size 1000 or more"]),
])
def test_sample_counts_beyond_the_limits_are_refused_up_front(tmp_path, cli, args, needles):
    proc = cli("run", EXAMPLE, "--out", tmp_path / "ds", "--quiet", *args)
    assert_one_line_error(proc, *needles)
    assert not (tmp_path / "ds").exists()


def _peak_rss_after_three_chunks(out, samples):
    """Peak RSS (kB) of ``mcbat run`` on 10^5-row chunks, killed after 3 chunk files."""
    run = subprocess.Popen([sys.executable, "-m", "mcbat", "run", str(EXAMPLE), "--out",
                            str(out), "--samples", str(samples), "--chunk-size", str(10**5),
                            "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 120
        while len(list(out.glob("chunk-*.parquet"))) < 3:
            assert time.monotonic() < deadline and run.poll() is None, run.stderr.read()
            time.sleep(0.05)
        status = Path(f"/proc/{run.pid}/status").read_text()
    finally:
        run.kill()
        run.wait()
    return int(re.search(r"VmHWM:\s+(\d+) kB", status).group(1))


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc (Linux)")
def test_a_huge_scan_streams_with_the_memory_of_a_small_one(tmp_path):
    # 10^10 samples (10^5 chunks; --samples 10^15 is refused above) against 10^6: the
    # samples are drawn chunk by chunk, so the peak is what one chunk in flight needs.
    small = _peak_rss_after_three_chunks(tmp_path / "small", 10**6)
    huge = _peak_rss_after_three_chunks(tmp_path / "huge", 10**10)
    assert huge < 1024**2, f"peak RSS {huge / 1024:.0f} MB"
    assert huge < 1.1 * small, f"peak RSS {huge / 1024:.0f} MB vs {small / 1024:.0f} MB"


def test_sobol_limit_is_checked_before_anything_runs(tmp_path, cli):
    text = _edit(STUDY, IMPACT, 'impact_parameter = { dist = "sobol", low = -1.5, high = 1.5,'
                 ' unit = "in" }')
    (tmp_path / "s.toml").write_text(text)
    proc = cli("run", tmp_path / "s.toml", "--out", tmp_path / "ds", "--samples", 2**32 + 1,
               "--chunk-size", 2**20)
    assert_one_line_error(proc, "--samples", "sobol", "2**32")
    assert not (tmp_path / "ds").exists()


def test_huge_weights_keep_their_ratio(tmp_path, cli):
    text = _edit(STUDY, SPIN, 'z = { dist = "choice", values = [79, 0], '
                 'weights = [1e308, 1e308] }')
    (tmp_path / "s.toml").write_text(text)
    proc = cli("run", tmp_path / "s.toml", "--out", tmp_path / "ds", "--samples", 4000,
               "--quiet")
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    share = (mcbat.load(tmp_path / "ds")["ball_wz_in"] == 79.0).mean()
    assert abs(share - 0.5) < 0.04  # 4000 draws: sigma 0.008


def test_a_failed_first_run_does_not_block_the_corrected_rerun(tmp_path, monkeypatch):
    # The run fails in its first chunk (a kernel error injected here): the directory it
    # created is gone, so the corrected rerun is not "a dataset of another config".
    from mcbat.runner import chunk_run, run_study
    from mcbat.study import load_study

    def broken(*args, **kwargs):
        raise MemoryError("injected")

    monkeypatch.setattr(chunk_run, "solve_impacts", broken)
    study = load_study(EXAMPLE)
    with pytest.raises(MemoryError):
        run_study(study, tmp_path / "ds", samples=100, progress=False)
    assert not (tmp_path / "ds").exists()
    monkeypatch.undo()
    summary = run_study(study.with_overrides(seed=3), tmp_path / "ds", samples=100,
                        progress=False)
    assert summary.chunks_computed == 1


@pytest.mark.parametrize("url,needles", [
    ("memory://x/y", ["--out", "memory:// keeps files"]),
    ("file://otherhost/tmp/x", ["--out", "host 'otherhost' is not supported"]),
    ("s3://bucket/ds?endpoint_override=localhost:9000", ["--out", "query strings"]),
])
def test_surprising_urls_are_refused(tmp_path, cli, url, needles):
    proc = cli("run", EXAMPLE, "--out", url, "--samples", 100, "--quiet", cwd=tmp_path)
    assert_one_line_error(proc, *needles)
    assert list(tmp_path.iterdir()) == []  # nothing written anywhere here


def test_a_duplicate_csv_column_is_named_as_such(tmp_path, cli):
    data = tmp_path / "drops.csv"
    data.write_text("impact_parameter,exit_speed,exit_speed\n0.01,1.5,1.6\n")
    proc = cli("fit", "--study", ROOT / "studies" / "cross_nathan_2006.toml",
                     "--data", data)
    line = assert_one_line_error(proc, "exit_speed: duplicate column: appears 2 times")
    assert "exit_speed.1" not in line


def test_a_std_that_is_zero_in_si_is_refused(tmp_path, cli):
    # Found by the long fuzz run: 5e-324 mm is a positive number that is 0 m.
    text = _edit(STUDY, 'from_barrel_end = { dist = "uniform", low = 14, high = 16, unit = "cm" }',
                 'from_barrel_end = { dist = "truncnormal", mean = 150, std = 5e-324, '
                 'low = 140, high = 160, unit = "mm" }')
    (tmp_path / "s.toml").write_text(text)
    proc = cli("run", tmp_path / "s.toml", "--out", tmp_path / "ds", "--quiet")
    assert_one_line_error(proc, "contact.from_barrel_end.std", "too small", "0 in SI")
    assert not (tmp_path / "ds").exists()
