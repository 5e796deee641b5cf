"""The benchmark suite's plumbing: the entry points, the JSON results, and the generated
tables of the docs (speed, long runs, accuracy, fuzzing, the Dask engine), which must be
what ``python -m benchmarks render`` makes of the committed results (benchmarks/results/)."""

import ast
import copy
import json
import statistics
from pathlib import Path

import pytest

import harness
from benchmarks import render

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def committed():
    results = harness.load_results(render.RESULTS)
    assert results, "no committed results in benchmarks/results"
    return results


def test_every_generated_block_of_the_docs_is_rendered_from_the_committed_results(committed):
    texts = {path: path.read_text() for path in set(render.TARGETS.values())}
    for name, body in render.render_blocks(committed).items():
        assert render.read_block(texts[render.TARGETS[name]], name) == body, (
            f"the '{name}' block of {render.TARGETS[name].name} is not what the committed "
            "results render: python -m benchmarks render")
    assert render.stale_blocks(committed, texts) == []
    assert render.main(["--check"]) == 0


def test_every_block_in_a_rendered_file_is_one_render_writes():
    # A generated block the renderer does not know would never be checked.
    for path in set(render.TARGETS.values()):
        marked = render.marked_blocks(path.read_text())
        assert len(marked) == len(set(marked)), path
        assert set(marked) == {n for n, p in render.TARGETS.items() if p == path}, path


def test_a_hand_edit_of_any_generated_block_is_caught(committed):
    texts = {path: path.read_text() for path in set(render.TARGETS.values())}
    for name, path in render.TARGETS.items():
        body = render.read_block(texts[path], name)
        edited = dict(texts)
        edited[path] = render.replace_block(texts[path], name, body + " ")
        assert render.stale_blocks(committed, edited) == [name]


def test_every_table_has_its_committed_result(committed):
    blocks = render.render_blocks(committed)
    assert {name for name, body in blocks.items() if body == "No results."} == set()
    assert {"speed", "long-runs", "accuracy", "convergence", "fuzz", "cluster",
            "speed-short"} <= set(blocks)


def test_a_changed_result_changes_the_tables(committed):
    changed = copy.deepcopy(committed)
    changed["overview"]["metrics"]["kernel_2_threads"] = 4_321_000.0
    blocks, before = render.render_blocks(changed), render.render_blocks(committed)
    assert blocks["speed"] != before["speed"] and "4,320,000 impacts/s" in blocks["speed"]
    assert "≥ 1,200,000: met" in blocks["speed"]
    assert "4,320,000 impacts/s" in blocks["speed-short"]
    del changed["flight"]
    assert "flights/s" not in render.render_blocks(changed)["speed"]


def test_the_verdicts_follow_the_figures(committed):
    changed = copy.deepcopy(committed)
    mix = changed["accuracy_mix"]["metrics"]
    mix["by_mode"]["all"]["velocity"] = 2e-8
    mix["passed"]["velocity"], mix["over_target"]["velocity"] = False, 3
    changed["dask"]["metrics"]["dask_over_local"] = 0.79
    changed["memory"]["metrics"]["ratio"] = changed["memory"]["settings"]["limit"] + 0.01
    blocks = render.render_blocks(changed)
    assert "**not met** (3 cases over)" in blocks["accuracy"]
    assert "within 2.0e-8 of the velocity change (target 1e-8: **not met**)" in (
        blocks["speed-short"])
    assert "79.0 %**: **not met**" in blocks["cluster"]
    assert "≥ 80 %: **not met**" in blocks["long-runs"]
    assert f"within {changed['memory']['settings']['limit']:g}x: **not met**" in (
        blocks["long-runs"])
    changed["dask"]["metrics"]["dask_over_local"] = 0.81
    assert "81.0 %**: met" in render.render_blocks(changed)["cluster"]


