"""The VLM fine-tuning recipe (baselines/vlm) on a tiny, randomly initialised LLaVA built
offline from its config, saved and loaded back through from_pretrained, and real data
from `legent-gym collect`: loss masking, overfitting to exact action codes, evaluation in
the env through evaluate.py, resume, LoRA, errors, and the table."""

from __future__ import annotations

import json

import pytest

torch = pytest.importorskip("torch", reason="install the 'baselines' extra: pip install -e '.[baselines]'")
pytest.importorskip("transformers", reason="install the 'vlm' extra: pip install -e '.[vlm]'")
pytest.importorskip("peft", reason="install the 'vlm' extra: pip install -e '.[vlm]'")

from baselines.evaluate import main as evaluate_main  # noqa: E402
from baselines.evaluate import run_episodes as run_episodes_one  # noqa: E402
from baselines.vla.dataset import DatasetError, read_trajectories  # noqa: E402
from baselines.vla.evaluate import main as vla_evaluate_main  # noqa: E402
from baselines.vlm.data import IGNORE, Encoder, read_samples  # noqa: E402
from baselines.vlm.model import ModelError, load_model, load_processor  # noqa: E402
from baselines.vlm.policy import VLMPolicy, run_episodes  # noqa: E402
from baselines.vlm.tiny import build_tiny_model  # noqa: E402
from baselines.vlm.train import FINAL, LAST, FinetuneConfig, train  # noqa: E402
from baselines.vlm.train import main as train_main  # noqa: E402
from legent_gym.data import CollectConfig, collect  # noqa: E402
from legent_gym.data.legent_format import read_png  # noqa: E402

SIZE = 32
ENV = "Legent/ComeHere-OneRoom-v0"
torch.set_num_threads(1)  # the machine's cores are shared


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    root = tmp_path_factory.mktemp("vlm")
    collect(CollectConfig(ENV, 4, str(root / "data"), formats=("legent",), seed=0,
                          env_kwargs={"width": SIZE, "height": SIZE}), show_progress=False)
    base = build_tiny_model(root / "tiny", image_size=SIZE)
    return root, base


@pytest.fixture(scope="module")
def overfit(setup):
    """The tiny model fine-tuned (full) until it reproduces its four trajectories."""
    root, base = setup
    config = FinetuneConfig(str(base), (str(root / "data"),), str(root / "full"), epochs=60, batch_size=2,
                            grad_accum=1, lr=5e-3, weight_decay=0.1, warmup=0.0, lora=False)
    metrics = train(config, resume=False, show_progress=False)
    return root / "full" / FINAL, metrics


