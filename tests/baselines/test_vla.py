"""The VLA baseline on real data from `legent-gym collect`: codec, data contract, model,
training (determinism, resume), the policy in the env, and evaluation."""

from __future__ import annotations

import dataclasses
import json
import shutil

import gymnasium as gym
import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="install the 'baselines' extra: pip install -e '.[baselines]'")

from baselines.evaluate import run_episodes  # noqa: E402
from baselines.vla.checkpoint import load_model, read_checkpoint  # noqa: E402
from baselines.vla.codec import ActionCodec, decompose  # noqa: E402
from baselines.vla.dataset import (  # noqa: E402
    BEARING_SECTORS,
    IGNORE,
    DatasetError,
    aux_targets,
    batches,
    encode,
    mirror_slots,
    read_trajectories,
)
from baselines.vla.evaluate import EXPERT, RANDOM, evaluate_many  # noqa: E402
from baselines.vla.evaluate import main as evaluate_main  # noqa: E402
from baselines.vla.model import VLA, ModelConfig  # noqa: E402
from baselines.vla.policy import VLAPolicy  # noqa: E402
from baselines.vla.train import FINAL, LAST, LOG, TrainConfig, shift_views, train  # noqa: E402
from baselines.vla.words import UNK, WordVocab  # noqa: E402
from legent_gym.agent.actions import ActionParseError, parse_actions  # noqa: E402
from legent_gym.data import CollectConfig, collect  # noqa: E402

SIZE = 32
# One thread: on a shared 2-core machine two torch threads contend and run ~10x slower.
torch.set_num_threads(1)
TINY = ModelConfig(image_size=SIZE, d_model=32, heads=4, layers=1, ff=64)


@pytest.fixture(scope="module")
def datasets(tmp_path_factory):
    """Real expert data: 4 Come Here and 4 Where Is trajectories at 32x32."""
    root = tmp_path_factory.mktemp("vla-data")
    out = {}
    for name, seed in (("ComeHere-OneRoom", 10_000_000), ("WhereIs-OneRoom", 12_000_000)):
        collect(CollectConfig(f"Legent/{name}-v0", 4, str(root / name), formats=("legent",), seed=seed,
                              env_kwargs={"width": SIZE, "height": SIZE}), show_progress=False)
        out[name] = root / name
    return out


# -- codec -----------------------------------------------------------------------------------
def test_decompose_and_format_round_trip():
    codec = ActionCodec.fit(["move_forward(1.5), rotate_right(-30)", 'speak("It\'s on the bed.")',
                             "rotate_right(90), rotate_down(20)", "grab(3)", "finish()"])
    d = decompose("move_forward(1.5), rotate_right(-30)")
    assert d.template == "move_forward(#), rotate_right(#)"
    assert d.numbers == {"move_forward:0": 1.5, "rotate_right:0": -30.0} and d.speech is None
    assert decompose("grab(3)").template == "grab(3)"  # ids are part of the template
    tid = codec.template_id(d.template)
    text = codec.format(tid, {"move_forward:0": 1.234, "rotate_right:0": -29.96}, 0)
    assert text == "move_forward(1.23), rotate_right(-30)"
    speak = codec.format(codec.template_id("speak(@)"), {}, codec.speech_id("It's on the bed."))
    assert parse_actions(speak)[0].text == "It's on the bed."
    assert codec.template_id("rotate_down(#)") == 0  # unseen template
    with pytest.raises(ValueError, match="not a known template"):
        codec.format(0, {}, 0)
    with pytest.raises(ValueError, match="no value for slot"):
        codec.format(tid, {"move_forward:0": 1.0}, 0)
    assert ActionCodec.from_dict(json.loads(json.dumps(codec.to_dict()))).templates == codec.templates


def test_bins_cover_the_range_and_invert():
    codec = ActionCodec.fit(["move_forward(2), rotate_right(-90)"], bins=37)
    for slot, values in (("move_forward:0", [0.0, 0.37, 1.999, 2.0, 5.0]),
                         ("rotate_right:0", [-90.0, -47.9, 0.0, 12.3, 90.0])):
        for value in values:
            index, offset = codec.to_bin(slot, value)
            assert 0 <= index < 37 and -0.5 <= offset <= 0.5
            low, high = (0.0, 2.0) if slot.startswith("move") else (-90.0, 90.0)
            assert codec.from_bin(slot, index, offset) == pytest.approx(min(max(value, low), high))
    assert codec.to_bin("move_forward:0", 2.0) == (36, 0.0)  # the expert's favourite value is exact


