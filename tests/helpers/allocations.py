"""Allocation measurements that see only the measured code's own work.

``tracemalloc`` counts every thread's allocations. Under pytest-xdist a worker has a second
Python thread (execnet's, receiving the next tests) that may allocate while a test measures a
control tick, which then reads as the tick allocating (seen: 834 B "kept" over 1000 ticks of
a tick that keeps nothing). :func:`alone` runs the measurement in a child made by
``fork()``, which holds only the thread that forked: the same objects, and no other thread.
"""

from __future__ import annotations

import os
import pickle
import tracemalloc
from collections.abc import Callable
from typing import TypeVar

__all__ = ["alone", "traced_growth_and_peak"]

T = TypeVar("T")


def alone(measure: Callable[[], T]) -> T:
    """``measure()`` run in a forked child with no other thread; its result, or its error.

    The child inherits this process's memory (fixtures, warmed-up controllers) and sends the
    result back through a pipe (pickled: our own values between our own processes).
    """
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: measure, send, leave without running the parent's exit hooks
        os.close(read_fd)
        try:
            try:
                payload = pickle.dumps((True, measure()))
            except BaseException as exc:  # sent to the parent, raised there
                payload = pickle.dumps((False, f"{type(exc).__name__}: {exc}"))
            with os.fdopen(write_fd, "wb") as pipe:
                pipe.write(payload)
        finally:
            os._exit(0)
    os.close(write_fd)
    with os.fdopen(read_fd, "rb") as pipe:
        payload = pipe.read()
    _, status = os.waitpid(pid, 0)
    if not payload:
        raise RuntimeError(f"the measuring child sent nothing (wait status {status})")
    ok, value = pickle.loads(payload)
    if not ok:
        raise RuntimeError(f"the measuring child failed: {value}")
    return value


def traced_growth_and_peak(tick: Callable[[int], object], ticks: int) -> tuple[int, int]:
    """Bytes ``tick(k)`` kept over ``ticks`` calls, and the peak above the start [B].

    Measured :func:`alone` with :mod:`tracemalloc` (started just before the loop).
    """

    def measure() -> tuple[int, int]:
        tracemalloc.start()
        try:
            baseline, _ = tracemalloc.get_traced_memory()
            tracemalloc.reset_peak()
            for k in range(ticks):
                tick(k)
            current, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        return current - baseline, peak - baseline

    return alone(measure)