def test_only_the_reply_is_trained_on(setup):
    root, base = setup
    processor = load_processor(str(base))
    encoder = Encoder(processor)
    samples = read_samples([root / "data"])
    batch = encoder.batch(samples[:3])
    tokenizer = processor.tokenizer
    image_id = tokenizer.convert_tokens_to_ids("<image>")
    for row, sample in enumerate(samples[:3]):
        ids, labels, mask = batch["input_ids"][row], batch["labels"][row], batch["attention_mask"][row]
        trained = (labels != IGNORE).nonzero().flatten().tolist()
        assert trained == list(range(trained[0], int(mask.sum()))), "one span, up to the last real token"
        # The span is exactly the reply: the action code and the template's end of turn.
        assert tokenizer.decode(ids[trained]) == sample.target + "<|im_end|>\n"
        assert (labels[trained] == ids[trained]).all()
        # Everything before it (instruction, views, history, the generation prompt) is not.
        prompt = tokenizer.decode(ids[: trained[0]])
        assert prompt.endswith("<|im_start|>assistant\n") and sample.instruction in prompt
        assert all(action in prompt for action in sample.history)
        assert int((ids == image_id).sum()) == len(sample.images) * (SIZE // 8) ** 2
        assert (labels[ids == image_id] == IGNORE).all()
    assert (batch["labels"][batch["attention_mask"] == 0] == IGNORE).all(), "padding is not trained on"
    assert batch["pixel_values"].shape[0] == sum(len(s.images) for s in samples[:3])


def test_finetuned_model_reproduces_its_data_and_succeeds_in_the_env(setup, overfit, capsys):
    root, _ = setup
    final, metrics = overfit
    assert metrics["finished"] and metrics["token_accuracy"] > 0.95
    meta = json.loads((final / "legent_vlm.json").read_text())
    assert (meta["width"], meta["height"]) == (SIZE, SIZE)
    # Reloaded through from_pretrained: every action code of the data, teacher-forced.
    policy = VLMPolicy(final)
    data = root / "data" / "legent"
    trajectories = read_trajectories(data)
    for traj in trajectories:
        episode = policy.new_episode(traj.instruction)
        for n, path in enumerate(traj.image_paths):
            assert policy.act_batch([episode], [{"rgb": read_png(data / path)}]) == [traj.labels[n]]
    assert policy.fallbacks == []
    # In the env, on the seeds the data was collected on: it replays the expert and succeeds.
    assert evaluate_main(["--policy", f"vlm:{final}", "--env", ENV, "--episodes", "4", "--seed", "0", "--json"]) == 0
    lines = capsys.readouterr().out.splitlines()
    episodes = [json.loads(line) for line in lines if line.startswith("{")]
    assert [e["success"] for e in episodes] == [True] * 4
    assert [e["steps"] for e in episodes] == [len(t.actions) for t in trajectories]
    assert "success 1.000 over 4 episodes" in lines[-1]
    # The VLA's evaluator takes the same spec (and the model's view size from the folder).
    assert vla_evaluate_main(["--policy", f"vlm:{final}", "--env", ENV, "--episodes", "2"]) == 0
    assert "success 1.000 over 2 episodes" in capsys.readouterr().out
    # Batched decoding (4 episodes in lockstep) gives what one episode at a time gives.
    env_kwargs = {"width": SIZE, "height": SIZE}
    assert run_episodes(policy, ENV, 3, 100, env_kwargs, batch=3) == run_episodes_one(policy, ENV, 3, 100, env_kwargs)


def test_resume_gives_the_uninterrupted_weights(setup):
    root, base = setup
    config = FinetuneConfig(str(base), (str(root / "data"),), str(root / "a"), epochs=2, batch_size=4,
                            grad_accum=2, lr=1e-3, lora=False, save_every=1)
    whole = train(config, resume=False, show_progress=False)
    split = FinetuneConfig(**{**config.__dict__, "out": str(root / "b")})
    first = train(split, resume=False, show_progress=False, max_steps=2)
    assert not first["finished"] and first["steps"] == 2
    assert (root / "b" / LAST / "state.pt").is_file() and not (root / "b" / FINAL).exists()
    rest = train(split, show_progress=False)
    assert rest["finished"] and rest["steps"] == whole["steps"] == 4
    a, b = load_model(str(root / "a" / FINAL)).state_dict(), load_model(str(root / "b" / FINAL)).state_dict()
    assert a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)
    other = FinetuneConfig(**{**split.__dict__, "lr": 2e-3})
    with pytest.raises(ValueError, match="another configuration"):
        train(other, show_progress=False, max_steps=1)


