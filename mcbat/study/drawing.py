"""How a study's declared inputs are drawn: sample ``i`` depends only on the study, the
seed and ``i``, never on how rows are grouped into chunks (``sample(0, n)`` equals any
concatenation of ``sample(a, b)`` pieces). The scheme, family by family, is described in
``docs/study-format.md`` (section "Determinism"):

* ``fixed``: the value itself;
* ``random`` (uniform, normal, truncnormal, choice, mixture): the counter-based Philox
  sampler of ``mcbat.study.random_program``;
* ``grid``: an outer product, the first declared input varying slowest, sample ``i`` taking
  point ``i mod G``;
* ``sobol``: one scrambled ``scipy.stats.qmc.Sobol`` engine shared by the study's
  sobol inputs, seeded with ``SeedSequence(seed, spawn_key=(SOBOL_SPAWN_KEY,))``;
* ``lhs``: one ``scipy.stats.qmc.LatinHypercube`` design per block of
  ``LHS_BLOCK`` samples, seeded with ``SeedSequence(seed, spawn_key=(LHS_SPAWN_KEY,
  block))``.
"""

from __future__ import annotations

import warnings

import numpy as np

from mcbat.study.random_program import compile_program, draw

__all__ = ["FAMILIES", "LHS_BLOCK", "LHS_SPAWN_KEY", "SOBOL_BITS", "SOBOL_SPAWN_KEY",
           "check_sample_range", "draw_families", "plan_families", "sampling_scheme"]

#: Samples per LHS design (the stratification holds within each full block).
LHS_BLOCK = 65536
#: ``spawn_key`` of the Sobol engine's SeedSequence.
SOBOL_SPAWN_KEY = 2**31
#: First element of the ``spawn_key`` of the per-block LHS designs.
LHS_SPAWN_KEY = 2**31 + 1
#: Bits of the Sobol engine: at most ``2**SOBOL_BITS`` samples.
SOBOL_BITS = 32
#: How inputs are drawn (``mcbat.study.dist_types.Dist.family``).
FAMILIES = ("fixed", "random", "grid", "sobol", "lhs")


def sampling_scheme() -> dict:
    """The scheme of each sampled family, as recorded in a study's config (and hash)."""
    return {
        "random": "Philox4x32-10, key = seed, counter = (sample index, "
                  "CRC-32 of the input's name); inverse-CDF normals (AS241)",
        "sobol": f"scipy.stats.qmc.Sobol(scramble=True, bits={SOBOL_BITS}), "
                 f"SeedSequence(seed, spawn_key=({SOBOL_SPAWN_KEY},))",
        "lhs": f"scipy.stats.qmc.LatinHypercube per block of {LHS_BLOCK}, "
               f"SeedSequence(seed, spawn_key=({LHS_SPAWN_KEY}, block))",
    }


def plan_families(inputs) -> tuple[dict, int | None]:
    """The inputs (name -> distribution, in declaration order) grouped by family:
    ``({family: [(name, dist), ...]}, G)``, ``G`` the number of points of the grid
    inputs' outer product (None: no grid input)."""
    families = {family: [] for family in FAMILIES}
    for name, dist in inputs.items():
        families[dist.family].append((name, dist))
    grids = families["grid"]
    grid_size = int(np.prod([d.num for _, d in grids])) if grids else None
    return families, grid_size


def draw_families(families, grid_size, start, stop, seed, table, rows) -> None:
    """Write the values of every input of ``families`` (``plan_families``) for samples
    ``[start, stop)`` into row ``rows[name]`` of ``table`` (float64, ``stop - start``
    columns)."""
    n = stop - start
    fam = families
    for name, dist in fam["fixed"]:
        table[rows[name]] = dist.value

    if fam["random"]:
        program = compile_program(fam["random"], rows)
        draw(program, seed, start, table)

    if fam["grid"]:
        g = np.arange(start, stop, dtype=np.int64) % grid_size
        stride = grid_size
        for name, dist in fam["grid"]:
            stride //= dist.num
            np.take(dist.values(), (g // stride) % dist.num, out=table[rows[name]])

    if fam["sobol"]:
        if stop > 2**SOBOL_BITS:
            raise ValueError(f"sobol inputs support at most 2**{SOBOL_BITS} samples, "
                             f"asked for sample {stop - 1}")
        rng = np.random.default_rng(np.random.SeedSequence(seed,
                                                           spawn_key=(SOBOL_SPAWN_KEY,)))
        engine = _qmc("Sobol", len(fam["sobol"]), rng, scramble=True, bits=SOBOL_BITS)
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=".*balance properties.*")
            if start:  # (scipy's fast_forward(0) on a fresh engine fails)
                engine.fast_forward(start)
            points = engine.random(n)
        for j, (name, dist) in enumerate(fam["sobol"]):
            table[rows[name]] = dist.from_unit(points[:, j])

    if fam["lhs"]:
        B = LHS_BLOCK
        for k in range(start // B, (stop - 1) // B + 1):
            rng = np.random.default_rng(np.random.SeedSequence(
                seed, spawn_key=(LHS_SPAWN_KEY, k)))
            design = _qmc("LatinHypercube", len(fam["lhs"]), rng).random(B)
            lo, hi = max(start, k * B), min(stop, (k + 1) * B)
            for j, (name, dist) in enumerate(fam["lhs"]):
                table[rows[name], lo - start:hi - start] = dist.from_unit(
                    design[lo - k * B:hi - k * B, j])


def check_sample_range(start, stop, seed) -> tuple[int, int, int]:
    """Validated ``(start, stop, seed)`` of a study's ``sample``, as ints."""
    for label, value in (("start", start), ("stop", stop), ("seed", seed)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise TypeError(f"{label} must be an integer, got {value!r}")
    if not 0 <= start <= stop:
        raise ValueError(f"need 0 <= start <= stop, got start={start}, stop={stop}")
    if seed < 0:
        raise ValueError(f"seed must be >= 0, got {seed}")
    return int(start), int(stop), int(seed)


def _qmc(name, d, rng, **kwargs):
    """The scipy.stats.qmc engine ``name`` seeded with a Generator (``rng=`` from scipy
    1.15 on). Imported here, not with the module: scipy.stats costs ~0.3 s of start-up,
    and only studies with sobol or lhs inputs need it."""
    from scipy.stats import qmc

    engine = getattr(qmc, name)
    try:
        return engine(d, rng=rng, **kwargs)
    except TypeError:  # scipy < 1.15
        return engine(d, seed=rng, **kwargs)
