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