@pytest.mark.parametrize("dtype", ["auto", "bf16"])
def test_lora_merges_into_a_plain_model(setup, dtype):
    """auto: float32 on a CPU, bfloat16 on a GPU; bf16: bfloat16 training on any device. The
    merged model is the float32 base with the adapter added: the frozen vision encoder
    keeps the base's weights bit for bit (not rounded to bfloat16)."""
    root, base = setup
    config = FinetuneConfig(str(base), (str(root / "data"),), str(root / f"lora-{dtype}"), limit=2, epochs=2,
                            batch_size=4, grad_accum=1, lr=1e-2, lora_rank=4, lora_dropout=0.0, dtype=dtype)
    first = train(config, resume=False, show_progress=False, max_steps=1)  # then resumed from the adapter
    assert not first["finished"] and (root / f"lora-{dtype}" / LAST / "adapter_config.json").is_file()
    metrics = train(config, show_progress=False)
    assert metrics["finished"] and metrics["steps"] == 4  # 2 trajectories, 6 samples: 2 steps an epoch
    assert 0 < metrics["trainable_parameters"] < metrics["parameters"] / 2
    before = load_model(str(base)).state_dict()
    after = load_model(str(root / f"lora-{dtype}" / FINAL)).state_dict()  # no peft wrapper: merged
    assert before.keys() == after.keys()
    assert {v.dtype for v in after.values()} == {torch.float32}, "written in the base's dtype"
    changed = {k for k in before if not torch.equal(before[k], after[k])}
    assert any("language_model" in k and "q_proj" in k for k in changed)
    assert not any("vision_tower" in k for k in changed), "the vision encoder stays frozen"
    assert not any("lora" in k for k in after)


def test_full_finetuning_in_bf16_keeps_the_frozen_encoder(setup):
    """Full fine-tuning in bfloat16 (a GPU's default, forced here on any device): the final
    model is the float32 base with the trained weights put in; the frozen vision encoder
    is the base's bit for bit."""
    root, base = setup
    config = FinetuneConfig(str(base), (str(root / "data"),), str(root / "full-bf16"), limit=2, epochs=1,
                            batch_size=4, grad_accum=1, lr=1e-3, lora=False, dtype="bf16")
    assert train(config, resume=False, show_progress=False)["finished"]
    before = load_model(str(base)).state_dict()
    after = load_model(str(root / "full-bf16" / FINAL)).state_dict()
    assert before.keys() == after.keys() and {v.dtype for v in after.values()} == {torch.float32}
    changed = {k for k in before if not torch.equal(before[k], after[k])}
    assert any("language_model" in k and "q_proj" in k for k in changed)
    assert not any("vision_tower" in k for k in changed), "the vision encoder stays frozen"


