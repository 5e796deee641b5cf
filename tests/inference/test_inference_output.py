"""An inference written to Parquet (mcbat.inference.output, ``mcbat infer``): the balls and
their spin with units in the metadata; a bad output refused before any work."""

from tests.conftest import ROOT


def test_cli_infer_writes_the_balls_and_their_spin(tmp_path, capsys):
    import json

    import pyarrow.parquet as pq

    from mcbat.cli import main

    out = tmp_path / "spin.parquet"
    assert main(["infer", str(ROOT / "data" / "statcast_2019_darvish.csv"), "--out",
                 str(out)]) == 0
    text = capsys.readouterr().out
    assert "balls in play: converged" in text and f"written: {out}" in text
    table = pq.read_table(out)
    meta = json.loads(table.schema.metadata[b"mcbat.inference"])
    assert meta["units"]["backspin"] == "rpm" and meta["units"]["launch_speed"] == "mph"
    df = table.to_pandas()
    assert len(df) == sum(meta["status_counts"].values())
    assert {"hit_distance_sc", "launch_angle", "backspin", "inference_status"} <= set(df)


def test_cli_infer_refuses_a_bad_output_before_any_work(tmp_path, capsys):
    from mcbat.cli import main

    code = main(["infer", str(ROOT / "data" / "statcast_2019_darvish.csv"), "--out",
                 str(tmp_path / "spin.txt")])
    assert code == 2
    assert "--out: unsupported file type '.txt'" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
