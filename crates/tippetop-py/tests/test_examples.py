"""The examples in examples/python run (tiny, with --tiny or TINY = True)
and write their figures; they need matplotlib (skipped without it), and
without it they say how to install it."""

import json
import os
import pathlib
import subprocess
import sys

import pytest

from _helpers import ROOT

EXAMPLES = ROOT / "examples" / "python"
SCRIPTS = ["paper_fig2.py", "inversion_map.py"]


def run(args, cwd, **kw):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=300, **kw
    )


@pytest.mark.parametrize("script", SCRIPTS)
def test_script_runs_tiny_and_writes_a_png(script, tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "figure.png"
    p = run([str(EXAMPLES / script), "--tiny", "--out", str(out)], cwd=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {out}" in p.stdout


@pytest.mark.parametrize("script", SCRIPTS)
def test_script_without_matplotlib_says_how_to_install_it(script, tmp_path):
    code = (
        "import runpy, sys; sys.modules['matplotlib'] = None; "
        f"sys.argv = [{str(EXAMPLES / script)!r}, '--tiny']; "
        f"runpy.run_path({str(EXAMPLES / script)!r}, run_name='__main__')"
    )
    p = run(["-c", code], cwd=tmp_path)
    assert p.returncode == 1
    assert "pip install matplotlib" in p.stderr


def notebook():
    return json.loads((EXAMPLES / "tippetop.ipynb").read_text())


def test_notebook_is_a_valid_nbformat_4_document():
    nb = notebook()
    assert nb["nbformat"] == 4 and nb["metadata"]["kernelspec"]["language"] == "python"
    kinds = [c["cell_type"] for c in nb["cells"]]
    assert set(kinds) == {"markdown", "code"}
    for c in nb["cells"]:
        assert isinstance(c["source"], list) and "id" in c
        if c["cell_type"] == "code":
            compile("".join(c["source"]), "<cell>", "exec")
    text = json.dumps(nb)
    assert "tt.sweep(" in text and "Fig. 2" in text and "inversion" in text


def test_notebook_runs_tiny(tmp_path):
    """The code cells in order, TINY = True, from examples/python (the
    notebook's directory, as Jupyter runs it, with it on sys.path: the
    notebook imports inversion_map.py)."""
    pytest.importorskip("matplotlib")
    cells = ["".join(c["source"]) for c in notebook()["cells"] if c["cell_type"] == "code"]
    src = "\n\n".join(cells)
    assert "TINY = False" in src
    script = tmp_path / "nb.py"
    src = src.replace("TINY = False", "TINY = True", 1)
    script.write_text(f"import sys\nsys.path.insert(0, {str(EXAMPLES)!r})\n{src}")
    p = run([str(script)], cwd=EXAMPLES)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "g=9.8 bilateral" in p.stdout and "regularized: 20 tops" in p.stdout


def test_guide_python_example_runs():
    """The user guide's ```python block of "From Python", as written."""
    text = (ROOT / "docs" / "guide.md").read_text()
    section = text[text.index("## From Python") :]
    block = section[section.index("```python\n") + len("```python\n") :]
    block = block[: block.index("```\n")]
    assert "tt.sweep(" in block
    env = {}
    exec(compile(block, "docs/guide.md", "exec"), env)
    assert env["tr"].error is None
    assert list(env["sw"]["status"]) == ["ok"] * 20
