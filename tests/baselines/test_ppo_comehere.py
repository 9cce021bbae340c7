"""The PPO baseline runs end to end for a few hundred steps and writes its curve (CSV + PNG)."""

from __future__ import annotations

import csv
import json

import pytest

pytest.importorskip("stable_baselines3", reason="install the 'baselines' extra: pip install -e '.[baselines]'")
pytest.importorskip("matplotlib", reason="install the 'baselines' extra: pip install -e '.[baselines]'")

from baselines.ppo_comehere import Config, main  # noqa: E402

SHORT = ["--timesteps", "256", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--n-epochs", "1",
         "--random-episodes", "4", "--eval-episodes", "2", "--seed", "3"]


def test_short_run_writes_the_curve_and_the_summary(tmp_path, capsys):
    assert main([*SHORT, "--out", str(tmp_path), "--save-model", str(tmp_path / "model.zip")]) == 0
    rows = list(csv.DictReader((tmp_path / "ppo_curve.csv").open()))
    assert rows[0]["policy"] == "random" and rows[0]["episodes"] == "4"
    ppo = [r for r in rows if r["policy"] == "ppo"]
    assert ppo and [int(r["timesteps"]) for r in ppo] == sorted(int(r["timesteps"]) for r in ppo)
    assert all(0.0 <= float(r["success_rate"]) <= 1.0 for r in rows)
    assert (tmp_path / "ppo_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "model.zip").stat().st_size > 0
    summary = json.loads((tmp_path / "ppo_summary.json").read_text())
    assert summary["config"]["timesteps"] == 256 and summary["config"]["seed"] == 3
    for name in ("ppo_greedy", "ppo_sampled", "random"):
        assert 0.0 <= summary["evaluation"][name]["success_rate"] <= 1.0
    assert '"evaluation"' in capsys.readouterr().out
    # The docs' PPO figures are made from these two files.
    from baselines.figures import ppo_curve_table, ppo_evaluation_table

    curve = ppo_curve_table(rows)
    assert curve.rows[0][:2] == ["random policy, same envs and seeds", 4]
    assert sum(row[1] for row in curve.rows[1:]) == sum(int(r["episodes"]) for r in ppo)
    evaluation = ppo_evaluation_table(summary)
    assert [row[1] for row in evaluation.rows] == [summary["evaluation"][k]["success_rate"]
                                                   for k in ("ppo_greedy", "ppo_sampled", "random")]


def test_same_seed_same_curve(tmp_path):
    args = [*SHORT, "--timesteps", "128", "--eval-episodes", "0"]
    main([*args, "--out", str(tmp_path / "a")])
    main([*args, "--out", str(tmp_path / "b")])
    assert (tmp_path / "a" / "ppo_curve.csv").read_text() == (tmp_path / "b" / "ppo_curve.csv").read_text()


@pytest.mark.parametrize("bad, message", [({"width": 32}, "at least 36"), ({"timesteps": 0}, "timesteps"),
                                          ({"n_envs": 1.5}, "n_envs")])
def test_bad_configuration_is_refused(bad, message):
    with pytest.raises(ValueError, match=message):
        Config(**bad)


def test_cli_reports_bad_arguments(capsys):
    assert main(["--width", "20"]) == 2
    assert "at least 36" in capsys.readouterr().err