def test_unparsable_text_is_rejected_with_the_parser_message():
    with pytest.raises(ActionParseError):
        decompose("walk(3)")
    assert ActionCodec.fit(["finish()"]).encode("walk(3)") is None


def test_word_vocab():
    vocab = WordVocab.fit(["Where's the cola?", "Come here."], max_words=4)
    assert vocab.encode("where is the cola") == [vocab.encode("where")[0], UNK, vocab.encode("the")[0],
                                                 vocab.encode("cola")[0]]
    assert len(vocab.encode("a b c d e f")) == 4 and vocab.encode("") == [UNK]


# -- data ------------------------------------------------------------------------------------
def test_reads_collect_output_and_rebuilds_trajectories(datasets):
    trajectories = read_trajectories(datasets["WhereIs-OneRoom"])
    assert len(trajectories) == 4
    saved = json.loads((datasets["WhereIs-OneRoom"] / "legent" / "trajectories.json").read_text())
    for traj, record in zip(trajectories, saved):
        assert traj.actions == [s["action"] for s in record["interactions"][1]["trajectory"]]
        assert traj.instruction == record["interactions"][0]["text"]
    assert all(t.actions[-1].startswith("speak(") for t in trajectories)
    assert len(read_trajectories(datasets["WhereIs-OneRoom"], limit=2)) == 2


def test_encoded_windows_match_the_jsonl_lines(datasets):
    root = datasets["ComeHere-OneRoom"] / "legent"
    loaded = [(root, t) for t in read_trajectories(root)]
    codec = ActionCodec.fit(a for _, t in loaded for a in t.actions)
    vocab = WordVocab.fit(t.instruction for _, t in loaded)
    data = encode(loaded, codec, vocab, window=3)
    lines = [json.loads(x) for x in (root / "interleaved.jsonl").read_text().splitlines()]
    assert data.n_samples == len(lines) and data.images.shape[1:] == (SIZE, SIZE, 3)
    paths = [p for _, t in loaded for p in t.image_paths]
    for i, line in enumerate(lines):
        shown = [paths[j] for j in data.window_images[i] if j >= 0]
        assert shown == line["images"][-3:]  # the last 3 of the line's 6
        n_hist = int((data.history_template[i] > 0).sum())
        assert n_hist == min(len(line["history"]), 2)
        assert codec.templates[data.target_template[i]] == decompose(line["action"]).template
    batch = next(batches(data, [0, 1], 2, rng=None))
    assert batch["images"].shape[1:] == (3, SIZE, SIZE)
    assert int(batch["window_images"].max()) < batch["images"].shape[0]


def test_recovery_data_trains_on_the_experts_labels_and_shows_what_was_executed(tmp_path):
    out = tmp_path / "perturbed"
    collect(CollectConfig("Legent/ComeHere-OneRoom-v0", 4, str(out), formats=("legent",), seed=10_000_000,
                          env_kwargs={"width": SIZE, "height": SIZE}, perturb=0.5), show_progress=False)
    root = out / "legent"
    trajectories = read_trajectories(root)
    assert sum(t.perturbed for t in trajectories) > 0
    lines = [json.loads(x) for x in (root / "interleaved.jsonl").read_text().splitlines()]
    loaded = [(root, t) for t in trajectories]
    codec = ActionCodec.fit(a for _, t in loaded for a in (*t.labels, *t.actions))
    vocab = WordVocab.fit(t.instruction for _, t in loaded)
    data = encode(loaded, codec, vocab, window=6)
    executed = [a for t in trajectories for a in t.actions]
    for i, line in enumerate(lines):
        assert codec.templates[data.target_template[i]] == decompose(line["action"]).template  # the label
        assert line.get("executed", line["action"]) == executed[i]
        if "executed" in line:  # the next line's history holds the perturbation, not the label
            nxt = lines[i + 1] if i + 1 < len(lines) and lines[i + 1]["trajectory"] == line["trajectory"] else None
            assert nxt is None or nxt["history"][-1] == line["executed"]


