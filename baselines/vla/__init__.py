"""The VLA imitation-learning baseline: a compact vision-language-action model in plain torch.

It reads the instruction and an image-text interleaved window of the last k views and
actions (as the paper's VILA model does) and writes the next action as action code, so its
output is controls and spoken answers directly. Trained by behaviour cloning on the
``interleaved.jsonl`` of ``legent-gym collect --format legent``.

* :mod:`~baselines.vla.codec`: action text <-> template, binned numbers and sentence;
* :mod:`~baselines.vla.words`: the instruction vocabulary;
* :mod:`~baselines.vla.dataset`: the interleaved data, checked and batched;
* :mod:`~baselines.vla.model`: the model; :mod:`~baselines.vla.checkpoint`: saving it;
* :mod:`~baselines.vla.train`: behaviour cloning (``python -m baselines.vla.train``);
* :mod:`~baselines.vla.policy`: the model as a ``reset``/``act`` policy;
* :mod:`~baselines.vla.evaluate`: success rates on seeded episodes, with random and expert bounds.

``baselines/reproduce_table.py`` runs the paper's experiment end to end; results in
``docs/results.md``.
"""
