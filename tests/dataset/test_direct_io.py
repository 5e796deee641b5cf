"""Large chunk files are written bypassing the page cache where the file system allows it
(mcbat.dataset.storage._write_direct), byte for byte the same as a buffered write."""

import os

import numpy as np
import pyarrow as pa
import pytest

from mcbat.dataset import storage


def _aligned(size, offset=0):
    raw = np.empty(size + 2 * storage.DIRECT_ALIGNMENT, np.uint8)
    start = -raw.ctypes.data % storage.DIRECT_ALIGNMENT + offset
    view = raw[start:start + size]
    view[:] = np.random.default_rng(size).integers(0, 256, size, dtype=np.uint8)
    return pa.py_buffer(view)


@pytest.mark.skipif(not hasattr(os, "O_DIRECT"), reason="no O_DIRECT on this OS")
@pytest.mark.parametrize("size", [1 << 20, (1 << 20) + 1, 3 * 4096 * 100 + 1234])
def test_direct_write_is_byte_identical(tmp_path, size):
    data = _aligned(size)
    path = tmp_path / "chunk.parquet"
    wrote = storage._write_direct(data, path)
    if not wrote:  # a file system without O_DIRECT (tmpfs): nothing may be left behind
        assert not path.exists()
        pytest.skip("this file system refuses O_DIRECT")
    assert path.read_bytes() == data.to_pybytes()
    assert not storage._write_direct(data, path)  # never over an existing file
    assert path.read_bytes() == data.to_pybytes()


def test_what_cannot_go_direct_is_written_normally(tmp_path, monkeypatch):
    small = _aligned(1000)
    misaligned = _aligned(1 << 20, offset=8)
    assert not storage._write_direct(small, tmp_path / "a")
    assert not storage._write_direct(misaligned, tmp_path / "b")
    monkeypatch.setenv("MCBAT_DIRECT_IO", "0")
    assert not storage._write_direct(_aligned(1 << 20), tmp_path / "c")
    assert not any(tmp_path.iterdir())
    for name, data in (("a", small), ("b", misaligned), ("c", _aligned((1 << 20) + 7))):
        storage.write_bytes_atomic(data, tmp_path / name)
        assert (tmp_path / name).read_bytes() == data.to_pybytes()