def test_goal_view_labels_reach_the_training_targets(datasets):
    """collect stores the expert wrapper's goal_view per step; the loader turns it into the
    auxiliary targets of the same step."""
    root = datasets["WhereIs-OneRoom"] / "legent"
    record = json.loads((root / "000000" / "trajectory.json").read_text())
    steps = record["interactions"][1]["trajectory"]
    assert all(set(step["goal_view"]) == {"visible", "bearing", "distance"} for step in steps)
    lines = [json.loads(line) for line in (root / "interleaved.jsonl").read_text().splitlines()]
    assert [line["goal_view"] for line in lines if line["trajectory"] == "000000"] == [s["goal_view"] for s in steps]
    loaded = [(root, t) for t in read_trajectories(root)]
    assert loaded[0][1].goal_views == [s["goal_view"] for s in steps]
    assert loaded[0][1].goal_views[-1]["visible"]  # the expert answers with the object in view
    codec = ActionCodec.fit(a for _, t in loaded for a in t.actions)
    data = encode(loaded, codec, WordVocab.fit(t.instruction for _, t in loaded), window=6)
    expected = [aux_targets(v) for _, t in loaded for v in t.goal_views]
    assert [tuple(map(int, row)) for row in zip(data.target_visible, data.target_bearing, data.target_distance)] == expected
    assert aux_targets({"visible": True, "bearing": -31.0, "distance": 2.5}) == (1, 11, 2)
    assert aux_targets({"visible": False, "bearing": 175.0, "distance": 0.5}) == (0, 6, 0)
    assert aux_targets(None) == (IGNORE, IGNORE, IGNORE)


def test_auxiliary_goal_view_losses_train_and_need_labels(datasets, tmp_path):
    config = _config(datasets, tmp_path / "aux", model=ModelConfig(**{**TINY.to_dict(), "aux_weight": 0.5}))
    train(config, show_progress=False)
    model, vocab = load_model(tmp_path / "aux" / FINAL)
    assert model.config.aux_weight == 0.5 and hasattr(model, "head_aux")
    root = datasets["ComeHere-OneRoom"] / "legent"
    loaded = [(root, t) for t in read_trajectories(root)]
    batch = next(batches(encode(loaded, model.codec, vocab, window=6), range(2), 2, rng=None))
    out = model(**{k: v for k, v in batch.items() if not k.startswith("target")})
    _, parts = model.loss(out, batch)
    assert parts["aux"] > 0 and out["bearing"].shape == (len(batch["target_template"]), BEARING_SECTORS)
    # Without goal_view labels the option is refused by name.
    copy = tmp_path / "unlabelled"
    shutil.copytree(root, copy)
    lines = [json.loads(line) for line in (copy / "interleaved.jsonl").read_text().splitlines()]
    (copy / "interleaved.jsonl").write_text("".join(json.dumps({k: v for k, v in line.items() if k != "goal_view"})
                                                    + "\n" for line in lines))
    with pytest.raises(DatasetError, match="needs goal_view labels"):
        train(TrainConfig((str(copy),), str(tmp_path / "x"), epochs=1, threads=1, model=config.model),
              show_progress=False)
    with pytest.raises(ValueError, match="aux_weight must be >= 0"):
        ModelConfig(aux_weight=-1)


def test_film_conditions_the_views_on_the_instruction(datasets, tmp_path):
    config = _config(datasets, tmp_path / "film", model=ModelConfig(**{**TINY.to_dict(), "film": True}))
    train(config, show_progress=False)
    model, vocab = load_model(tmp_path / "film" / FINAL)
    assert model.config.film and model.images.film is not None
    root = datasets["WhereIs-OneRoom"] / "legent"
    loaded = [(root, t) for t in read_trajectories(root)]
    batch = next(batches(encode(loaded, model.codec, vocab, window=6), range(2), 2, rng=None))
    images = batch["images"][:1]
    with torch.no_grad():
        # The same view, looked at for two different instructions, gives two tokens.
        asked = [model._view_conditions(1, torch.zeros(1, 1, dtype=torch.long), torch.tensor([vocab.encode(text)]))
                 for text in ("where is the apple?", "come here")]
        tokens = [model.images(images, condition) for condition in asked]
    assert not torch.allclose(tokens[0], tokens[1])
    with pytest.raises(ValueError, match="needs a condition"):
        model.images(images)
    # The policy runs it in the env as any other checkpoint.
    results = run_episodes(VLAPolicy(tmp_path / "film" / FINAL), "Legent/WhereIs-OneRoom-v0", 1, 0,
                           {"width": SIZE, "height": SIZE, "max_episode_steps": 4})
    assert results[0].steps >= 1


