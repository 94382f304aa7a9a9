"""glibc heap settings (heap.py): thresholds raised only by pinn-mesh's own processes, memory
handed back after each block."""

from __future__ import annotations

import pytest

from pinn_engine import heap


class FakeLibc:
    def __init__(self) -> None:
        self.calls: list[tuple] = []

    def mallopt(self, param: int, value: int) -> int:
        self.calls.append(("mallopt", param, value))
        return 1

    def malloc_trim(self, pad: int) -> int:
        self.calls.append(("malloc_trim", pad))
        return 1


def test_the_library_hands_memory_back_and_changes_no_threshold(monkeypatch):
    libc = FakeLibc()
    monkeypatch.setattr(heap, "_glibc", lambda: libc)
    with pytest.raises(RuntimeError), heap.reuse_freed_memory():
        assert libc.calls == []  # a host process (ParaView, a script) keeps its allocator
        raise RuntimeError("training failed")
    assert libc.calls == [("malloc_trim", 0)]


def test_own_processes_raise_the_thresholds(monkeypatch):
    libc = FakeLibc()
    monkeypatch.setattr(heap, "_glibc", lambda: libc)
    heap.tune_process()
    assert libc.calls == [
        ("mallopt", heap.M_MMAP_THRESHOLD, heap.MMAP_THRESHOLD),
        ("mallopt", heap.M_TRIM_THRESHOLD, heap.TRIM_THRESHOLD),
    ]


def test_the_command_line_tunes_its_process(monkeypatch, tmp_path):
    from helpers import EXAMPLES

    from pinn_engine.routes.cli import main

    libc = FakeLibc()
    monkeypatch.setattr(heap, "_glibc", lambda: libc)
    assert (
        main(
            [
                str(EXAMPLES / "fig2.vtp"),
                "--method",
                "tfi",
                "-o",
                str(tmp_path / "g.vts"),
                "--quiet",
            ]
        )
        == 0
    )
    assert ("mallopt", heap.M_MMAP_THRESHOLD, heap.MMAP_THRESHOLD) in libc.calls


def test_without_glibc_it_does_nothing(monkeypatch):
    """Outside glibc (musl here) no C library is loaded or called, and the block still runs."""
    monkeypatch.setattr(heap.platform, "libc_ver", lambda: ("musl", "1.2"))
    monkeypatch.setattr(heap.ctypes, "CDLL", lambda *a: pytest.fail("a C library was loaded"))
    heap._glibc.cache_clear()
    ran = []
    try:
        assert heap._glibc() is None
        with heap.reuse_freed_memory():
            ran.append(True)
        heap.tune_process()
    finally:
        heap._glibc.cache_clear()
    assert ran == [True]


def test_the_real_glibc_accepts_the_settings():
    libc = heap._glibc()
    if libc is None:
        pytest.skip("not glibc")
    assert libc.mallopt(heap.M_MMAP_THRESHOLD, heap.MMAP_THRESHOLD) == 1
    assert libc.mallopt(heap.M_TRIM_THRESHOLD, heap.TRIM_THRESHOLD) == 1
