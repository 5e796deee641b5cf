"""The run's allocation settings (mcbat.runner.memory): set for a run, restored after."""

import ctypes

import pytest

from mcbat.runner import memory


def test_the_thresholds_are_set_during_a_run_and_restored_after(monkeypatch):
    libc = memory._glibc()
    if libc is None:
        pytest.skip("not glibc")
    calls = []

    class Recording:
        def mallopt(self, parameter, value):
            calls.append((parameter, value))
            return libc.mallopt(parameter, value)

        def malloc_trim(self, pad):
            calls.append(("trim", pad))
            return libc.malloc_trim(pad)

    monkeypatch.setattr(memory, "_glibc", lambda: Recording())
    with memory.reuse_freed_memory():
        during = list(calls)
    assert (memory._M_MMAP_THRESHOLD, memory._RUN_MMAP_THRESHOLD) in during
    assert (memory._M_TRIM_THRESHOLD, memory._RUN_TRIM_THRESHOLD) in during
    after = calls[len(during):]
    assert (memory._M_TRIM_THRESHOLD, memory._DEFAULT_TRIM_THRESHOLD) in after
    assert (memory._M_MMAP_THRESHOLD, memory._DEFAULT_MMAP_THRESHOLD) in after
    assert after[-1] == ("trim", 0)


def test_without_glibc_a_run_goes_on_unchanged(monkeypatch):
    monkeypatch.setattr(memory, "_glibc", lambda: None)
    with memory.reuse_freed_memory():
        pass
    assert memory.set_run_allocation(None) is False


def test_glibc_accepts_the_run_settings():
    libc = memory._glibc()
    if libc is None:
        pytest.skip("not glibc")
    assert isinstance(libc, ctypes.CDLL)
    try:
        assert memory.set_run_allocation(libc) is True
    finally:
        libc.mallopt(memory._M_TRIM_THRESHOLD, memory._DEFAULT_TRIM_THRESHOLD)
        libc.mallopt(memory._M_MMAP_THRESHOLD, memory._DEFAULT_MMAP_THRESHOLD)