def test_mirrored_trajectories_flip_views_and_turns(datasets):
    root = datasets["ComeHere-OneRoom"] / "legent"
    loaded = [(root, t) for t in read_trajectories(root)]
    codec = ActionCodec.fit(a for _, t in loaded for a in t.actions)
    data = encode(loaded, codec, WordVocab.fit(t.instruction for _, t in loaded), window=6)
    turn = codec.slot_id("rotate_right:0")
    mirror = mirror_slots(codec)
    assert mirror[turn] and not mirror[codec.slot_id("move_forward:0")]
    plain = next(batches(data, range(4), 4, np.random.default_rng(7)))
    flipped = next(batches(data, range(4), 4, np.random.default_rng(7), mirror))
    seen = set()  # the same order in both: the shuffle comes before the flips
    for i in range(len(plain["target_template"])):
        view = int(plain["window_images"][i, -1])
        was, now = plain["images"][view], flipped["images"][view]
        is_flipped = not torch.equal(was, now)
        if is_flipped:
            assert torch.equal(now, was.flip(-1))
        b0, b1 = int(plain["target_bins"][i, turn]), int(flipped["target_bins"][i, turn])
        if b0 >= 0:
            assert b1 == (codec.bins - 1 - b0 if is_flipped else b0)
            o0, o1 = float(plain["target_offsets"][i, turn]), float(flipped["target_offsets"][i, turn])
            assert o1 == pytest.approx(-o0 if is_flipped else o0)
        h0, h1 = plain["history_numbers"][i, :, turn], flipped["history_numbers"][i, :, turn]
        assert torch.equal(h1, -h0 if is_flipped else h0)
        s0, s1 = int(plain["target_bearing"][i]), int(flipped["target_bearing"][i])
        assert s0 >= 0 and s1 == ((BEARING_SECTORS - s0) % BEARING_SECTORS if is_flipped else s0)
        seen.add(is_flipped)
    assert seen == {True, False}  # with this seed both kinds occur
    assert torch.equal(plain["target_template"], flipped["target_template"])


