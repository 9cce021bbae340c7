"""Recording and export: Minari round trip, LEGENT's format, the interleaved JSONL, video."""

from __future__ import annotations

import json

import minari
import numpy as np
import pytest

from legent_gym.agent.actions import parse_actions
from legent_gym.cli import main
from legent_gym.data import CollectConfig, collect
from legent_gym.data.legent_format import (
    build_prompt,
    interleaved_records,
    load_interleaved,
    load_trajectories,
    read_png,
)
from legent_gym.data.minari_store import load_minari_dataset
from legent_gym.data.video import read_video

ENV_ID = "Legent/ComeHere-OneRoom-v0"
SIZE = 48
DATASET_ID = "legent/ComeHere-OneRoom/expert-v0"


@pytest.fixture(scope="module")
def collected(tmp_path_factory):
    out = tmp_path_factory.mktemp("collected")
    summary = collect(CollectConfig(ENV_ID, 3, str(out), formats=("minari", "legent", "video"),
                                    env_kwargs={"width": SIZE, "height": SIZE}), show_progress=False)
    assert summary.episodes == 3 and summary.new_episodes == 3
    return out


def test_minari_round_trip_and_recovered_env_replays_the_episode(collected, monkeypatch):
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(collected / "minari"))
    dataset = minari.load_dataset(DATASET_ID)
    assert dataset.total_episodes == 3
    assert dataset.storage.metadata["jpeg_encoding"] is False
    episodes = list(dataset.iterate_episodes())
    assert dataset.total_steps == sum(len(e.actions) for e in episodes)
    seeds = [m["seed"] for m in dataset.storage.get_episode_metadata(range(3))]
    assert seeds == sorted(set(seeds))
    env = dataset.recover_environment()
    assert env.spec.id == ENV_ID and env.spec.kwargs["width"] == SIZE
    for episode, seed in zip(episodes, seeds):
        assert episode.observations["rgb"].shape == (len(episode.actions) + 1, SIZE, SIZE, 3)
        assert episode.terminations[-1] and episode.infos["success"][-1]
        assert not episode.infos["success"][:-1].any()
        # Lossless and deterministic: the recovered env, replayed, gives the stored pixels.
        obs, _ = env.reset(seed=seed)
        assert np.array_equal(obs["rgb"], episode.observations["rgb"][0])
        assert obs["instruction"] == episode.observations["instruction"][0]
        for n, action in enumerate(episode.actions):
            obs, reward, terminated, _, _ = env.step(action)
            assert np.array_equal(obs["rgb"], episode.observations["rgb"][n + 1])
            assert reward == episode.rewards[n] and terminated == episode.terminations[n]
    env.close()


def test_legent_json_loads_and_its_images_equal_the_recorded_observations(collected):
    trajectories = load_trajectories(collected / "legent")
    dataset = load_minari_dataset(collected / "minari", DATASET_ID)
    assert [t["id"] for t in trajectories] == ["000000", "000001", "000002"]
    for trajectory, episode in zip(trajectories, dataset.iterate_episodes()):
        on_disk = json.loads((collected / "legent" / trajectory["id"] / "trajectory.json").read_text())
        assert on_disk == trajectory
        human, agent = trajectory["interactions"]
        assert human == {"from": "human", "text": episode.observations["instruction"][0]}
        *steps, closing = agent["trajectory"]  # LEGENT's closing finish() of a successful Come Here
        assert agent["from"] == "agent" and len(steps) == len(episode.actions)
        assert closing == {"image": f"{trajectory['id']}/{len(steps):04d}.png", "action": "finish()",
                           "after_end": True, "goal_view": closing["goal_view"]}
        for n, step in enumerate(agent["trajectory"]):
            assert step["image"] == f"{trajectory['id']}/{n:04d}.png"
            assert np.array_equal(read_png(collected / "legent" / step["image"]), episode.observations["rgb"][n])
        for n, step in enumerate(steps):
            assert parse_actions(step["action"]) == parse_actions(episode.actions[n])
        assert not (collected / "legent" / trajectory["id"] / f"{len(steps) + 1:04d}.png").exists()


def test_interleaved_jsonl_follows_the_contract(collected):
    trajectories = load_trajectories(collected / "legent")
    lines = load_interleaved(collected / "legent")
    assert len(lines) == sum(len(t["interactions"][1]["trajectory"]) - 1 for t in trajectories)  # no closing finish()
    first = trajectories[0]
    line = lines[0]
    assert set(line) == {"trajectory", "step", "instruction", "images", "history", "prompt", "action",
                         "task", "env_id", "seed", "goal_view"}
    assert line["goal_view"] == first["interactions"][1]["trajectory"][0]["goal_view"]
    assert line["trajectory"] == first["id"] and line["step"] == 0 and line["task"] == "ComeHere"
    assert line["env_id"] == ENV_ID and line["seed"] == first["seed"]
    assert line["images"] == [f"{first['id']}/0000.png"] and line["history"] == []
    assert line["prompt"] == f"Instruction: {first['interactions'][0]['text']} Observation: <image> Action:"
    for record in lines:
        assert len(record["history"]) == len(record["images"]) - 1 <= 5
        assert all((collected / "legent" / image).is_file() for image in record["images"])


