"""Tiny, randomly initialised LLaVA and Idefics3 models built offline: for tests and smoke runs.

:func:`build_tiny_model` writes a folder that ``AutoModelForImageTextToText`` and
``AutoProcessor`` load with ``from_pretrained`` exactly as they load a downloaded model:
the real LLaVA architecture (the one VILA, the paper's model, follows: a CLIP vision
tower, a two-layer projector, a Llama language model) with two text layers and a hidden
size of 64, a byte-level BPE tokenizer trained here on the action language and
instructions (so any text encodes) with ChatML's special tokens and ``<image>``, a
ChatML chat template that keeps images where the messages put them, and CLIP's image
processor (PIL backend) at the view size, 8-pixel patches (a 32 x 32 view is 16 image
tokens). Nothing is downloaded.
"""

from __future__ import annotations

import os
from pathlib import Path

#: ChatML, with images where the content puts them (``{"type": "image"}`` -> ``<image>``).
CHAT_TEMPLATE = (
    "{% for message in messages %}"
    "<|im_start|>{{ message['role'] }}\n"
    "{% if message['content'] is string %}{{ message['content'] }}"
    "{% else %}{% for content in message['content'] %}"
    "{% if content['type'] == 'image' %}<image>"
    "{% elif content['type'] == 'text' %}{{ content['text'] }}{% endif %}"
    "{% endfor %}{% endif %}<|im_end|>\n{% endfor %}"
    "{% if add_generation_prompt %}<|im_start|>assistant\n{% endif %}"
)
SPECIAL_TOKENS = ("<|endoftext|>", "<|im_start|>", "<|im_end|>", "<image>")
_CORPUS = (
    "move_forward(1.5) rotate_right(-30) rotate_down(15) speak(\"It is on the sofa.\") finish() grab() put() "
    "open() close() interact() Come here. Come to me. Can you come here? Please come over. Where is the orange? "
    "Observation: Action: You are an embodied agent in a house. The user's instruction: system user assistant "
    "0123456789 -.,()\"'?! apple banana cola table chair countertop dresser sofa bed kitchen room"
)


def _tokenizer(vocab_size: int):
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    from tokenizers import Tokenizer, decoders, models, pre_tokenizers, trainers
    from transformers import PreTrainedTokenizerFast

    tok = Tokenizer(models.BPE())
    tok.pre_tokenizer = pre_tokenizers.ByteLevel(add_prefix_space=False)
    tok.decoder = decoders.ByteLevel()
    trainer = trainers.BpeTrainer(vocab_size=vocab_size, special_tokens=list(SPECIAL_TOKENS),
                                  initial_alphabet=pre_tokenizers.ByteLevel.alphabet(), show_progress=False)
    tok.train_from_iterator([_CORPUS] * 4, trainer=trainer)
    return PreTrainedTokenizerFast(tokenizer_object=tok, eos_token="<|im_end|>", pad_token="<|endoftext|>")