def test_broken_data_is_named(datasets, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(datasets["ComeHere-OneRoom"] / "legent", copy)
    lines = (copy / "interleaved.jsonl").read_text().splitlines()
    second = json.loads(lines[1])
    second["history"] = ["move_forward(1)"]
    lines[1] = json.dumps(second)
    (copy / "interleaved.jsonl").write_text("\n".join(lines) + "\n")
    with pytest.raises(DatasetError, match=r"interleaved.jsonl:2 .*window is not"):
        read_trajectories(copy)
    (copy / "interleaved.jsonl").write_text('{"step": 0}\n')
    with pytest.raises(DatasetError, match="missing field"):
        read_trajectories(copy)
    with pytest.raises(DatasetError, match="no interleaved.jsonl"):
        read_trajectories(tmp_path / "nothing")


# -- model and training ----------------------------------------------------------------------
def test_model_learns_a_small_set_and_decodes_valid_code(datasets):
    root = datasets["WhereIs-OneRoom"] / "legent"
    loaded = [(root, t) for t in read_trajectories(root)]
    codec = ActionCodec.fit(a for _, t in loaded for a in t.actions)
    vocab = WordVocab.fit(t.instruction for _, t in loaded)
    torch.manual_seed(0)
    model = VLA(ModelConfig(image_size=SIZE, d_model=32, layers=1, ff=64, dropout=0.0), codec, len(vocab), vocab.max_words)
    data = encode(loaded, codec, vocab, window=6)
    batch = next(batches(data, range(4), 4, rng=None))
    inputs = {k: v for k, v in batch.items() if not k.startswith("target")}
    optimizer = torch.optim.Adam(model.parameters(), lr=3e-3)
    first = None
    for _ in range(100):
        loss, _ = model.loss(model(**inputs), batch)
        first = first if first is not None else loss.item()
        optimizer.zero_grad()
        loss.backward()
        optimizer.step()
    assert loss.item() < 0.1 * first
    model.eval()
    with torch.no_grad():
        texts = model.decode(model(**inputs))
    expected = [a for _, t in loaded for a in t.actions]
    assert texts[-1].startswith("speak(")
    assert sum(decompose(a).template == decompose(e).template for a, e in zip(texts, expected)) == len(expected)
    for text in texts:
        parse_actions(text)


def _config(datasets, out, **kw) -> TrainConfig:
    return TrainConfig((str(datasets["ComeHere-OneRoom"]), str(datasets["WhereIs-OneRoom"])), str(out),
                       trajectories=3, epochs=2, trajectories_per_batch=2, threads=1, **{"model": TINY, **kw})


def test_training_is_deterministic_and_resumes(datasets, tmp_path):
    a = train(_config(datasets, tmp_path / "a"), show_progress=False)
    b = train(_config(datasets, tmp_path / "b"), show_progress=False)
    wa = read_checkpoint(tmp_path / "a" / FINAL)["weights"]
    wb = read_checkpoint(tmp_path / "b" / FINAL)["weights"]
    assert all(torch.equal(wa[k], wb[k]) for k in wa) and a["train_loss"] == b["train_loss"]
    assert len((tmp_path / "a" / LOG).read_text().splitlines()) == 2
    # One epoch, stop, resume: the same weights as the uninterrupted run.
    train(_config(datasets, tmp_path / "c"), show_progress=False, stop_after=1)
    assert read_checkpoint(tmp_path / "c" / LAST)["epoch"] == 1 and not (tmp_path / "c" / FINAL).exists()
    train(_config(datasets, tmp_path / "c"), resume=True, show_progress=False)
    wc = read_checkpoint(tmp_path / "c" / FINAL)["weights"]
    assert all(torch.equal(wa[k], wc[k]) for k in wa)
    assert len((tmp_path / "c" / LOG).read_text().splitlines()) == 2
    with pytest.raises(ValueError, match="another configuration"):
        train(_config(datasets, tmp_path / "c", lr=5e-4), resume=True, show_progress=False)


def test_shifted_views_move_whole_images_and_repeat_the_edges():
    views = torch.arange(2 * 3 * 8 * 8, dtype=torch.uint8).reshape(2, 3, 8, 8)
    generator = torch.Generator().manual_seed(0)
    moved = shift_views(views, 2, generator)
    assert moved.shape == views.shape and moved.dtype == torch.uint8
    assert torch.equal(shift_views(views, 0, generator), views)
    for view, shifted in zip(views, moved):
        # Some (dy, dx) in [-2, 2]^2 explains every pixel: the view moved, edges repeated.
        found = [(dy, dx) for dy in range(-2, 3) for dx in range(-2, 3)
                 if torch.equal(shifted, view[:, (torch.arange(8) + dy).clamp(0, 7)][:, :, (torch.arange(8) + dx).clamp(0, 7)])]
        assert len(found) == 1
    # Many views: every offset occurs, so the shift is drawn per view.
    many = shift_views(torch.zeros(200, 1, 8, 8, dtype=torch.uint8).index_fill_(3, torch.tensor([4]), 255), 2,
                       generator)
    assert len({int(v[0, 0].argmax()) for v in many}) == 5


def test_shift_trains_and_is_part_of_the_configuration(datasets, tmp_path):
    plain = train(_config(datasets, tmp_path / "plain"), show_progress=False)
    shifted = train(_config(datasets, tmp_path / "shifted", shift=3), show_progress=False)
    assert np.isfinite(shifted["train_loss"]) and shifted["train_loss"] != plain["train_loss"]
    stored = read_checkpoint(tmp_path / "shifted" / FINAL)["train_config"]
    assert stored["shift"] == 3 and _config(datasets, tmp_path / "shifted", shift=3).matches(stored)
    assert not _config(datasets, tmp_path / "shifted").matches(stored)
    # A checkpoint written before the field existed is the same run as shift=0.
    old = {k: v for k, v in read_checkpoint(tmp_path / "plain" / FINAL)["train_config"].items() if k != "shift"}
    assert _config(datasets, tmp_path / "plain").matches(old)
    assert not _config(datasets, tmp_path / "plain", shift=3).matches(old)
    # ... and so is one whose model lacks a later model field (film, default False).
    old["model"] = {k: v for k, v in old["model"].items() if k != "film"}
    assert _config(datasets, tmp_path / "plain").matches(old)
    old["model"]["unknown_field"] = 1  # written by newer code: not this run
    assert not _config(datasets, tmp_path / "plain").matches(old)
    with pytest.raises(ValueError, match="shift must be in"):
        _config(datasets, tmp_path, shift=16)


def test_training_rejects_mismatched_data(datasets, tmp_path):
    with pytest.raises(DatasetError, match="4 trajectories, 9 wanted"):
        train(TrainConfig((str(datasets["ComeHere-OneRoom"]),), str(tmp_path), trajectories=9, model=TINY),
              show_progress=False)
    with pytest.raises(DatasetError, match="views are 32x32 but the model takes 48x48"):
        train(TrainConfig((str(datasets["ComeHere-OneRoom"]),), str(tmp_path), epochs=1,
                          model=ModelConfig(image_size=48, d_model=32, layers=1)), show_progress=False)
    with pytest.raises(ValueError, match="multiple of 16"):
        ModelConfig(image_size=40)


# -- policy and evaluation -------------------------------------------------------------------
@pytest.fixture(scope="module")
def checkpoint(datasets, tmp_path_factory):
    out = tmp_path_factory.mktemp("vla-model")
    train(_config(datasets, out), show_progress=False)
    return out / FINAL


def test_policy_acts_in_the_env_with_the_papers_window(checkpoint):
    policy = VLAPolicy(checkpoint)
    assert policy.window == 6 and policy.env_kwargs == {"width": SIZE, "height": SIZE}
    results = run_episodes(policy, "Legent/ComeHere-OneRoom-v0", 1, seed=3, env_kwargs=policy.env_kwargs)
    assert results[0].steps >= 1
    assert len(policy._views) == min(results[0].steps, 6) and len(policy._actions) <= 5
    for text in policy._actions:
        parse_actions(text)
    policy.reset("Come here.")
    with pytest.raises(ValueError, match="trained on 32x32"):
        policy.act({"rgb": np.zeros((48, 48, 3), np.uint8)})
    model, _ = load_model(checkpoint)
    assert not model.training


def test_evaluation_is_deterministic_and_bounded(checkpoint):
    jobs = [(str(checkpoint), "Legent/ComeHere-OneRoom-v0"), (RANDOM, "Legent/ComeHere-OneRoom-v0"),
            (EXPERT, "Legent/ComeHere-OneRoom-v0")]
    kwargs = {"width": SIZE, "height": SIZE}
    first = evaluate_many(jobs, 2, 0, kwargs)
    second = evaluate_many(jobs, 2, 0, kwargs)
    assert first == second
    assert [r.seed for r in first[0]] == [0, 1]
    assert all(r.success for r in first[2])  # the expert solves what the others are measured on
    with pytest.raises(FileNotFoundError, match="neither 'random', 'expert' nor a checkpoint"):
        evaluate_many([("nope.pt", "Legent/ComeHere-OneRoom-v0")], 1, 0, kwargs)
    with pytest.raises(ValueError, match="unknown environment id"):
        evaluate_many([(RANDOM, "Legent/Nope-v0")], 1, 0, kwargs)


def test_evaluate_cli(checkpoint, capsys):
    assert evaluate_main(["--policy", str(checkpoint), "--env", "Legent/WhereIs-OneRoom-v0",
                          "--episodes", "1", "--seed", "5"]) == 0
    assert "success" in capsys.readouterr().out
    assert evaluate_main(["--policy", "missing.pt", "--env", "Legent/ComeHere-OneRoom-v0"]) == 2
    assert "neither 'random', 'expert' nor a checkpoint" in capsys.readouterr().err
    # Further env arguments: the expert asked LEGENT's Where Is questions.
    paper = '{"task_options": {"objects": ["orange", "apple", "banana", "cola_can"], "receptacles": ["sofa", "chair", "side_table", "coffee_table", "dresser"]}}'
    assert evaluate_main(["--policy", "expert", "--env", "Legent/WhereIs-OneRoom-v0", "--episodes", "3",
                          "--image-size", str(SIZE), "--env-kwargs", paper, "--json"]) == 0
    episodes = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line.startswith("{")]
    assert len(episodes) == 3 and all(e["success"] for e in episodes)
    assert all(any(w in e["instruction"] for w in ("orange", "apple", "banana", "cola")) for e in episodes)
    assert evaluate_main(["--policy", "random", "--env", "Legent/WhereIs-OneRoom-v0", "--env-kwargs", "{oops"]) == 2
    assert "--env-kwargs is not valid JSON" in capsys.readouterr().err


