"""Writing a person's episodes as the agent in the LEGENT and Minari formats.

The layout under the record directory is ``legent-gym collect``'s: ``minari/<dataset id>``
(a Minari dataset, ``legent/<Task>-<Layout>/human-v0``) and ``legent/`` (trajectory folders,
``trajectories.json``, ``interleaved.jsonl``), written by the same writers
(:class:`~legent_gym.data.minari_store.MinariWriter`,
:class:`~legent_gym.data.legent_format.LegentWriter`) from the same
:class:`~legent_gym.data.rollout.Episode` records. Every episode that ends (success,
``finish()`` or the action cap) is written; its Minari metadata and its trajectory say
whether it succeeded. A directory recorded into before is appended to.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from legent_gym.data.legent_format import LegentWriter, episode_pngs
from legent_gym.data.minari_store import MinariWriter
from legent_gym.data.rollout import Episode, begin_episode, recorded_info


def dataset_id(env_id: str) -> str:
    """``Legent/ComeHere-OneRoom-v0`` -> ``legent/ComeHere-OneRoom/human-v0``."""
    name = env_id.split("/")[-1]
    name = name.rsplit("-v", 1)[0] if "-v" in name else name
    return f"legent/{name}/human-v0"


class Recorder:
    """Keeps the episode being played and appends it to both datasets when it ends."""

    def __init__(self, root: str | Path, env_id: str, env: Any):
        self.root = Path(root)
        self.env_id = env_id
        self.env = env
        self.root.mkdir(parents=True, exist_ok=True)
        self.minari = MinariWriter(self.root / "minari", dataset_id(env_id), staging=self.root / ".staging")
        if not self.minari.exists:
            self.minari.create(env.spec, env.observation_space, env.action_space,
                               algorithm_name="legent_gym play (a person as the agent)",
                               description=f"{env_id} episodes played by a person in the browser "
                                           "(legent-gym play --as agent); lossless images.")
        self.count = int(self.minari.metadata()["total_episodes"])
        self.legent = LegentWriter(self.root / "legent")
        self.legent.resume(self.count)
        self.episode: Episode | None = None
        self.attempt = 0

    def begin(self, obs: dict[str, Any], info: dict[str, Any], seed: int) -> None:
        self.episode = begin_episode(self.env, obs, info, attempt=self.attempt, seed=seed, env_id=self.env_id)
        self.attempt += 1

    def step(self, action: str, obs: dict[str, Any], reward: float, terminated: bool, truncated: bool,
             info: dict[str, Any]) -> None:
        episode = self.episode
        if episode is None:
            raise RuntimeError("Recorder.step before begin")
        episode.actions.append(action)
        episode.labels.append(None)
        episode.action_texts.append(str(info.get("action_text") or action))
        episode.rewards.append(reward)
        episode.terminations.append(terminated)
        episode.truncations.append(truncated)
        episode.observations.append(obs)
        episode.infos.append(recorded_info(info))
        episode.goal_views.append(info.get("goal_view"))

    def end(self, info: dict[str, Any]) -> str:
        """Write the ended episode to both datasets; returns its trajectory id."""
        episode = self.episode
        if episode is None or not episode.actions:
            return ""
        episode.success = bool(info.get("success", False))
        index = self.count
        traj_id = LegentWriter.trajectory_id(index)
        self.legent.write(episode, index, episode_pngs(episode))
        self.legent.checkpoint(durable=True)
        self.minari.append(episode, index, {"legent_id": traj_id}, durable=True)
        self.count += 1
        self.episode = None
        return traj_id

    def close(self) -> None:
        self.minari.close()