def build_tiny_model(out: str | os.PathLike, *, image_size: int = 32, seed: int = 0, hidden_size: int = 64,
                     layers: int = 2, vision_layers: int = 1, vision_size: int = 64, patch_size: int = 8,
                     vocab_size: int = 400, architecture: str = "llava") -> Path:
    """Write a tiny random LLaVA (weights, tokenizer, processor, chat template) to ``out``
    for views of ``image_size`` x ``image_size`` pixels; ``architecture="idefics3"``: an
    Idefics3 (SmolVLM's architecture) instead (see :func:`build_tiny_idefics3`)."""
    if architecture == "idefics3":
        return build_tiny_idefics3(out, image_size=image_size, seed=seed, hidden_size=hidden_size, layers=layers,
                                   vision_layers=vision_layers, vision_size=vision_size, patch_size=patch_size,
                                   vocab_size=vocab_size)
    if architecture != "llava":
        raise ValueError(f"architecture must be llava or idefics3, got {architecture!r}")
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    import torch
    from transformers import (
        CLIPVisionConfig,
        LlamaConfig,
        LlavaConfig,
        LlavaForConditionalGeneration,
        LlavaProcessor,
    )
    from transformers.models.clip.image_processing_pil_clip import CLIPImageProcessorPil

    if image_size % patch_size:
        raise ValueError(f"image_size {image_size} is not a multiple of patch_size {patch_size}")
    out = Path(out)
    tokenizer = _tokenizer(vocab_size)
    ids = {name: tokenizer.convert_tokens_to_ids(name) for name in SPECIAL_TOKENS}
    vision = CLIPVisionConfig(hidden_size=vision_size, intermediate_size=2 * vision_size, num_hidden_layers=vision_layers + 1,
                              num_attention_heads=2, image_size=image_size, patch_size=patch_size, projection_dim=vision_size)
    text = LlamaConfig(vocab_size=len(tokenizer), hidden_size=hidden_size, intermediate_size=2 * hidden_size,
                       num_hidden_layers=layers, num_attention_heads=4, num_key_value_heads=2,
                       max_position_embeddings=4096, bos_token_id=ids["<|endoftext|>"],
                       eos_token_id=ids["<|im_end|>"], pad_token_id=ids["<|endoftext|>"])
    config = LlavaConfig(vision_config=vision, text_config=text, image_token_index=ids["<image>"],
                         image_seq_length=(image_size // patch_size) ** 2, vision_feature_select_strategy="default",
                         vision_feature_layer=-2, tie_word_embeddings=True)
    torch.manual_seed(seed)
    model = LlavaForConditionalGeneration(config)
    model.generation_config.eos_token_id = ids["<|im_end|>"]
    model.generation_config.pad_token_id = ids["<|endoftext|>"]
    image_processor = CLIPImageProcessorPil(size={"shortest_edge": image_size},
                                            crop_size={"height": image_size, "width": image_size})
    processor = LlavaProcessor(image_processor=image_processor, tokenizer=tokenizer, patch_size=patch_size,
                               vision_feature_select_strategy="default", chat_template=CHAT_TEMPLATE,
                               num_additional_image_tokens=1)
    out.mkdir(parents=True, exist_ok=True)
    model.save_pretrained(out)
    processor.save_pretrained(out)
    return out


#: Idefics3's turn format ("User:...<end_of_utterance>\nAssistant:"), images where the content puts them.
IDEFICS3_TEMPLATE = (
    "{% for message in messages %}{{ message['role'] | capitalize }}:"
    "{% if message['content'] is string %}{{ message['content'] }}"
    "{% else %}{% for content in message['content'] %}"
    "{% if content['type'] == 'image' %}<image>{% elif content['type'] == 'text' %}{{ content['text'] }}{% endif %}"
    "{% endfor %}{% endif %}<end_of_utterance>\n{% endfor %}"
    "{% if add_generation_prompt %}Assistant:{% endif %}"
)


def build_tiny_idefics3(out: str | os.PathLike, *, image_size: int = 32, seed: int = 0, hidden_size: int = 64,
                        layers: int = 2, vision_layers: int = 1, vision_size: int = 64, patch_size: int = 8,
                        vocab_size: int = 400) -> Path:
    """Write a tiny random Idefics3 (SigLIP-style vision encoder, pixel-shuffle connector,
    Llama language model) with its processor (no image splitting: one global image of
    ``(image_size / patch_size)^2 / 4`` tokens per view) to ``out``."""
    # the vlm extra's libraries take seconds to import: only when a model is made or run
    import torch
    from transformers import (
        Idefics3Config,
        Idefics3ForConditionalGeneration,
        Idefics3Processor,
        LlamaConfig,
    )
    from transformers.models.idefics3.configuration_idefics3 import Idefics3VisionConfig
    from transformers.models.idefics3.image_processing_pil_idefics3 import Idefics3ImageProcessorPil

    if image_size % (2 * patch_size):
        raise ValueError(f"image_size {image_size} is not a multiple of 2 x patch_size {patch_size}")
    out = Path(out)
    tokenizer = _tokenizer(vocab_size)
    image_processor = Idefics3ImageProcessorPil(do_image_splitting=False, size={"longest_edge": image_size},
                                                max_image_size={"longest_edge": image_size})
    # The processor adds its image and end-of-utterance tokens to the tokenizer.
    processor = Idefics3Processor(image_processor=image_processor, tokenizer=tokenizer,
                                  image_seq_len=(image_size // patch_size) ** 2 // 4, chat_template=IDEFICS3_TEMPLATE)
    tokenizer.eos_token = "<end_of_utterance>"
    ids = tokenizer.convert_tokens_to_ids
    text = LlamaConfig(vocab_size=len(tokenizer), hidden_size=hidden_size, intermediate_size=2 * hidden_size,
                       num_hidden_layers=layers, num_attention_heads=4, num_key_value_heads=2,
                       max_position_embeddings=4096, bos_token_id=ids("<|endoftext|>"),
                       eos_token_id=ids("<end_of_utterance>"), pad_token_id=ids("<|endoftext|>"))
    vision = Idefics3VisionConfig(hidden_size=vision_size, intermediate_size=2 * vision_size,
                                  num_hidden_layers=vision_layers, num_attention_heads=2, image_size=image_size,
                                  patch_size=patch_size)
    config = Idefics3Config(vision_config=vision.to_dict(), text_config=text.to_dict(), image_token_id=ids("<image>"),
                            scale_factor=2, tie_word_embeddings=True)
    torch.manual_seed(seed)
    model = Idefics3ForConditionalGeneration(config)
    model.generation_config.eos_token_id = ids("<end_of_utterance>")
    model.generation_config.pad_token_id = ids("<|endoftext|>")
    out.mkdir(parents=True, exist_ok=True)
    model.save_pretrained(out)
    processor.save_pretrained(out)
    return out
