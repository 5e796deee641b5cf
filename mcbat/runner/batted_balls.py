"""The batted balls of a game run, summarised for its closing report: medians and 5-95 %
ranges of the launch and the flight, read from the chunk files in constant memory."""

from __future__ import annotations

import numpy as np

from mcbat.dataset import chunks
from mcbat.dataset.streaming import streamed_percentiles

__all__ = ["BATTED_BALL_COLUMNS", "SWEET_SPOT_WINDOW", "batted_ball_lines",
           "batted_ball_summary"]

#: Rows counted as hit "at the sweet spot" by ``batted_ball_summary``: within 0.5 in of
#: 6 in from the barrel end, and within 0.25 in of a head-on hit.
SWEET_SPOT_WINDOW = (0.1524, 0.0127, 0.00635)


#: The columns ``batted_ball_summary`` reads (with ``flight``: and the flight's).
BATTED_BALL_COLUMNS = ("launch_speed", "launch_angle", "backspin", "collision_efficiency",
                       "from_barrel_end", "undercut", "status")


def batted_ball_summary(out, flight=False) -> dict:
    """Median and 5-95 % range of launch speed, launch angle and backspin (and, with
    ``flight``, of the distance and hang time) of a game dataset's ok rows, and the median
    collision efficiency of its sweet-spot hits.

    The chunk files are read one at a time, a few times over
    (``mcbat.dataset.streaming.streamed_percentiles``): memory stays that of one chunk
    whatever the dataset's size, and the percentiles are numpy's of all the rows."""
    carried = ["hit_distance", "hang_time"] if flight else []
    names = ["launch_speed", "launch_angle", "backspin", *carried, "collision_efficiency",
             "from_barrel_end", "undercut", "status"]
    paths = [path for _, path in sorted(chunks.chunk_files(out).items())]
    centre, half_width, square = SWEET_SPOT_WINDOW

    def read_pass():
        for path in paths:
            table = chunks.read_table(path, columns=names)
            cols = {n: table.column(n).to_numpy() for n in names}
            del table
            ok = cols["status"] == 0
            part = {}
            for name in ("launch_speed", "launch_angle", "backspin", *carried):
                values = cols[name]
                part[name] = values[ok & np.isfinite(values)]
            sweet = ok & (np.abs(cols["from_barrel_end"] - centre) <= half_width) \
                & (np.abs(cols["undercut"]) <= square)
            q = cols["collision_efficiency"]
            part["collision_efficiency"] = q[sweet & np.isfinite(q)]
            yield part

    wanted = {name: (50, 5, 95) for name in ("launch_speed", "launch_angle", "backspin",
                                             *carried)}
    wanted["collision_efficiency"] = (50,)
    found = streamed_percentiles(read_pass, wanted)
    result = {name: found[name][1] for name in wanted if name != "collision_efficiency"}
    n_sweet, (median,) = found["collision_efficiency"]
    result["collision_efficiency_sweet_spot"] = (median, int(n_sweet))
    return result


def batted_ball_lines(b: dict) -> list[str]:
    """The batted-ball summary of a game run, one string per line."""
    units = {"launch_speed": "mph", "launch_angle": "deg", "backspin": "rpm",
             "hit_distance": "ft", "hang_time": "s"}
    out = ["batted ball (median, 5-95 %):"]
    for name, unit in units.items():
        if name not in b:
            continue
        med, lo, hi = b[name]
        out.append(f"  {name}: {med:.1f} {unit} ({lo:.1f} to {hi:.1f})")
    q, n = b["collision_efficiency_sweet_spot"]
    value = f"{q:.3f} (median of {n:,} rows)" if n else "no row in that window"
    out.append(f"  collision_efficiency at the sweet spot (6 +- 0.5 in, |undercut| <= 0.25 in): "
               f"{value}")
    return out