def test_train_cli(datasets, tmp_path, capsys):
    from baselines.vla.train import main as train_main

    args = ["--data", str(datasets["ComeHere-OneRoom"]), "--out", str(tmp_path / "m"), "--trajectories", "2",
            "--epochs", "1", "--image-size", str(SIZE), "--d-model", "32", "--layers", "1", "--threads", "1",
            "--quiet"]
    assert train_main(args) == 0
    assert json.loads(capsys.readouterr().out.strip().splitlines()[-1])["trajectories"] == 2
    assert (tmp_path / "m" / FINAL).is_file()
    assert train_main(["--data", str(tmp_path / "nothing"), "--out", str(tmp_path / "x")]) == 2
    assert "no interleaved.jsonl" in capsys.readouterr().err
    # The image encoder's widths, the auxiliary losses and the device are options too.
    wide = args[:-1] + ["--out", str(tmp_path / "w"), "--channels", "8,16,32,32", "--aux-weight", "0.3",
                        "--device", "cpu", "--film", "--quiet"]
    assert train_main(wide) == 0
    config = read_checkpoint(tmp_path / "w" / FINAL)["config"]
    assert list(config["channels"]) == [8, 16, 32, 32] and config["aux_weight"] == 0.3 and config["film"]
    assert train_main(args[:-1] + ["--channels", "8,x", "--quiet"]) == 2
    assert "--channels must be comma-separated integers" in capsys.readouterr().err


