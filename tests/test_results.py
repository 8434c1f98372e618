"""The results page (``climb-ompl bench results``, ``make results``): figures from the benchmarks' JSON files, the
commands that produced them, and the README's copy of its table."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

import pytest
import typer
from typer.testing import CliRunner

from climb_ompl.bench import results
from climb_ompl.bench._common import envelope
from climb_ompl.cli import app
from climb_ompl.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


def _write(path: Path, name: str, params: dict, figures: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({**envelope(name, params), **figures}))


@pytest.fixture()
def bench_dirs(tmp_path: Path) -> tuple[Path, Path]:
    """Three benchmarks' files with known figures (equilibrium, climb, replan) and a suite; the others missing."""
    bench, suite = tmp_path / "bench", tmp_path / "suite"
    _write(bench / "equilibrium.json", "equilibrium", {"stances": 40, "cone_edges": 8, "seed": 0}, {
        "polygon_ms_median": 0.1234, "klampt_ms_median": 0.3702, "klampt_ratio": 3.0, "exact_ms_p95": 17.26,
        "exact_cpu_ms_p95": 9.5, "com_tests_per_s": 7.2e6, "oracle_agreement": 1.0, "lp_test_ms_median": 0.9,
        "speedup_vs_lp": 6480.0, "torque_check_us_median": 61.0, "feasible_region_ms_median": 0.5,
        "feasible_region_oracle_agreement": 0.995, "wide_ours_ms_h2": 0.0091, "wide_ours_ms_h3": 0.0123,
        "wide_ours_ms_h4": 0.0244, "wide_klampt_ratio_h2": 2.14, "wide_klampt_ratio_h3": 2.75,
        "wide_klampt_ratio_h4": 10.86, "wide_exact_ms_p95": 33.0, "wide_exact_cpu_ms_p95": 8.1,
        "wide_exact_oracle_agreement": 1.0})
    walls = [{"success": True, "cpu_s": c} for c in (2.0, 6.0, 4.0)] + [{"success": False, "cpu_s": 99.0}]
    _write(bench / "climb.json", "climb", {
        "robot": "lemur", "terrain": "demo-wall", "height": 1.5, "seed": 3, "time_limit": 120.0, "walls": 4,
        "plot": None, "search": "guided", "sampler": None, "compare": None}, {
        "steps": 61, "cpu_s": 8.0, "verified": True, "success": True,
        "walls": {"n": 4, "successes": 3, "runs": walls}})
    _write(bench / "replan.json", "replan", {
        "robot": "lemur", "terrain": "demo-wall", "height": 2.0, "failures": 7, "seed": 0, "time_limit": 120.0,
        "change": "move"}, {
        "n": 7, "verified_warm": 6, "median_s_warm": 0.5, "median_s_scratch": 2.0, "median_ratio": 0.31,
        "median_cpu_ratio": 0.29})
    _write(suite / "suite.json", "suite", {
        "robots": ["lemur"], "terrains": None, "climb": None, "seed": 0, "seeds": [0], "budget": 180.0, "workers": 2}, {
        "counts": {"verified": 5, "infeasible": 1}, "applicable": 6,
        "lemur_generated_over_demo": {"ratio": 1.5, "cpu_ratio": 1.4, "median_generated_s": 6.0, "demo_wall_s": 4.0,
                                      "lower_bound": False}})
    return bench, suite


def _rows(block: str) -> dict[str, list[str]]:
    """Each benchmark's rows of the table, by name (the command row first)."""
    out: dict[str, list[str]] = {}
    name = None
    for line in block.splitlines():
        if line.startswith("| **"):
            name = line[4:line.index("**", 4)]
            out[name] = []
        if name:
            out[name].append(line)
    return out


def test_the_page_shows_the_figures_of_the_files_and_marks_the_missing_ones(bench_dirs):
    bench, suite = bench_dirs
    page = results.page(bench, suite)
    rows = _rows(results.block_of(page))
    assert set(rows) == {b.name for b in results.BENCHES}
    eq = "\n".join(rows["equilibrium"])
    assert "0.009/0.012/0.024; 0.12 ms" in eq and "Klampt: ratio 2.14/2.75/10.86; 3.00" in eq
    assert "17.3 ms (CPU 9.5); 33.0 ms (CPU 8.1)" in eq and "SOCP oracle: 100.00 % agree" in eq
    assert "7.2 M/s, 100.00 % agree" in eq and "x6480" in eq
    assert "61 us" in eq and "99.50 % agree" in eq
    climb = "\n".join(rows["climb"])
    # the generated walls: 3 of 4 verified, median CPU of the verified ones 4.0 s, over the demo wall's 8.0 s
    assert "61 steps, 8.0 s CPU, verified" in climb and "3/4 verified, median 4.0 s CPU" in climb
    assert "ratio 0.50" in climb
    rp = "\n".join(rows["replan"])
    assert "6/7 verified, median 0.50 s" in rp and "from scratch 2.00 s: ratio 0.31 (CPU 0.29)" in rp
    assert "5/6 verified; LEMUR 1.50" in "\n".join(rows["suite"])
    for name in ("robot", "onestep", "grid", "treebot", "slope", "papers"):
        assert all(results.NOT_MEASURED in r for r in rows[name][1:]), rows[name]
        assert rows[name][1:], name
    for name in ("equilibrium", "climb", "replan", "suite"):
        assert results.NOT_MEASURED not in "\n".join(rows[name])


