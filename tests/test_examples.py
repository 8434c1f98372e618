"""The example scripts the docs send users to run as the docs say."""

from __future__ import annotations

import pytest


@pytest.mark.heavy
def test_the_onestep_figure_script_runs(tmp_path):
    """``examples/onestep_figures.py``, which docs/onestep.md and docs/papers.md send users to, draws its three
    figures (it had broken on the atlas default, on a moved helper and on seed-independent transitions)."""
    from conftest import ROOT, run_subprocess

    r = run_subprocess([str(ROOT / "examples" / "onestep_figures.py"), "--out-dir", str(tmp_path)], timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    for name in ("planar3", "double_link", "lemur"):
        assert (tmp_path / f"onestep_{name}.png").stat().st_size > 10_000