def test_interleaved_window_and_prompt_on_a_long_trajectory():
    steps = [{"image": f"t/{n:04d}.png", "action": f"rotate_right({n})"} for n in range(9)]
    record = {"id": "t", "interactions": [{"from": "human", "text": "Come here."},
                                          {"from": "agent", "trajectory": steps}],
              "task": {"name": "ComeHere"}, "env_id": ENV_ID, "seed": 4}
    lines = interleaved_records(record, window=6)
    assert len(lines) == 9
    last = lines[8]
    assert last["images"] == [f"t/{n:04d}.png" for n in range(3, 9)]
    assert last["history"] == [f"rotate_right({n})" for n in range(3, 8)]
    assert last["action"] == "rotate_right(8)" and last["step"] == 8
    assert last["prompt"] == ("Instruction: Come here. " + " ".join(
        f"Observation: <image> Action: rotate_right({n})" for n in range(3, 8)) + " Observation: <image> Action:")
    assert last["prompt"].count("<image>") == len(last["images"])
    assert interleaved_records(record, window=2)[5]["images"] == ["t/0004.png", "t/0005.png"]
    assert build_prompt("Go.", []) == "Instruction: Go. Observation: <image> Action:"
    with pytest.raises(ValueError, match="window"):
        interleaved_records(record, window=0)


def test_video_has_one_frame_per_view_and_the_map_shows_the_path(collected):
    dataset = load_minari_dataset(collected / "minari", DATASET_ID)
    for index, episode in enumerate(dataset.iterate_episodes()):
        video = collected / "video" / f"{index:06d}.mp4"
        import av

        with av.open(str(video)) as container:
            assert container.streams.video[0].codec_context.name == "h264"
        frames = read_video(video)
        assert len(frames) == len(episode.actions) + 1
        assert frames[0].shape[0] % 2 == 0 and frames[0].shape[1] >= 320
        # The view fills the top of the frame (scaled up, lossy): close to the observation.
        scale = frames[0].shape[1] // SIZE
        top = frames[0][:SIZE * scale:scale, ::scale][:SIZE, :SIZE].astype(int)
        assert np.abs(top - episode.observations["rgb"][0].astype(int)).mean() < 12
        path_map = read_png(collected / "video" / f"{index:06d}_map.png")
        path_colour = np.all(path_map == (230, 120, 20), axis=-1)
        assert path_map.shape[0] > 100 and path_colour.sum() > 10


def test_continuous_actions_round_trip(tmp_path):
    collect(CollectConfig(ENV_ID, 2, str(tmp_path), formats=("minari", "legent"),
                          env_kwargs={"width": 32, "height": 32, "action_type": "continuous"}), show_progress=False)
    dataset = load_minari_dataset(tmp_path / "minari", DATASET_ID)
    env = dataset.recover_environment()
    episode = dataset[0]
    assert set(episode.actions) == set(env.action_space.spaces)
    assert isinstance(episode.actions["speak"], list)
    obs, _ = env.reset(seed=dataset.storage.get_episode_metadata([0]).__next__()["seed"])
    for n in range(len(episode.rewards)):
        action = {key: np.asarray(values[n]) if isinstance(values, np.ndarray) else values[n]
                  for key, values in episode.actions.items()}
        assert env.action_space.contains(action)
        obs, *_ = env.step(action)
        assert np.array_equal(obs["rgb"], episode.observations["rgb"][n + 1])
    steps = load_trajectories(tmp_path / "legent")[0]["interactions"][1]["trajectory"]
    assert steps[-1]["after_end"] and len(steps) == len(episode.rewards) + 1  # LEGENT's closing finish()
    assert parse_actions(steps[0]["action"])  # exported as action code


def test_collect_errors_are_clear(tmp_path, collected, capsys):
    def run(*extra: str) -> str:
        assert main(["collect", ENV_ID, "--episodes", "2", "--out", str(tmp_path / "x"), "--quiet", *extra]) == 2
        return capsys.readouterr().err

    assert "unknown format(s) hdf6" in run("--format", "minari,hdf6")
    assert "--episodes must be >= 1" in main_error(["collect", ENV_ID, "--episodes", "0", "--out",
                                                    str(tmp_path / "y")], capsys)
    assert "unknown env id 'Legent/Nope-v0'" in main_error(["collect", "Legent/Nope-v0", "--episodes", "1",
                                                            "--out", str(tmp_path / "z")], capsys)
    assert "--env-kwargs must be a JSON object" in run("--env-kwargs", "[1]")
    assert "cannot make" in run("--env-kwargs", '{"camera": "fisheye"}')
    assert "cannot import module 'no_such_module'" in run("--policy", "no_such_module:act")
    err = main_error(["collect", ENV_ID, "--episodes", "3", "--out", str(collected), "--seed", "7",
                      "--width", str(SIZE), "--height", str(SIZE), "--format", "minari,legent,video"], capsys)
    assert "seed: was 0, now 7" in err and "use a new --out" in err


def main_error(argv: list[str], capsys) -> str:
    assert main(argv) == 2
    return capsys.readouterr().err
