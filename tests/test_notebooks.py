"""Execute every notebook in ``notebooks/`` with a tiny parameter set (nbclient); a cell error fails the test.

Notebooks take their parameters from environment variables read in their first cell (tagged
``parameters``); the kernel inherits this process's environment.  The ``.ipynb`` files are generated from
the ``.py`` percent files by jupytext, and a test checks they are in sync.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

NB = Path(__file__).resolve().parents[1] / "notebooks"

#: Small parameters per notebook: together they run in about a minute on 2 cores.
SMALL: dict[str, dict[str, str]] = {
    "01_equilibrium": {"NB_STANCES": "2", "NB_GRID": "25"},
    # RRT and RRTConnect stop on the check budget (LazyPRM and PRM would run to the time limit)
    "02_one_step_planners": {"NB_QUERIES": "1", "NB_PLANNERS": "RRT,RRTConnect", "NB_TIME_LIMIT": "2",
                             "NB_MAX_ITERATIONS": "300", "NB_WORKERS": "2"},
    "03_climb": {"NB_GOAL": "0.55", "NB_TIME_LIMIT": "120"},
    "04_papers": {"NB_SCALE": "small"},
}


def test_every_notebook_has_small_parameters() -> None:
    assert sorted(p.stem for p in NB.glob("*.py")) == sorted(SMALL)
    assert sorted(p.stem for p in NB.glob("*.ipynb")) == sorted(SMALL)


@pytest.mark.parametrize("name", sorted(SMALL))
def test_ipynb_matches_percent_source(name: str) -> None:
    import jupytext

    src = jupytext.read(NB / f"{name}.py")
    nb = jupytext.read(NB / f"{name}.ipynb")
    code = [c.source for c in src.cells]
    assert code == [c.source for c in nb.cells], f"regenerate: jupytext --to ipynb notebooks/{name}.py"
    assert "parameters" in nb.cells[[c.cell_type for c in nb.cells].index("code")].metadata.get("tags", [])


@pytest.mark.slow
@pytest.mark.timeout(400)
@pytest.mark.parametrize("name", sorted(SMALL))
def test_notebook_executes(name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import nbformat
    from nbclient import NotebookClient

    for k, v in {**SMALL[name], "NB_OUT": str(tmp_path), "MPLBACKEND": "Agg"}.items():
        monkeypatch.setenv(k, v)
    nb = nbformat.read(NB / f"{name}.ipynb", as_version=4)
    client = NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(NB)}})
    client.execute()  # raises CellExecutionError on the first failing cell
    outs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outs if o.get("output_type") == "error"]
    assert os.environ.get("NB_OUT") == str(tmp_path)
