"""Figures as data (baselines/figures.py): the docs' tables are their data files, and the
cheap figures still measure what the committed files say."""

from __future__ import annotations

import json

import pytest

from baselines import figures
from baselines.figures import FIGURES, FigureError, blocks, load, render, rewrite, stale_blocks
from baselines.refresh import main as refresh_main


def _doc_blocks():
    return [(path, name) for path in figures.DOC_FILES
            for name, _ in blocks((figures.ROOT / path).read_text())]


def test_every_doc_block_is_its_data_file():
    assert _doc_blocks(), "no figure block in the docs"
    assert stale_blocks() == []
    assert refresh_main(["--check"]) == 0


def test_every_figure_is_in_the_docs_and_has_a_data_file():
    shown = {name for _, name in _doc_blocks()}
    assert shown == set(FIGURES)
    for name in FIGURES:
        data = load(name)
        assert data["command"] == FIGURES[name].command and data["commit"] and data["machine"]["cores"]


def test_a_figure_edited_by_hand_is_caught(tmp_path):
    path = figures.ROOT / "docs" / "results.md"
    text = path.read_text()
    name, body = next((n, b) for n, b in blocks(text) if n == "random-policy")
    value = f"{load(name)['rows'][0][1]:.2f}"
    edited = text.replace(body, body.replace(f"| {value} |", "| 0.99 |", 1))
    assert edited != text
    copy = tmp_path / "results.md"
    copy.write_text(edited)
    assert stale_blocks([copy]) == ["results.md: random-policy"]
    assert rewrite(edited) == text  # rewriting puts the measured figure back


def test_a_block_without_a_data_file_is_named(tmp_path, monkeypatch):
    monkeypatch.setattr(figures, "FIGURE_DIR", tmp_path)
    with pytest.raises(FigureError, match="random-policy.*baselines.refresh --only random-policy"):
        load("random-policy")
    (tmp_path / "random-policy.json").write_text("{not json")
    with pytest.raises(FigureError, match="unreadable"):
        load("random-policy")


def test_moved_reports_changes_beyond_the_standard_error():
    old = {"name": "f", "columns": ["env", "rate"], "rows": [["a", 0.40], ["b", 0.30]], "stderr": [[None, 0.05]] * 2}
    new = json.loads(json.dumps(old))
    new["rows"] = [["a", 0.43], ["b", 0.20]]
    assert figures.moved(old, new) == ["f: b / rate: 0.3 -> 0.2 (standard error 0.050)"]


@pytest.mark.parametrize("name", [n for n, f in FIGURES.items() if f.cheap])
def test_cheap_figures_reproduce(name):
    """A committed cheap figure is what the code measures now (else: python -m baselines.refresh)."""
    committed = load(name)
    table = FIGURES[name].produce()
    assert table.columns == committed["columns"]
    assert table.rows == committed["rows"], f"{name} is stale: run `python -m baselines.refresh --only {name}`"


def test_render_says_where_the_figure_comes_from():
    text = render(load("random-policy"))
    assert "python -m baselines.refresh --only random-policy" in text and "docs/data/figures/random-policy.json" in text
