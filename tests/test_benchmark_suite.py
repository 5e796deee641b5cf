"""The benchmark suite's plumbing: the entry points, the JSON results, and the speed tables
of the docs, which must be what ``python -m benchmarks render`` makes of the committed
results (benchmarks/results/)."""

import ast
import copy
import json
import statistics
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks import harness, render  # noqa: E402


@pytest.fixture(scope="module")
def committed():
    results = harness.load_results(render.RESULTS)
    assert results, "no committed results in benchmarks/results"
    return results


def test_the_docs_speed_tables_are_rendered_from_the_committed_results(committed):
    for name, body in render.render_blocks(committed).items():
        text = render.TARGETS[name].read_text()
        assert render.read_block(text, name) == body, (
            f"the '{name}' table of {render.TARGETS[name].name} is not what the committed "
            "results render: python -m benchmarks render")
    assert render.main(["--check"]) == 0


def test_a_changed_result_changes_the_tables(committed):
    changed = copy.deepcopy(committed)
    changed["overview"]["metrics"]["kernel_2_threads"] = 4_321_000.0
    blocks, before = render.render_blocks(changed), render.render_blocks(committed)
    assert blocks["speed"] != before["speed"] and "4,320,000 impacts/s" in blocks["speed"]
    assert "4,320,000 impacts/s" in blocks["speed-short"]
    del changed["flight"]
    assert "flights/s" not in render.render_blocks(changed)["speed"]


def test_every_committed_result_states_its_machine_settings_and_command(committed):
    for name, result in committed.items():
        assert result["benchmark"] == name
        assert result["command"].startswith(f"python -m benchmarks {name}")
        assert {"cpu", "cores", "python", "numpy", "numba", "numba_num_threads",
                "load_average_1min"} <= set(result["machine"])
        assert result["settings"] and result["metrics"]


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