# -- DAgger ----------------------------------------------------------------------------------
def test_dagger_labels_every_state_the_learner_reached_with_the_expert(checkpoint, tmp_path):
    from baselines.vla.dagger import DaggerConfig, collect_dagger
    from legent_gym.data.legent_format import load_trajectories
    from legent_gym.wrappers.expert import ExpertInfo

    config = DaggerConfig(str(checkpoint), "Legent/ComeHere-OneRoom-v0", str(tmp_path / "d1"), 3, 20_000_000)
    summary = collect_dagger(config, show_progress=False)
    assert summary["episodes"] == 3 and 0.0 <= summary["learner_success"] <= 1.0
    trajectories = load_trajectories(tmp_path / "d1" / "legent")
    assert [t["seed"] for t in trajectories] == [20_000_000, 20_000_001, 20_000_002]
    assert summary["steps"] == sum(t["steps"] for t in trajectories)
    assert 0 <= summary["steps_unlike_expert"] <= summary["steps"]
    # Replay what the learner executed: at every state, the label is the expert's action there.
    env = ExpertInfo(gym.make("Legent/ComeHere-OneRoom-v0", width=SIZE, height=SIZE))
    try:
        for trajectory in trajectories:
            obs, info = env.reset(seed=trajectory["seed"])
            for step in trajectory["interactions"][1]["trajectory"]:
                if step.get("after_end"):  # LEGENT's closing finish(), after the episode ended
                    break
                assert step["expert_action"] == info["expert_action"]
                obs, _, terminated, truncated, info = env.step(step["action"])
            assert terminated or truncated
            assert bool(info["success"]) == trajectory["success"]  # failed rollouts are kept too
    finally:
        env.close()
    # The training lines: the learner's actions in the history, the expert's as the target.
    lines = [json.loads(line) for line in (tmp_path / "d1" / "legent" / "interleaved.jsonl").open()]
    assert len(lines) == summary["steps"] and all("executed" in line for line in lines)
    # The same checkpoint and seeds give the same data, with any number of workers.
    again = DaggerConfig(str(checkpoint), "Legent/ComeHere-OneRoom-v0", str(tmp_path / "d2"), 3, 20_000_000,
                         workers=2)
    collect_dagger(again, show_progress=False)
    assert (tmp_path / "d2" / "legent" / "interleaved.jsonl").read_text() == \
        (tmp_path / "d1" / "legent" / "interleaved.jsonl").read_text()
    # A finished folder is kept as it is (also asked with another worker count); other
    # arguments into it are refused by name.
    assert collect_dagger(config, show_progress=False) == summary
    assert collect_dagger(dataclasses.replace(config, workers=2), show_progress=False) == summary
    with pytest.raises(ValueError, match="other arguments"):
        collect_dagger(DaggerConfig(str(checkpoint), "Legent/ComeHere-OneRoom-v0", str(tmp_path / "d1"), 4,
                                    20_000_000), show_progress=False)
    with pytest.raises(ValueError, match="other arguments"):
        collect_dagger(dataclasses.replace(config, env_kwargs={"reward": "dense"}), show_progress=False)
    # A summary written before env_kwargs existed is the same collection (rolled out with none).
    stored = json.loads((tmp_path / "d1" / "dagger.json").read_text())
    del stored["config"]["env_kwargs"]
    (tmp_path / "d1" / "dagger.json").write_text(json.dumps(stored))
    assert collect_dagger(config, show_progress=False)["episodes"] == 3
    # The rollouts train a model next to the demonstrations (each dataset with its own limit).
    out = tmp_path / "m"
    metrics = train(TrainConfig((str(tmp_path / "d1"),), str(out), (2,), 1, threads=1,
                                model=ModelConfig(image_size=SIZE, d_model=32, layers=1)), show_progress=False)
    assert metrics["trajectories"] == 2


