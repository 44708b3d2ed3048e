"""The example notebook examples/python/tippetop.ipynb agrees with
examples/python/inversion_map.py: executed (nbclient, as `jupyter nbconvert
--execute` runs it, from the notebook's directory), it prints the script's
inversion counts line for line, and the notebook is committed executed, with
those same lines and its figures in its outputs.

The execution needs nbclient, ipykernel and matplotlib (skipped without them;
TIPPETOP_REQUIRE_NOTEBOOK=1, as .ci/run sets, makes a missing one a
failure). The full map (840 runs, twice: script and notebook) and the Fig. 2 runs
take about 10 s on two cores."""

import json
import os
import subprocess
import sys

import pytest

from _helpers import ROOT

EXAMPLES = ROOT / "examples" / "python"
NOTEBOOK = EXAMPLES / "tippetop.ipynb"
LAWS = ("regularized:", "exact Coulomb:")


def need(module):
    """Import `module`, or skip (fail under TIPPETOP_REQUIRE_NOTEBOOK=1)."""
    if os.environ.get("TIPPETOP_REQUIRE_NOTEBOOK") == "1":
        return __import__(module)
    return pytest.importorskip(module)


def count_lines(text):
    """The lines of `text` that give a friction law's inversion counts."""
    return [line for line in text.splitlines() if line.startswith(LAWS)]


def printed(nb):
    """Everything the notebook's code cells printed (stream outputs)."""
    return "".join(
        "".join(o["text"]) if isinstance(o["text"], list) else o["text"]
        for c in nb["cells"]
        if c["cell_type"] == "code"
        for o in c["outputs"]
        if o["output_type"] == "stream"
    )


@pytest.fixture(scope="module")
def script_counts():
    """inversion_map.py's count lines (the full map, as the README quotes)."""
    need("matplotlib")
    p = subprocess.run(
        [sys.executable, str(EXAMPLES / "inversion_map.py"), "--out", os.devnull],
        cwd=EXAMPLES,
        env=dict(os.environ, MPLBACKEND="Agg"),
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert p.returncode == 0, p.stdout + p.stderr
    lines = count_lines(p.stdout)
    assert len(lines) == 2, p.stdout
    return lines


def test_script_counts_are_the_readmes(script_counts):
    """The README's figures: 76 of 176 inside the window, 0 of 244 outside."""
    assert "76 of 176 inside the window, 0 of 244 outside" in script_counts[0]


def test_committed_notebook_is_executed_with_its_figures(script_counts):
    nb = json.loads(NOTEBOOK.read_text())
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert all(c["execution_count"] is not None for c in code), "not executed"
    assert [c["execution_count"] for c in code] == list(range(1, len(code) + 1))
    outputs = [o for c in code for o in c["outputs"]]
    assert not [o for o in outputs if o["output_type"] == "error"]
    figures = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(figures) >= 2, "Fig. 2 and the inversion map are embedded"
    assert count_lines(printed(nb)) == script_counts


def test_notebook_executes_and_prints_the_scripts_counts(script_counts):
    need("matplotlib")
    need("ipykernel")
    nbclient = need("nbclient")
    nbformat = need("nbformat")
    nb = nbformat.read(str(NOTEBOOK), as_version=4)
    client = nbclient.NotebookClient(
        nb,
        timeout=600,
        kernel_name="python3",
        resources={"metadata": {"path": str(EXAMPLES)}},
    )
    client.execute()
    assert count_lines(printed(nb)) == script_counts