def test_a_file_of_another_version_reads_n_a_not_an_error(tmp_path):
    _write(tmp_path / "slope.json", "slope", {}, {"angles": 3})  # the figures' keys missing
    rows = _rows(results.block_of(results.page(tmp_path, tmp_path)))
    assert "| n/a |" in rows["slope"][1]
    (tmp_path / "robot.json").write_text("{not json")
    assert results.NOT_MEASURED in _rows(results.block_of(results.page(tmp_path, tmp_path)))["robot"][1]


def _parsed(command: str) -> dict:
    """The parameters the CLI itself parses from ``command`` (``climb-ompl bench NAME ...``), without running it."""
    group = typer.main.get_command(app)
    argv = shlex.split(command)[1:]
    ctx = group.make_context("climb-ompl", list(argv), resilient_parsing=True)
    bench = group.get_command(ctx, argv[0])
    sub = bench.get_command(ctx, argv[1])
    return sub.make_context(argv[1], argv[2:], parent=ctx).params


def test_the_commands_rebuilt_from_the_files_give_back_their_parameters(bench_dirs):
    # the oracle: the command line parsed by the CLI's own parser gives the parameters recorded in the file
    bench, suite = bench_dirs
    for name in ("climb", "replan", "equilibrium"):
        data = json.loads((bench / f"{name}.json").read_text())
        cmd = results.rebuild_command(name, data, f"out/{name}.json")
        parsed = _parsed(cmd)
        for key, value in data["params"].items():
            if key == "compare":
                assert [c for c in parsed[key] if c] == (value or []), cmd
            else:
                assert parsed[key] == value or str(parsed[key]) == str(value), (cmd, key)
        assert str(parsed["out"]) == f"out/{name}.json"
    cmd = results.rebuild_command("climb", json.loads((bench / "climb.json").read_text()), "c.json")
    assert cmd == "climb-ompl bench climb --height 1.5 --seed 3 --walls 4 --compare '' --out c.json"


def test_onestep_booleans_and_grid_options_are_rebuilt():
    cmd = results.rebuild_command("onestep", {"params": {"queries": 20, "direct": False, "torque": "state"}}, "o.json")
    parsed = _parsed(cmd)
    assert parsed["queries"] == 20 and parsed["direct"] is False and parsed["torque"] == "state"
    grid = {"params": {"preset": "small"}, "serial_s": 3.0}
    assert results.rebuild_command("grid", grid, "g") == "climb-ompl bench grid --preset small --compare-serial --out g"


def test_suite_commands_name_only_what_differs_from_the_whole_suite():
    from climb_ompl.bench.suite import TERRAINS

    every = {"params": {"robots": ["lemur"], "terrains": list(TERRAINS), "seeds": [0], "budget": 180.0}}
    assert results.rebuild_command("suite", every, "s") == "climb-ompl bench suite --robot lemur --out s"
    some = {"params": {"robots": ["lemur", "go1"], "terrains": ["slab"], "seeds": [0, 2], "budget": 60.0}}
    parsed = _parsed(results.rebuild_command("suite", some, "s"))
    assert (parsed["robot"], parsed["terrain"], parsed["seed"], parsed["budget"]) == (["lemur", "go1"], ["slab"],
                                                                                      [0, 2], 60.0)


def test_the_readme_block_is_replaced_and_bad_readmes_are_refused(bench_dirs, tmp_path):
    bench, suite = bench_dirs
    readme = tmp_path / "README.md"
    readme.write_text(f"# x\n\nbefore\n\n{results.BEGIN}\nold table\n{results.END}\n\nafter\n")
    out = tmp_path / "docs" / "results.md"
    out.parent.mkdir()
    r = CliRunner().invoke(app, ["bench", "results", "--bench-dir", str(bench), "--suite-dir", str(suite), "--out",
                                 str(out), "--readme", str(readme)])
    assert r.exit_code == 0, r.output
    text = readme.read_text()
    assert "old table" not in text and text.startswith("# x\n\nbefore\n\n") and text.endswith("\n\nafter\n")
    assert results.block_of(text) == results.block_of(out.read_text())
    assert "Klampt: ratio 2.14/2.75/10.86; 3.00" in text
    bad = tmp_path / "bad.md"
    bad.write_text("no markers\n")
    with pytest.raises(InputError, match="results block"):
        results.replace_block(bad.read_text(), "x", str(bad))
    r = CliRunner().invoke(app, ["bench", "results", "--bench-dir", str(bench), "--out", str(out), "--readme",
                                 str(tmp_path / "missing.md")])
    assert r.exit_code == 2 and "--readme" in r.output


def test_the_readme_figures_are_the_results_page():
    # `make results` copies the page's table into the README; an edit of either alone fails here
    readme = (ROOT / "README.md").read_text()
    page = (ROOT / "docs" / "results.md").read_text()
    assert results.block_of(page) is not None
    assert results.block_of(readme) == results.block_of(page)


def test_the_readme_is_short():
    lines = (ROOT / "README.md").read_text().splitlines()
    assert len(lines) <= 150
    assert [i + 1 for i, line in enumerate(lines) if len(line) > 120] == []