def test_dagger_cli_names_bad_arguments(checkpoint, tmp_path, capsys):
    from baselines.vla.dagger import main as dagger_main

    base = ["--env", "Legent/ComeHere-OneRoom-v0", "--episodes", "1", "--seed", "20000000", "--quiet"]
    assert dagger_main(["--policy", str(tmp_path / "none.pt"), "--out", str(tmp_path / "a"), *base]) == 2
    assert "is not a checkpoint file" in capsys.readouterr().err
    bad_env = ["--policy", str(checkpoint), "--out", str(tmp_path / "b"), *base]
    bad_env[bad_env.index("Legent/ComeHere-OneRoom-v0")] = "Legent/Nope-v0"
    assert dagger_main(bad_env) == 2 and "unknown environment id" in capsys.readouterr().err
    bad_strategy = ["--policy", str(checkpoint), "--out", str(tmp_path / "b"), *base, "--find-strategy", "peek"]
    assert dagger_main(bad_strategy) == 2 and "--find-strategy must be one of direct, scan" in capsys.readouterr().err
    assert dagger_main([*bad_strategy[:-2], "--env-kwargs", "{not json"]) == 2
    assert "--env-kwargs is not valid JSON" in capsys.readouterr().err
    assert dagger_main([*bad_strategy[:-2], "--env-kwargs", '{"width": 32}']) == 2
    assert "--env-kwargs may not set width" in capsys.readouterr().err
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "stray.txt").write_text("x")
    assert dagger_main(["--policy", str(checkpoint), "--out", str(tmp_path / "c"), *base]) == 2
    assert "not a finished DAgger collection" in capsys.readouterr().err
    assert dagger_main(["--policy", str(checkpoint), "--out", str(tmp_path / "d"), *base]) == 0
    assert "learner success" in capsys.readouterr().out


def test_per_dataset_trajectory_limits_are_checked():
    with pytest.raises(ValueError, match="2 limits for 1 datasets"):
        TrainConfig(("a",), "out", (1, None))
    with pytest.raises(ValueError, match="trajectories must be >= 1"):
        TrainConfig(("a", "b"), "out", (0, None))
    assert TrainConfig(("a", "b"), "out", (5, None)).to_dict()["trajectories"] == [5, None]


def test_a_trained_vla_drives_the_agent_in_legent_gym_play(checkpoint):
    """`legent-gym play ENV --partner baselines.vla.policy:partner:CHECKPOINT`: the session's partner is the model,
    made with the view size it was trained on, reset with the person's instruction."""
    pytest.importorskip("pettingzoo")
    from legent_gym.play.session import PlaySession

    session = PlaySession("Legent/ComeHere-OneRoom-v0", partner=f"baselines.vla.policy:partner:{checkpoint}", size=(64, 48))
    try:
        assert session.obs["agent"]["rgb"].shape == (SIZE, SIZE, 3)
        session.say("Come here.")  # the person's first words are the agent's instruction
        assert session.agent_instructed
        for _ in range(3):
            assert session.tick()
        assert session.partner_error == "" and session.partner.instruction == "Come here."
        assert len(session.partner.policy._actions) >= 3
    finally:
        session.close()
    with pytest.raises(ValueError, match="no checkpoint file"):
        PlaySession("Legent/ComeHere-OneRoom-v0", partner="baselines.vla.policy:partner:/no/such/model.pt")
