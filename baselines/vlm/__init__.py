"""The paper's VLA recipe for a GPU: fine-tune a pretrained Hugging Face vision-language model.

LEGENT's VLA is a pretrained VLM (VILA-7B) fine-tuned on the generated trajectories. This
package does that with any Hugging Face image-text-to-text model (LoRA or full), on the
``interleaved.jsonl`` of ``legent-gym collect --format legent``; see ``docs/vlm.md``.

* :mod:`~baselines.vlm.data`: the samples, in the model's chat template, loss on the reply only;
* :mod:`~baselines.vlm.model`: loading a model folder or hub id, with one-line errors;
* :mod:`~baselines.vlm.train`: fine-tuning (``python -m baselines.vlm.train``; ``accelerate launch``);
* :mod:`~baselines.vlm.policy`: the model as a policy, batched greedy decoding (``--policy vlm:PATH``);
* :mod:`~baselines.vlm.tiny`: a tiny random LLaVA built offline, for tests and smoke runs.
"""
