"""Fingerprints of seeded rollouts, to pin the episodes every env id produces.

``python -m tests.rollout_fingerprint`` rewrites ``tests/fixtures/rollouts.json`` from the
current code; ``tests/test_rollout_fingerprints.py`` recomputes the fingerprints and
compares. A refactor that must not change behaviour leaves the file as it is.

Each rollout: ``reset(seed)``, then up to ``STEPS`` actions, alternating the expert's
action (``ExpertInfo``) with a seeded random text action (moves, turns, interactions,
speech, and an unparsable string), so that both the expert's path and the error paths are
pinned. The fingerprint is a SHA-256 over every observation array's bytes, every reward,
termination, truncation and the info fields that describe the episode.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import legent_gym  # noqa: F401  (registers the ids)
from legent_gym.envs.registration import ENV_IDS
from legent_gym.wrappers import ExpertInfo

PATH = Path(__file__).parent / "fixtures" / "rollouts.json"
STEPS = 12
SIZE = 32
RANDOM_ACTIONS = ("move_forward(0.7)", "rotate_right(-40)", "rotate_down(15)", "grab()", "put()", "open()",
                  "interact()", 'speak("hello")', "rotate_right(75), move_forward(1.1)", "close()",
                  "not an action(")
INFO_KEYS = ("agent_pose", "user_pose", "held", "task", "success", "distance_to_goal", "house_seed",
             "scene_name", "n_actions", "action_text", "action_results", "action_error")


def _round(value: Any) -> Any:
    if isinstance(value, float | np.floating):
        return round(float(value), 6)
    if isinstance(value, tuple | list):
        return [_round(v) for v in value]
    if isinstance(value, dict):
        return {k: _round(v) for k, v in sorted(value.items())}
    if isinstance(value, np.integer):
        return int(value)
    return value


def _feed(h, obs: dict) -> None:
    for key in sorted(obs):
        value = obs[key]
        h.update(key.encode())
        if isinstance(value, np.ndarray):
            h.update(np.ascontiguousarray(value).tobytes())
        else:
            h.update(str(value).encode())


def single_agent(env_id: str, seed: int, action_type: str) -> str:
    env = ExpertInfo(gym.make(env_id, width=SIZE, height=SIZE, action_type=action_type, depth=True,
                              segmentation=True, reward="dense"))
    rng = np.random.default_rng(seed)
    h = hashlib.sha256()
    obs, info = env.reset(seed=seed)
    _feed(h, obs)
    h.update(json.dumps(_round({k: info.get(k) for k in INFO_KEYS})).encode())
    for step in range(STEPS):
        if step % 2 == 0 or action_type == "continuous":
            action = info["expert_action"]
        else:
            action = RANDOM_ACTIONS[int(rng.integers(len(RANDOM_ACTIONS)))]
        obs, reward, terminated, truncated, info = env.step(action)
        _feed(h, obs)
        h.update(json.dumps(_round([reward, terminated, truncated,
                                    {k: info.get(k) for k in INFO_KEYS}])).encode())
        if terminated or truncated:
            break
    env.close()
    return h.hexdigest()


def multi_agent(env_id: str, seed: int) -> str:
    from legent_gym.multiagent import parallel_env
    from legent_gym.multiagent.registration import id_kwargs

    env = parallel_env(**id_kwargs(env_id), width=SIZE, height=SIZE, reward="dense", rewards="per_agent",
                       distance_info=True, render_mode="rgb_array", render_size=SIZE)
    rng = np.random.default_rng(seed)
    h = hashlib.sha256()
    observations, infos = env.reset(seed=seed)
    for who in ("user", "agent"):
        _feed(h, observations[who])
        h.update(json.dumps(_round({k: infos[who].get(k) for k in INFO_KEYS})).encode())
    for _ in range(STEPS):
        actions = {who: RANDOM_ACTIONS[int(rng.integers(len(RANDOM_ACTIONS)))] for who in ("user", "agent")}
        observations, rewards, terms, truncs, infos = env.step(actions)
        for who in ("user", "agent"):
            _feed(h, observations[who])
            h.update(json.dumps(_round([rewards[who], terms[who], truncs[who],
                                        {k: infos[who].get(k) for k in INFO_KEYS}])).encode())
        h.update(np.ascontiguousarray(env.render()).tobytes())
        if not env.agents:
            break
    env.close()
    return h.hexdigest()


def cases() -> list[tuple[str, str, int]]:
    """(kind, env id, seed): every id, text actions; continuous actions and the
    multi-agent form on the OneRoom ids."""
    out = [("text", env_id, 3) for env_id in ENV_IDS]
    out += [("continuous", env_id, 4) for env_id in ENV_IDS if "OneRoom" in env_id]
    out += [("multiagent", env_id, 5) for env_id in ENV_IDS if "OneRoom" in env_id]
    return out


def fingerprint(kind: str, env_id: str, seed: int) -> str:
    if kind == "multiagent":
        return multi_agent(env_id, seed)
    return single_agent(env_id, seed, kind)


def key(kind: str, env_id: str, seed: int) -> str:
    return f"{kind}:{env_id}:{seed}"


def main() -> None:
    table = {key(*c): fingerprint(*c) for c in cases()}
    tmp = PATH.with_suffix(".tmp")
    tmp.write_text(json.dumps(table, indent=1, sort_keys=True) + "\n")
    tmp.replace(PATH)
    print(f"wrote {len(table)} fingerprints to {PATH}", file=sys.stderr)


if __name__ == "__main__":
    main()
