"""docs/papers.md is rendered from its template and the evidence JSON (``climb-ompl bench papers-doc``, ``make
papers``): the committed page is what the committed evidence gives, and every row rated *reproduced* names the
command or test that produces its figure."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from climb_ompl.bench import papers_doc
from climb_ompl.cli import app
from climb_ompl.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
TEMPLATE, EVIDENCE, PAGE = ROOT / "docs/papers.md.in", ROOT / "docs/papers.json", ROOT / "docs/papers.md"


def test_the_page_is_the_template_rendered_from_the_evidence() -> None:
    """Edit docs/papers.md.in (or re-run the benchmarks), then `make papers`: the page never drifts from them."""
    page = papers_doc.render(TEMPLATE.read_text(), json.loads(EVIDENCE.read_text()))
    assert page == PAGE.read_text(), "docs/papers.md differs from its template and evidence: run `make papers`"


def _rows(text: str) -> list[list[str]]:
    """The cells of every five-column row (item | paper | ours | command | verdict) of the page's tables."""
    out = []
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if line.startswith("| ") and len(cells) == 5 and cells[0] != "item" and not set(cells[0]) <= {"-"}:
            out.append(cells)
    return out


def test_every_reproduced_row_names_its_command() -> None:
    rows = _rows(PAGE.read_text())
    assert len(rows) > 30
    for item, _, _, command, verdict in rows:
        if verdict.lstrip("*").startswith("reproduced"):
            assert command not in ("", "-") and ("`" in command or "notebook" in command), item[:60]
    assert all(r[4].lstrip("*").split()[0] in ("reproduced", "not") for r in rows)


def test_placeholders_formats_and_a_missing_key() -> None:
    ev = {"a": {"b": [0.5, 2]}, "c": 0.12345, "s": "x y"}
    assert papers_doc.render("{{a.b.0|pct}}, {{a.b.1}}, {{c|.2f}}, {{ c | pct1 }}, {{a.b.0|int}}, {{s}}", ev) \
        == "50 %, 2, 0.12, 12.3 %, 0, x y"
    with pytest.raises(InputError, match="a.x: no such value"):
        papers_doc.render("{{a.x}}", ev)


def test_the_command_refuses_a_missing_key_and_writes_nothing(tmp_path: Path) -> None:
    (tmp_path / "t.md").write_text("{{papers.nope}}\n")
    (tmp_path / "e.json").write_text("{}")
    out = tmp_path / "page.md"
    r = CliRunner().invoke(app, ["bench", "papers-doc", "--template", str(tmp_path / "t.md"), "--evidence",
                                 str(tmp_path / "e.json"), "--out", str(out)])
    assert r.exit_code == 2 and "e.json: papers.nope: no such value" in r.output
    assert not out.exists()