def _scan(samples, wall_s, peak_mb=280.0, disk_bytes=4e5):
    return {"benchmark": f"pipeline_scan_{samples}", "date": "2026-01-01",
            "command": "python -m benchmarks pipeline --scan",
            "machine": {"cpu": "cpu", "cores": 2, "system": "s", "python": "3", "numpy": "2",
                        "numba": "0", "scipy": "1", "pyarrow": "1", "numba_num_threads": 2,
                        "load_average_1min": 1.0},
            "settings": {"samples": samples},
            "metrics": {"rows_per_s": samples / wall_s, "wall_s": wall_s,
                        "peak_memory_mb": peak_mb, "bytes_on_disk": disk_bytes}}


def test_a_scan_below_the_target_size_is_judged_pro_rata_and_says_so():
    # 10^9 rows in 20 min is 833,333 rows/s for the whole process.
    fast = render.long_table({"pipeline_scan_100000000": _scan(10 ** 8, 100.0)})
    assert "measured at 10^8, not 10^9" in fast and ": met |" in fast
    slow = render.long_table({"pipeline_scan_100000000": _scan(10 ** 8, 130.0)})
    assert "**not met** (time)" in slow
    full = render.long_table({"pipeline_scan_1000000000": _scan(10 ** 9, 1190.0)})
    assert "a 10^9-impact summary scan" in full and "pro rata" not in full
    assert "< 20 min, < 100 MB on disk, < 1 GB: met" in full
    heavy = render.long_table({"pipeline_scan_1000000000": _scan(10 ** 9, 1190.0, 1100.0)})
    assert "**not met** (memory)" in heavy
    both = render.long_table({"pipeline_scan_10000000": _scan(10 ** 7, 10.0, 280.0),
                              "pipeline_scan_100000000": _scan(10 ** 8, 100.0, 300.0)})
    assert "**280 MB** against **300 MB** (+7.1 %) | same within 10 %: met" in both


def test_a_block_without_its_markers_is_an_error():
    with pytest.raises(KeyError, match="speed"):
        render.replace_block("no markers here\n", "speed", "| a |")
    text = "x\n<!-- begin generated: speed -->\nold\n<!-- end generated: speed -->\ny\n"
    assert render.replace_block(text, "speed", "new") == text.replace("old", "new")
    empty = "x\n<!-- begin generated: speed -->\n<!-- end generated: speed -->\n"
    assert render.read_block(empty, "speed") == ""
    assert render.read_block(render.replace_block(empty, "speed", "| a |"), "speed") == "| a |"


def test_record_writes_json_only_under_a_results_directory(tmp_path, monkeypatch):
    monkeypatch.setattr(harness, "_RESULTS_DIR", None)
    assert harness.record("demo", {"rate": 1.0}, {"n": 1}) is None
    monkeypatch.setattr(harness, "_RESULTS_DIR", tmp_path / "results")
    monkeypatch.setattr(harness, "_COMMAND", "python -m benchmarks demo --n 1")
    path = harness.record("demo", {"rate": 2.5}, {"n": 1})
    saved = json.loads(path.read_text())
    assert path == tmp_path / "results" / "demo.json"
    assert saved["metrics"] == {"rate": 2.5} and saved["settings"] == {"n": 1}
    assert saved["command"] == "python -m benchmarks demo --n 1"
    assert saved["machine"]["cores"] >= 1
    assert harness.load_results(tmp_path / "results") == {"demo": saved}


def test_median_time_warms_up_then_times_each_run():
    calls = []
    timing = harness.median_time(lambda: calls.append(1), runs=5, warmup=2)
    assert len(calls) == 7 and len(timing.times) == 5
    assert timing.median == statistics.median(timing.times)


@pytest.mark.parametrize("package", ["benchmarks", "validation"])
def test_every_run_of_a_folder_has_main_argv(package):
    runs = harness.runs(package)
    assert runs and not {"harness", "render", "__main__"} & set(runs)
    for module in runs.values():
        path = ROOT / (module.replace(".", "/") + ".py")
        mains = [node for node in ast.parse(path.read_text()).body
                 if isinstance(node, ast.FunctionDef) and node.name == "main"]
        assert mains and [a.arg for a in mains[0].args.args] == ["argv"], path


def test_unknown_run_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exit_:
        harness.main("benchmarks", ["no_such_benchmark"])
    assert exit_.value.code == 2 and "no_such_benchmark" in capsys.readouterr().err
