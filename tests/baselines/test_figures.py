"""Figures as data (baselines/figures.py): the docs' tables are their data files, and the
cheap figures still measure what the committed files say."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from baselines import figure_data, figures
from baselines.figure_data import FigureError, blocks, load, render, rewrite, stale_blocks
from baselines.figures import FIGURES
from baselines.refresh import main as refresh_main


def _doc_blocks():
    return [(path, name) for path in figure_data.DOC_FILES
            for name, _ in blocks((figure_data.ROOT / path).read_text())]


def test_every_doc_block_is_its_data_file():
    assert _doc_blocks(), "no figure block in the docs"
    assert stale_blocks() == []
    assert refresh_main(["--check"]) == 0


def test_every_figure_is_in_the_docs_and_has_a_data_file():
    """Each figure is shown in a doc, but for those kept as data only (DATA_ONLY), which no doc shows."""
    shown = {name for _, name in _doc_blocks()}
    assert set(FIGURES) >= figures.DATA_ONLY
    assert shown == set(FIGURES) - figures.DATA_ONLY
    for name in FIGURES:
        data = load(name)
        assert data["command"] == FIGURES[name].command and data["commit"]
        assert data.get("typed") or data["machine"]["cores"]  # a table typed in a doc: no machine recorded


def test_a_figure_edited_by_hand_is_caught(tmp_path):
    path = figure_data.ROOT / "docs" / "results.md"
    text = path.read_text()
    name, body = next((n, b) for n, b in blocks(text) if n == "random-policy")
    value = f"{load(name)['rows'][0][1]:.2f}"
    edited = text.replace(body, body.replace(f"| {value} |", "| 0.99 |", 1))
    assert edited != text
    copy = tmp_path / "results.md"
    copy.write_text(edited)
    assert stale_blocks([copy]) == ["results.md: random-policy"]
    assert rewrite(edited) == text  # rewriting puts the measured figure back


def test_a_quoted_value_edited_by_hand_is_caught(tmp_path):
    """A number in the prose that quotes a figure is checked and rewritten like a table."""
    path = figure_data.ROOT / "docs" / "results.md"
    text = path.read_text()
    match = next(m for m in figure_data.VALUE.finditer(text) if m["spec"].startswith("table-full |"))
    assert match["text"] == figure_data.quoted_value(match["spec"])
    edited = text[:match.start("text")] + "0.99" + text[match.end("text"):]
    copy = tmp_path / "results.md"
    copy.write_text(edited)
    assert stale_blocks([copy]) == [f"results.md: value {match['spec']} (the doc says '0.99')"]
    assert rewrite(edited) == text


def test_quoted_values_name_what_is_wrong():
    assert figure_data.quoted_value("random-policy | Legent/ComeHere-OneRoom-v0 | success (100 episodes)") == \
        f"{load('random-policy')['rows'][0][1]:.2f}"
    assert figure_data.quoted_value("random-policy | @ | commit") == load("random-policy")["commit"][:7]
    for spec, message in [("random-policy | Legent/ComeHere-OneRoom-v0 | no such column", "no column"),
                          ("random-policy | no such row | mean actions", "0 rows named"),
                          ("random-policy | @ | machine", "commit or wall_seconds"),
                          ("random-policy | one part", "expected"),
                          ("no-such-figure | a | b", "no data file")]:
        with pytest.raises(FigureError, match=message):
            figure_data.quoted_value(spec)


def test_a_block_without_a_data_file_is_named(tmp_path, monkeypatch):
    monkeypatch.setattr(figure_data, "FIGURE_DIR", tmp_path)
    with pytest.raises(FigureError, match="random-policy.*baselines.refresh --only random-policy"):
        load("random-policy")
    (tmp_path / "random-policy.json").write_text("{not json")
    with pytest.raises(FigureError, match="unreadable"):
        load("random-policy")


def test_moved_reports_changes_beyond_the_standard_error():
    old = {"name": "f", "columns": ["env", "rate"], "rows": [["a", 0.40], ["b", 0.30]], "stderr": [[None, 0.05]] * 2}
    new = json.loads(json.dumps(old))
    new["rows"] = [["a", 0.43], ["b", 0.20]]
    assert figure_data.moved(old, new) == ["f: b / rate: 0.3 -> 0.2 (standard error 0.050)"]


def test_the_code_changed_since_a_figure_was_measured_is_named(tmp_path, monkeypatch):
    """`--list-outdated` names a figure measured before a change to the package, with the files
    changed; one measured at HEAD is current; a commit the clone does not hold is an error
    that names it."""
    assert figure_data.code_changed_since("HEAD") == []
    # bd825a4 changed legent_gym/world/render.py: a figure measured at its parent is outdated.
    assert "legent_gym/world/render.py" in figure_data.code_changed_since("bd825a4^")
    with pytest.raises(FigureError, match="commit 0000000 is not in this clone's history"):
        figure_data.code_changed_since("0" * 40)

    monkeypatch.setattr(figure_data, "FIGURE_DIR", tmp_path)
    head = figure_data.git("rev-parse", "HEAD")
    old = figure_data.git("rev-parse", "bd825a4^")
    for name, commit in (("random-policy", head), ("expert-success", old)):
        (tmp_path / f"{name}.json").write_text(json.dumps({"format": figure_data.FORMAT_VERSION, "name": name,
                                                           "commit": commit, "dirty": False}))
    found = figures.outdated()
    assert [(name, commit) for name, commit, _ in found] == [("expert-success", old)]
    assert "legent_gym/world/render.py" in found[0][2]


def test_list_outdated_prints_each_figure_and_its_changes(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(figure_data, "FIGURE_DIR", tmp_path)
    old = figure_data.git("rev-parse", "bd825a4^")
    (tmp_path / "expert-success.json").write_text(json.dumps({"format": figure_data.FORMAT_VERSION, "name":
                                                              "expert-success", "commit": old, "dirty": True}))
    assert refresh_main(["--list-outdated"]) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith(f"expert-success (measured at {old[:7]}): ") and "legent_gym/world/render.py" in line
    assert "(uncommitted changes when it was measured)" in line
    (tmp_path / "expert-success.json").unlink()
    assert refresh_main(["--list-outdated"]) == 0
    assert "measured on the current code" in capsys.readouterr().out


@pytest.mark.parametrize("name", [n for n, f in FIGURES.items() if f.cheap])
def test_cheap_figures_reproduce(name):
    """A committed cheap figure is what the code measures now (else: python -m baselines.refresh)."""
    committed = load(name)
    table = FIGURES[name].produce()
    assert table.columns == committed["columns"]
    assert table.rows == committed["rows"], f"{name} is stale: run `python -m baselines.refresh --only {name}`"
    assert table.note == committed["note"]


def test_show_prints_a_figure_kept_as_data_only(capsys):
    assert refresh_main(["--show", "ablation-shift"]) == 0
    assert capsys.readouterr().out == render(load("ablation-shift"))
    assert refresh_main(["--show", "no-such-figure"]) == 2


def test_render_says_where_the_figure_comes_from():
    text = render(load("random-policy"))
    assert "python -m baselines.refresh --only random-policy" in text and "docs/data/figures/random-policy.json" in text
    data = {**load("random-policy"), "machine": {"cpu": "Some CPU", "cores": 2, "vector": "AVX2"}}
    assert "2 cores (Some CPU, AVX2)" in render(data)  # the instruction set that picked torch's kernels


def test_the_machine_names_its_vector_instruction_set():
    described = figure_data.machine()
    assert described["cores"] >= 1 and described["cpu"]
    lines = Path("/proc/cpuinfo").read_text().splitlines()
    flags = next((line for line in lines if line.startswith("flags")), "").split()
    assert described.get("vector") == ("AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags
                                       else "AVX" if "avx" in flags else None)


@pytest.mark.parametrize("name", [n for n, f in FIGURES.items() if f.typed is not None and load(n).get("typed")])
def test_an_adopted_typed_table_is_the_doc_at_its_commit(name):
    """A table adopted from a doc (and not measured since) is, cell for cell, the table that
    doc held at the commit the data names (its provenance is the history, nothing typed since)."""
    data = load(name)
    text = figure_data.git("show", f"{data['commit']}:{data['typed']}")
    if not text:
        pytest.skip("no git history here")
    columns, align, rows = figure_data.typed_table(text, data["typed_line"])
    assert (columns, align, rows) == (data["columns"], data["align"], data["rows"])
    if FIGURES[name].produce is None:  # no one command measures it again
        with pytest.raises(FigureError, match="adopt"):
            figure_data.measure(FIGURES[name])


@pytest.mark.parametrize(("name", "results", "row", "runs"), [
    ("ablation-epochs16", "epochs16", 1, ["ComeHere-OneRoom epochs16/Legent/ComeHere-OneRoom-v0",
                                          "WhereIs-OneRoom epochs16/Legent/WhereIs-OneRoom-v0",
                                          "WhereIs-OneRoom epochs16/Legent/WhereIs-TwoRoom-v0"]),
    ("ablation-shift", "shift", 1, ["ComeHere-OneRoom shift4/Legent/ComeHere-OneRoom-v0",
                                    "WhereIs shift4/Legent/WhereIs-OneRoom-v0",
                                    "WhereIs shift4/Legent/WhereIs-TwoRoom-v0"]),
])
def test_typed_ablation_rows_are_their_runs_results(name, results, row, runs):
    """Where the runs kept their episodes (docs/data/<results>/results.json), the typed rates
    are those runs' rates over seeds 0-99 / 0-299."""
    kept = json.loads((figure_data.ROOT / "docs" / "data" / results / "results.json").read_text())
    cells = []
    for run in runs:
        key, env_id = run.split("/", 1)
        rates = kept[key][env_id]
        cells.append(f"{rates['rate_0_99']:.2f} / {rates['rate_0_299']:.3f}")
    assert load(name)["rows"][row][1:] == cells