def test_errors_name_what_is_wrong(setup, tmp_path, capsys):
    root, base = setup
    with pytest.raises(ModelError, match="no config.json"):
        VLMPolicy(tmp_path)
    with pytest.raises(ModelError, match="is a file"):
        VLMPolicy(base / "config.json")
    with pytest.raises(ModelError, match="no model folder"):
        VLMPolicy(tmp_path / "missing")
    assert evaluate_main(["--policy", f"vlm:{tmp_path}", "--episodes", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "no config.json" in err
    assert evaluate_main(["--policy", "greedy", "--episodes", "1"]) == 2
    assert "--policy must be 'random' or vlm:PATH" in capsys.readouterr().err
    with pytest.raises(DatasetError, match="interleaved.jsonl"):
        train(FinetuneConfig(str(base), (str(tmp_path),), str(tmp_path / "out")), show_progress=False)
    assert train_main(["--model", str(tmp_path), "--data", str(root / "data"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no config.json" in err


@pytest.mark.slow
def test_table(tmp_path, capsys):
    """reproduce_table.py --scale small --model vlm:<tiny model>, end to end (data, seven
    fine-tuning runs, evaluation of every row on the four tasks, the tables)."""
    from baselines.reproduce_table import EVAL_TASKS
    from baselines.reproduce_table import main as table_main

    base = build_tiny_model(tmp_path / "tiny", image_size=48)
    out = tmp_path / "table"
    assert table_main(["--scale", "small", "--model", f"vlm:{base}", "--vlm-epochs", "1", "--out", str(out)]) == 0
    results = json.loads((out / "results.json").read_text())
    assert list(results["success_rates"]) == ["Random", "VLM-Sep 10 (ours)", "VLM-Sep 20 (ours)",
                                              "VLM-Joint 20 (ours)", "Expert (privileged)"]
    assert all(set(rates) == set(EVAL_TASKS) for rates in results["success_rates"].values())
    assert results["success_rates"]["Expert (privileged)"]["ComeHere-OneRoom"] == 1.0
    assert len(results["training"]) == 7 and all(r["metrics"]["finished"] for r in results["training"].values())
    assert "VLM-Joint 20 (ours)" in (out / "table.md").read_text()
    assert (out / "vlm" / "joint20" / FINAL / "legent_vlm.json").is_file()
    # A model that is not one: refused in one line before any data is collected.
    assert table_main(["--scale", "small", "--model", f"vlm:{tmp_path / 'none'}", "--out", str(tmp_path / "t2")]) == 2
    assert "no model folder" in capsys.readouterr().err and not (tmp_path / "t2" / "data").exists()


@pytest.mark.slow
def test_two_processes(setup, tmp_path):
    """Data-parallel training (the several-GPU path) with two CPU processes (gloo): each takes
    every other micro-batch, the gradients are averaged, one final model is written."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root, base = setup
    repo = Path(__file__).resolve().parents[2]
    command = [sys.executable, "-m", "torch.distributed.run", "--nproc_per_node", "2", "-m", "baselines.vlm.train",
               "--model", str(base), "--data", str(root / "data"), "--out", str(tmp_path / "ddp"), "--epochs", "2",
               "--batch-size", "2", "--grad-accum", "2", "--full"]
    env = {**os.environ, "PYTHONPATH": str(repo), "OMP_NUM_THREADS": "1"}
    done = subprocess.run(command, capture_output=True, text=True, cwd=repo, env=env, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    reports = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    # 13 samples in 7 micro-batches of 2: 4 and 3 per process, 2 optimizer steps an epoch each.
    assert [(r["processes"], r["steps"], r["finished"]) for r in reports] == [(2, 4, True)] * 2
    before, after = load_model(str(base)).state_dict(), load_model(str(tmp_path / "ddp" / FINAL)).state_dict()
    assert any(not torch.equal(before[k], after[k]) for k in before if "language_model" in k)


def test_idefics3(setup, tmp_path):
    """Another architecture through the same code: Idefics3 (SmolVLM's), whose processor
    pads each batch's views into (batch, views, 3, H, W) and frames every view with its own
    tokens. The reply alone is trained on; the model trains, reloads, and decodes the same
    episodes batched as one at a time."""
    root, _ = setup
    base = build_tiny_model(tmp_path / "tiny", image_size=SIZE, architecture="idefics3")
    processor = load_processor(str(base))
    samples = read_samples([root / "data"])[:3]
    batch = Encoder(processor).batch(samples)
    assert tuple(batch["pixel_values"].shape) == (3, max(len(s.images) for s in samples), 3, SIZE, SIZE)
    for row, sample in enumerate(samples):
        trained = (batch["labels"][row] != IGNORE).nonzero().flatten()
        assert processor.tokenizer.decode(batch["input_ids"][row][trained]) == sample.target + "<end_of_utterance>\n"
    config = FinetuneConfig(str(base), (str(root / "data"),), str(tmp_path / "run"), epochs=24, batch_size=2,
                            grad_accum=1, lr=5e-3, weight_decay=0.1, warmup=0.0, lora=False)
    metrics = train(config, resume=False, show_progress=False)
    assert metrics["finished"] and metrics["token_accuracy"] > 0.5
    policy = VLMPolicy(tmp_path / "run" / FINAL, max_new_tokens=24)
    env_kwargs = {"width": SIZE, "height": SIZE}
    batched = run_episodes(policy, ENV, 2, 0, env_kwargs, batch=2)
    assert batched == run_episodes_one(policy, ENV, 2, 0, env_kwargs)
    assert len(policy.fallbacks) < policy.replies  # it writes action code
