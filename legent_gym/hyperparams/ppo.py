"""``ppo.yml`` as RL Zoo's ``--conf-file legent_gym.hyperparams.ppo`` reads it."""

from legent_gym.hyperparams import load

hyperparams = load("ppo")