def test_the_paper_rows_are_the_quoted_table():
    from baselines.reproduce_table import PAPER_ROWS

    paper = figures.load_quoted("paper-table-3")
    assert paper["source"] == "paper"
    assert paper["rows"] == [[label, *rates] for label, rates in PAPER_ROWS]
    assert set(paper["conditions"]) == {label for label, _ in PAPER_ROWS}


@pytest.mark.parametrize(("producer", "args"), [
    (figures.render_speed, ["--frames", "20", "--sizes", "32"]),
    (figures.step_speed, ["--ids", "Legent/ComeHere-OneRoom-v0", "--steps", "100", "--resets", "2"]),
    (figures.generation_speed, ["--houses", "2", "--rooms", "1"]),
    (figures.expert_speed, ["--ids", "Legent/ComeHere-OneRoom-v0", "--attempts", "2", "--workers", "1",
                            "--collect-ids", "Legent/ComeHere-OneRoom-v0"]),
])
def test_speed_figures_read_their_benchmarks_reports(producer, args):
    """The speed figures run their benchmark script (here with small arguments) and make a
    row of every row it measured, with the load it ran under."""
    table = producer(args)
    assert table.rows and all(len(row) == len(table.columns) for row in table.rows)
    assert all(isinstance(v, int | float) and v > 0 for v in table.rows[0][1:] if v is not None)
    assert "Load average" in table.note


