"""Helpers shared by the tests (imported as `_helpers`: pytest puts this
directory on sys.path)."""

import os
import pathlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[3]


def cli_binary():
    """The workspace's `tippetop` binary: TIPPETOP_BIN, else
    target/release/tippetop or target/debug/tippetop; None if there is none."""
    env = os.environ.get("TIPPETOP_BIN")
    if env:
        return pathlib.Path(env)
    for profile in ("release", "debug"):
        p = ROOT / "target" / profile / "tippetop"
        if p.is_file():
            return p
    return None


def bits(a):
    """The bit patterns of a float64 array (NaN payloads included)."""
    return np.asarray(a, dtype=np.float64).view(np.uint64)


def gil_counts(call):
    """Run `call()` while a Python thread counts, and return (steps the
    counter made during a pure-Python control loop, steps it made during
    `call()`, what `call()` returned).

    The switch interval is set far longer than the test, so the main thread
    gives the GIL up only where it releases it itself: a control loop of pure
    Python lets the counter stand still, a call that releases the GIL lets it
    advance. A GIL request the counter began under the old interval (5 ms) may
    still be pending when the interval changes and would let it step once
    during the control loop; so the main thread first sleeps twice, handing
    the GIL over, after which every wait starts under the new interval."""
    import sys
    import threading
    import time

    counter = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            counter[0] += 1
            time.sleep(0)  # releases the GIL, so the main thread can take it

    old = sys.getswitchinterval()
    th = threading.Thread(target=count)
    th.start()
    try:
        while counter[0] == 0:
            time.sleep(0.001)
        sys.setswitchinterval(100.0)
        time.sleep(0.01)
        time.sleep(0.01)
        c0 = counter[0]
        x = 0
        for i in range(200_000):
            x += i
        c1 = counter[0]
        result = call()
        c2 = counter[0]
    finally:
        sys.setswitchinterval(old)
        stop.set()
        th.join()
    return c1 - c0, c2 - c1, result
