"""Docstrings and type stubs: every public name documented (so help() and
editors explain it), the stubs shipped in the package (PEP 561: py.typed
beside __init__.pyi) and consistent with the module (mypy's stubtest, when
mypy is installed)."""

import inspect
import pathlib
import subprocess
import sys

import pytest

import tippetop as tt

HERE = pathlib.Path(__file__).resolve().parent
STUB_SOURCE = HERE.parent / "tippetop.pyi"


def public_names():
    return [n for n in tt.__all__ if not n.startswith("_")]


def test_all_lists_the_api():
    assert set(public_names()) == {
        "Scenario",
        "Trajectory",
        "Simulation",
        "Snapshot",
        "run",
        "sweep",
        "ensemble",
        "rare",
        "COLUMNS",
    }


def test_every_public_name_has_a_docstring():
    assert tt.__doc__ and "sweep" in tt.__doc__
    missing = []
    for name in public_names():
        obj = getattr(tt, name)
        if name == "COLUMNS":  # a list: documented in the stubs
            continue
        if not (obj.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if not (getattr(member, "__doc__", None) or "").strip():
                    missing.append(f"{name}.{attr}")
    assert missing == []


def test_docstrings_give_units():
    assert "[s]" in tt.Simulation.integrate_to.__doc__
    assert "[s]" in tt.Simulation.time.__doc__
    assert "[rad]" in tt.Trajectory.__doc__ and "[rad/s]" in tt.Trajectory.__doc__
    assert "[rad]" in tt.sweep.__doc__ and "[J]" in tt.sweep.__doc__
    assert "[s]" in tt.run.__doc__


def test_signatures_are_visible_to_help():
    assert str(inspect.signature(tt.sweep)) == "(scenario, vary, threads=None)"
    assert str(inspect.signature(tt.run)) == "(scenario, pose=True)"
    assert str(inspect.signature(tt.Scenario.set)) == "(self, /, key, value)"


def test_stubs_are_installed_with_the_package():
    pkg = pathlib.Path(tt.__file__).parent
    stub = pkg / "__init__.pyi"
    assert stub.is_file(), f"no {stub}"
    assert (pkg / "py.typed").is_file()
    # The installed stub is the one in the repository (the wheel is current).
    assert stub.read_text() == STUB_SOURCE.read_text()
    text = stub.read_text()
    for name in public_names():
        assert name in text, name
    for column in tt.COLUMNS:
        assert f"    {column}: NDArray[np.float64]\n" in text, column


def test_stubtest_finds_the_stubs_consistent(tmp_path):
    pytest.importorskip("mypy.stubtest", reason="mypy not installed (pip install mypy)")
    cmd = [sys.executable, "-m", "mypy.stubtest", "tippetop"]
    cmd += ["--allowlist", str(HERE / "stubtest_allowlist.txt")]
    help_text = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "--help"], capture_output=True, text=True
    ).stdout
    if "--ignore-disjoint-bases" in help_text:
        # pyo3 classes are disjoint bases (PEP 800); the stubs say @final.
        cmd.append("--ignore-disjoint-bases")
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
