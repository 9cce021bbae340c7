"""A word vocabulary for instructions, built from the training data (nothing downloaded)."""

from __future__ import annotations

import re
from collections.abc import Iterable

PAD, UNK = 0, 1
_WORD = re.compile(r"[a-z0-9]+")


def words(text: str) -> list[str]:
    """Lower-cased alphanumeric words: ``"Where's the cola?"`` -> ``["where", "s", "the", "cola"]``."""
    return _WORD.findall(text.lower())


class WordVocab:
    """Ids for words: 0 pads, 1 is any word the training data did not contain."""

    def __init__(self, vocabulary: Iterable[str], max_words: int = 16):
        if max_words < 1:
            raise ValueError(f"max_words must be >= 1, got {max_words}")
        self.words = ["<pad>", "<unk>", *vocabulary]
        self.max_words = int(max_words)
        self._ids = {w: i for i, w in enumerate(self.words)}

    @classmethod
    def fit(cls, texts: Iterable[str], max_words: int = 16) -> WordVocab:
        return cls(sorted({w for text in texts for w in words(text)}), max_words)

    def __len__(self) -> int:
        return len(self.words)

    def encode(self, text: str) -> list[int]:
        """Word ids, cut to ``max_words`` (instructions are short; the cut is a safeguard)."""
        ids = [self._ids.get(w, UNK) for w in words(text)][: self.max_words]
        return ids or [UNK]  # an empty instruction still gives the model one token

    def to_dict(self) -> dict:
        return {"words": self.words[2:], "max_words": self.max_words}

    @classmethod
    def from_dict(cls, data: dict) -> WordVocab:
        return cls(data["words"], data["max_words"])
