"""The shared evaluation helper of baselines/ and its random-policy baseline."""

from __future__ import annotations

import pytest

from baselines.evaluate import (
    EpisodeResult,
    ExpertBaseline,
    RandomPolicy,
    evaluate,
    main,
    run_episodes,
)
from legent_gym.agent.actions import parse_actions

ENV_ID = "Legent/ComeHere-OneRoom-v0"
SMALL = {"width": 32, "height": 32}


def test_random_policy_is_seeded_and_writes_valid_code():
    a, b = RandomPolicy(seed=4), RandomPolicy(seed=4)
    codes = [a.act({}) for _ in range(20)]
    assert codes == [b.act({}) for _ in range(20)]
    assert len(set(codes)) == 20
    for code in codes:
        assert parse_actions(code)  # every draw is valid action code
    assert any("interact()" in c for c in codes) and not all("interact()" in c for c in codes)


def test_evaluation_is_deterministic_given_the_seed():
    first = run_episodes(RandomPolicy(), ENV_ID, 3, seed=7, env_kwargs=SMALL)
    again = run_episodes(RandomPolicy(seed=99), ENV_ID, 3, seed=7, env_kwargs=SMALL)  # seed() resets it
    other = run_episodes(RandomPolicy(), ENV_ID, 3, seed=8, env_kwargs=SMALL)
    assert first == again
    assert [r.seed for r in first] == [7, 8, 9] and [r.seed for r in other] == [8, 9, 10]
    assert first[1:] != other[:2]  # the same reset seeds, but the policy's draws differ
    for r in first:
        assert isinstance(r, EpisodeResult) and 1 <= r.steps <= 25




class _Constant:
    def __init__(self, action):
        self.action, self.instructions = action, []

    def reset(self, instruction):
        self.instructions.append(instruction)

    def act(self, observation):
        return self.action


class _ExpertOnEvenEpisodes(ExpertBaseline):
    """The expert on episodes 0, 2, ...; turning on the spot (never reaching the user) on the others."""

    def __init__(self):
        super().__init__()
        self.episode = -1

    def reset(self, instruction):
        self.episode += 1

    def act(self, observation):
        return super().act(observation) if self.episode % 2 == 0 else "rotate_right(90)"


def test_evaluate_returns_the_success_rate():
    """Rates known by construction: the expert wins every Come Here episode, turning on the
    spot none, and a policy that is the expert on every other episode half of them."""
    assert evaluate(ExpertBaseline(), ENV_ID, 4, seed=0, env_kwargs=SMALL) == 1.0
    assert evaluate(_Constant("rotate_right(90)"), ENV_ID, 2, seed=0, env_kwargs=SMALL) == 0.0
    assert evaluate(_ExpertOnEvenEpisodes(), ENV_ID, 4, seed=0, env_kwargs=SMALL) == 0.5


def test_a_policy_gets_the_instruction_and_its_actions_reach_the_env():
    policy = _Constant("rotate_right(90)")  # turning on the spot never reaches the user
    results = run_episodes(policy, ENV_ID, 2, seed=0, env_kwargs=SMALL)
    assert [r.instruction for r in results] == policy.instructions
    assert all(not r.success and r.steps == 25 for r in results)


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="episodes must be a positive integer"):
        evaluate(RandomPolicy(), ENV_ID, 0, seed=0)
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        evaluate(RandomPolicy(), ENV_ID, 1, seed=-1)
    with pytest.raises(TypeError, match="reset\\(instruction\\) and act"):
        evaluate(object(), ENV_ID, 1, seed=0)
    with pytest.raises(TypeError, match="must return action code"):
        evaluate(_Constant(None), ENV_ID, 1, seed=0, env_kwargs=SMALL)


def test_cli_prints_the_success_rate(capsys):
    assert main(["--episodes", "2", "--seed", "0", "--width", "32", "--height", "32"]) == 0
    assert "random on Legent/ComeHere-OneRoom-v0: success" in capsys.readouterr().out