def test_a_run_that_measures_remakes_the_figures_made_from_data():
    """After a table run, its details and the tables made beside it are made again."""
    from baselines.refresh import derived_from_data

    derived = {f.name for f in derived_from_data([FIGURES["table-full"]])}
    assert {"table-full-run", "recovery-against-clean", "paper-beside-ours"} <= derived
    assert not derived & {"table-full", "random-policy", "expert-success"}  # measured, not made from data


def test_the_full_scale_cost_lists_what_scale_full_measures():
    """One row per figure that `--scale full` measures and no other; one run measuring two
    figures (the PPO curve and its evaluation) is counted once in the total."""
    table = FIGURES["full-scale-cost"].produce()
    *rows, total = table.rows
    measured = [n for n, f in FIGURES.items() if f.produce is not None and n != "full-scale-cost"
                and not load(n).get("made_from")]
    assert [row[0] for row in rows] == [f"`{n}`" for n in measured]
    times = {row[0]: row[4] for row in rows}
    assert times["`ppo-curve`"] == times["`ppo-evaluation`"] == load("ppo-curve")["wall_seconds"]
    once = sum(t for name, t in times.items() if t is not None and name != "`ppo-evaluation`")
    assert total[4] == pytest.approx(once)
    assert all(times[f"`{n}`"] is None for n in measured if load(n).get("typed"))


def test_the_dagger_seeds_figure_names_the_run_it_needs(tmp_path, monkeypatch):
    """Measured from the models the DAgger table's run left; without them, it says which run to make first."""
    monkeypatch.setattr(figures, "ROOT", tmp_path)
    monkeypatch.setattr(figure_data, "ROOT", tmp_path)  # where its error message is relative to
    with pytest.raises(FigureError, match="no model runs/table_full_p25_scan/models/sep10000-.*"
                                          "--only table-full-p25-scan-dagger` first"):
        FIGURES["dagger-more-seeds"].produce()


def test_outdated_measures_only_the_figures_whose_code_changed(tmp_path, monkeypatch, capsys):
    """`--only A,B --outdated` measures B (measured before a change) and not A (measured at HEAD)."""
    import baselines.refresh as refresh

    monkeypatch.setattr(figure_data, "FIGURE_DIR", tmp_path)
    monkeypatch.setattr(refresh, "refresh_docs", lambda: [])  # the docs name figures this folder lacks
    monkeypatch.setattr(refresh, "measure", lambda fig, origin: {**load(fig.name), "wall_seconds": 0.0})
    for name, commit in (("random-policy", "HEAD"), ("expert-success", "bd825a4^")):
        (tmp_path / f"{name}.json").write_text(json.dumps({
            "format": figure_data.FORMAT_VERSION, "name": name, "commit": figure_data.git("rev-parse", commit),
            "dirty": False, "columns": ["a"], "rows": [[1]]}))
    assert refresh_main(["--only", "random-policy,expert-success", "--outdated"]) == 0
    err = capsys.readouterr().err
    assert "measuring expert-success" in err and "measuring random-policy" not in err
