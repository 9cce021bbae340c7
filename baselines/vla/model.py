"""A compact vision-language-action model in plain torch (no torchvision, no downloads).

Input, as in the paper: the instruction and an image-text interleaved window of the last k
views and the actions between them::

    [instruction words] [view] [action] [view] [action] ... [view]

* views: a small CNN (four stride-2 convolutions) whose flattened feature map goes through
  a linear layer to one token; flattening keeps *where* things are in the view, which the
  turn towards a goal depends on. With ``film``, the instruction scales and shifts every
  convolution's channels (FiLM, as in BabyAI), so the CNN looks for the object that was
  asked for instead of summarising everything in view into one token;
* instruction words: embeddings from a vocabulary built from the training data;
* history actions: an embedding of the action's template, a linear map of its numbers and
  an embedding of what it said;
* a transformer encoder over the sequence (the window is left-padded, so the current view
  is always the last token, at the same position).

Output, from the last token: the action's template, a bin and an in-bin offset for each
numeric slot, and a sentence (see :mod:`baselines.vla.codec`); :meth:`VLA.decode` writes
them as action code.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import torch
from torch import nn
from torch.nn import functional as F

from baselines.vla.codec import ActionCodec
from baselines.vla.dataset import BEARING_SECTORS, DISTANCE_EDGES, IGNORE


@dataclass(frozen=True)
class ModelConfig:
    image_size: int = 64
    window: int = 6
    d_model: int = 128
    heads: int = 4
    layers: int = 3
    ff: int = 256
    dropout: float = 0.1
    channels: tuple[int, ...] = (16, 32, 64, 128)
    #: Weight of the auxiliary losses (0: no auxiliary heads): from the same last token,
    #: predict whether the goal is in view, its bearing sector and its distance band, from
    #: the privileged ``goal_view`` labels of the data. Dense per-step supervision of what
    #: the image shows, where behaviour cloning gives one action.
    aux_weight: float = 0.0
    #: Condition the image encoder on the instruction (FiLM: a per-channel scale and shift
    #: after each convolution's normalisation, from the mean of the instruction's word
    #: embeddings). A fruit 3 m away covers a pixel or two of a 64 x 64 view; an encoder
    #: that knows which fruit is asked for could keep those pixels. Measured on Where Is:
    #: no gain (docs/results.md); an option for other data.
    film: bool = False

    def __post_init__(self) -> None:
        stride = 2 ** len(self.channels)
        if self.image_size < stride or self.image_size % stride:
            raise ValueError(f"image_size must be a multiple of {stride} (the CNN halves it "
                             f"{len(self.channels)} times), got {self.image_size}")
        if self.window < 1:
            raise ValueError(f"window must be >= 1 view, got {self.window}")
        if self.aux_weight < 0:
            raise ValueError(f"aux_weight must be >= 0, got {self.aux_weight}")
        if self.d_model % self.heads:
            raise ValueError(f"d_model ({self.d_model}) must be divisible by heads ({self.heads})")

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> ModelConfig:
        # A missing key (a checkpoint older than the field) takes the field's default.
        return cls(**{**data, **({"channels": tuple(data["channels"])} if "channels" in data else {})})


class ImageEncoder(nn.Module):
    def __init__(self, config: ModelConfig):
        super().__init__()
        layers, previous = [], 3
        for i, channels in enumerate(config.channels):
            kernel = 5 if i == 0 else 3
            layers += [nn.Conv2d(previous, channels, kernel, stride=2, padding=kernel // 2),
                       nn.GroupNorm(8, channels), nn.ReLU()]
            previous = channels
        self.convs = nn.Sequential(*layers)  # (conv, norm, relu) per halving
        side = config.image_size // 2 ** len(config.channels)
        self.project = nn.Linear(previous * side * side, config.d_model)
        self.film = None
        if config.film:
            # Zero-initialised: training starts from the unconditioned encoder.
            self.film = nn.Linear(config.d_model, 2 * sum(config.channels))
            nn.init.zeros_(self.film.weight)
            nn.init.zeros_(self.film.bias)

    def forward(self, images: torch.Tensor, condition: torch.Tensor | None = None) -> torch.Tensor:
        """(N, 3, H, W) uint8 -> (N, d_model); ``condition`` (N, d_model) is what each
        view is looked at for (needed with ``film``)."""
        x = images.float() / 127.5 - 1.0
        film = None
        if self.film is not None:
            if condition is None:
                raise ValueError("an image encoder with film needs a condition for every view")
            widths = [conv.out_channels for conv in self.convs[0::3] for _ in ("scale", "shift")]
            film = self.film(condition).split(widths, dim=1)
        for i, (conv, norm, relu) in enumerate(zip(self.convs[0::3], self.convs[1::3], self.convs[2::3])):
            x = norm(conv(x))
            if film is not None:  # per-channel scale and shift, from the instruction
                x = x * (1 + film[2 * i][:, :, None, None]) + film[2 * i + 1][:, :, None, None]
            x = relu(x)
        return self.project(x.flatten(1))


class VLA(nn.Module):
    def __init__(self, config: ModelConfig, codec: ActionCodec, vocab_size: int, max_words: int):
        super().__init__()
        self.config, self.codec = config, codec
        d, k = config.d_model, config.window
        self.n_slots, self.bins = len(codec.slots), codec.bins
        self.images = ImageEncoder(config)
        self.words = nn.Embedding(vocab_size, d, padding_idx=0)
        self.word_position = nn.Parameter(torch.zeros(max_words, d))
        self.template = nn.Embedding(codec.n_templates, d)
        self.numbers = nn.Linear(max(self.n_slots, 1), d)
        self.speech = nn.Embedding(codec.n_speeches, d)
        self.window_position = nn.Parameter(torch.zeros(2 * k - 1, d))
        self.kind = nn.Embedding(3, d)  # word, view, action
        nn.init.normal_(self.word_position, std=0.02)
        nn.init.normal_(self.window_position, std=0.02)
        layer = nn.TransformerEncoderLayer(d, config.heads, config.ff, config.dropout, batch_first=True,
                                           norm_first=True, activation="gelu")
        self.encoder = nn.TransformerEncoder(layer, config.layers, enable_nested_tensor=False)
        self.norm = nn.LayerNorm(d)
        self.head_template = nn.Linear(d, codec.n_templates)
        self.head_bins = nn.Linear(d, max(self.n_slots, 1) * self.bins)
        self.head_offsets = nn.Linear(d, max(self.n_slots, 1) * self.bins)
        self.head_speech = nn.Linear(d, codec.n_speeches)
        if config.aux_weight > 0:
            self.head_aux = nn.Linear(d, 2 + BEARING_SECTORS + len(DISTANCE_EDGES) + 1)

    def forward(self, images: torch.Tensor, window_images: torch.Tensor, instruction: torch.Tensor,
                history_template: torch.Tensor, history_numbers: torch.Tensor,
                history_speech: torch.Tensor) -> dict[str, torch.Tensor]:
        """``images`` (N, 3, H, W) uint8 are the views of the batch, each once;
        ``window_images`` (B, k) index into them (-1: padding, on the left); the rest as
        :func:`baselines.vla.dataset.window_inputs` writes them, batched."""
        batch, k = window_images.shape
        d = self.config.d_model
        shown = window_images >= 0
        views = self.images(images, self._view_conditions(images.shape[0], window_images, instruction))
        view_tokens = views[window_images.clamp(min=0)] + self.kind.weight[1]  # (B, k, d)
        if self.n_slots == 0:
            history_numbers = torch.zeros(*history_numbers.shape[:2], 1, device=views.device)
        action_tokens = (self.template(history_template) + self.numbers(history_numbers)
                         + self.speech(history_speech) + self.kind.weight[2])  # (B, k-1, d)
        window = torch.zeros(batch, 2 * k - 1, d, dtype=views.dtype, device=views.device)
        window[:, 0::2] = view_tokens
        window[:, 1::2] = action_tokens
        window = window + self.window_position
        # An action is padding when the view before it is (the window is left-padded).
        window_pad = torch.zeros(batch, 2 * k - 1, dtype=torch.bool, device=views.device)
        window_pad[:, 0::2] = ~shown
        window_pad[:, 1::2] = ~shown[:, :-1]
        # Words are left-aligned: drop the columns that are padding in every sample (most
        # instructions are far shorter than max_words, and attention cost grows with length).
        instruction = instruction[:, : max(int((instruction != 0).sum(1).max()), 1)]
        words = self.words(instruction) + self.word_position[: instruction.shape[1]] + self.kind.weight[0]
        tokens = torch.cat([words, window], dim=1)
        padding = torch.cat([instruction == 0, window_pad], dim=1)
        hidden = self.norm(self.encoder(tokens, src_key_padding_mask=padding)[:, -1])
        slots = max(self.n_slots, 1)
        out = {
            "template": self.head_template(hidden),
            "bins": self.head_bins(hidden).view(batch, slots, self.bins),
            "offsets": 0.5 * torch.tanh(self.head_offsets(hidden).view(batch, slots, self.bins)),
            "speech": self.head_speech(hidden),
        }
        if self.config.aux_weight > 0:
            aux = self.head_aux(hidden)
            out["visible"], out["bearing"], out["distance"] = aux.split(
                [2, BEARING_SECTORS, len(DISTANCE_EDGES) + 1], dim=1)
        return out

    def _view_conditions(self, n_images: int, window_images: torch.Tensor,
                         instruction: torch.Tensor) -> torch.Tensor | None:
        """For FiLM: the instruction of each view (the mean of its word embeddings). A
        view belongs to one trajectory, so every sample that shows it has the same
        instruction: take any of them."""
        if not self.config.film:
            return None
        words = (instruction != 0).unsqueeze(-1)
        summary = (self.words(instruction) * words).sum(1) / words.sum(1).clamp(min=1)  # (B, d)
        owner = torch.zeros(n_images, dtype=torch.long, device=instruction.device)
        rows = torch.arange(window_images.shape[0], device=instruction.device)[:, None].expand_as(window_images)
        shown = window_images >= 0
        owner[window_images[shown]] = rows[shown]
        return summary[owner]

    def loss(self, out: dict[str, torch.Tensor], batch: dict[str, torch.Tensor]) -> tuple[torch.Tensor, dict]:
        """Cross-entropy on the template, bins and sentence; squared error on the offset of
        the true bin. Absent slots and silent steps carry no loss. With ``aux_weight``, plus
        that weight times the cross-entropy of the goal-view predictions (steps without a
        goal view carry none)."""
        template = F.cross_entropy(out["template"], batch["target_template"])
        total, parts = template, {"template": template.item()}
        target_bins = batch["target_bins"]
        present = target_bins >= 0
        if present.any():
            logits = out["bins"][present]
            true_bins = target_bins[present]
            bins = F.cross_entropy(logits, true_bins)
            offset = out["offsets"][present].gather(1, true_bins[:, None]).squeeze(1)
            offsets = F.mse_loss(offset, batch["target_offsets"][present]) * 4.0  # in half-bins
            total = total + bins + offsets
            parts.update(bins=bins.item(), offsets=offsets.item())
        if (batch["target_speech"] >= 0).any():
            speech = F.cross_entropy(out["speech"], batch["target_speech"], ignore_index=-100)
            total = total + speech
            parts["speech"] = speech.item()
        if self.config.aux_weight > 0 and "target_visible" in batch and (batch["target_visible"] >= 0).any():
            aux = sum(F.cross_entropy(out[key], batch[f"target_{key}"], ignore_index=IGNORE)
                      for key in ("visible", "bearing", "distance"))
            total = total + self.config.aux_weight * aux
            parts["aux"] = aux.item()
        return total, parts

    def decode(self, out: dict[str, torch.Tensor]) -> list[str]:
        """Greedy action code for each sample of a forward pass's output."""
        texts = []
        template_logits = out["template"].clone()
        template_logits[:, 0] = -torch.inf  # never write the "unknown" template
        templates = template_logits.argmax(-1).tolist()
        bins = out["bins"].argmax(-1)                                       # (B, slots)
        offsets = out["offsets"].gather(2, bins[..., None]).squeeze(-1)     # (B, slots)
        speech_logits = out["speech"].clone()
        speech_logits[:, 0] = -torch.inf
        speeches = speech_logits.argmax(-1).tolist()
        for b, template in enumerate(templates):
            numbers = {}
            for slot in self.codec.template_slots(template):
                i = self.codec.slot_id(slot)
                numbers[slot] = self.codec.from_bin(slot, int(bins[b, i]), float(offsets[b, i]))
            texts.append(self.codec.format(template, numbers, speeches[b] if self.codec.n_speeches > 1 else 0))
        return texts
