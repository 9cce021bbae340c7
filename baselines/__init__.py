"""Baselines on the legent_gym environments (extra ``baselines``: ``pip install -e '.[baselines]'``).

* :mod:`baselines.evaluate`: the shared evaluation loop (``evaluate(policy, env_id, episodes,
  seed)``), the :class:`~baselines.evaluate.Policy` protocol and a random-policy baseline;
* :mod:`baselines.llm_agent`: a zero-shot multimodal LLM agent over any OpenAI-compatible
  chat endpoint (the paper's GPT-4V row);
* :mod:`baselines.ppo_comehere`: stable-baselines3 PPO on ComeHere with a learning curve;
* :mod:`baselines.figures` and :mod:`baselines.refresh`: the docs' tables of measured
  numbers as data files (``docs/data/figures/``), measured again and rewritten by
  ``python -m baselines.refresh``; :mod:`baselines.figure_data` is the machinery they share
  (tables, data files, doc blocks).

Results and the commands that produced them: ``docs/results.md``.
"""
