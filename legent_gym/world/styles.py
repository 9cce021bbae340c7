"""Rendering styles and domain randomisation (the paper's "diverse rendering").

A style preset decides lighting and transforms every colour of the scene's palette when a
world is built (``Scene.style.preset``). Domain randomisation re-colours the palette
texture and jitters the lights of an already built world in place, so an episode can get a
new look without a rebuild: call :func:`randomize_appearance`, then the renderer's
``upload_textures()``.

(What floors and walls a generated house gets is
:mod:`legent_gym.world.generation.surfaces_and_lights`.)
"""

from __future__ import annotations

import colorsys
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from legent_gym.world import materials

ColourTransform = Callable[[np.ndarray], np.ndarray]  # (N, 3) float RGB in [0, 1] -> same


def _identity(rgb: np.ndarray) -> np.ndarray:
    return rgb


def _pastel(rgb: np.ndarray) -> np.ndarray:
    return 0.55 * rgb + 0.45


def _night(rgb: np.ndarray) -> np.ndarray:
    return rgb * np.array([0.75, 0.78, 1.0])


def _greyscale(rgb: np.ndarray) -> np.ndarray:
    grey = rgb @ np.array([0.299, 0.587, 0.114])
    return np.repeat(grey[:, None], 3, axis=1)


@dataclass(frozen=True)
class StylePreset:
    name: str
    description: str
    headlight_ambient: float  # scales the scene's ambient
    headlight_diffuse: float
    light_scale: float  # scales every scene light's diffuse colour
    colours: ColourTransform = _identity


STYLES: dict[str, StylePreset] = {
    s.name: s
    for s in (
        StylePreset("realistic", "scene colours, ceiling lights, soft ambient", 1.0, 0.25, 1.0),
        StylePreset("flat", "unshaded flat colours, like a cartoon or a map", 2.6, 0.0, 0.0),
        StylePreset("pastel", "light, washed-out colours", 1.1, 0.25, 1.0, _pastel),
        StylePreset("night", "dim, blue ambient with warm ceiling lights", 0.35, 0.05, 1.3, _night),
        StylePreset("greyscale", "scene lighting, colours reduced to grey", 1.0, 0.25, 1.0, _greyscale),
    )
}


def get_style(name: str) -> StylePreset:
    try:
        return STYLES[name]
    except KeyError:
        raise ValueError(f"unknown style preset {name!r}; known: {', '.join(STYLES)}") from None


def styled_palette(image: np.ndarray, preset: StylePreset) -> np.ndarray:
    """The palette texture (H, W, 3) uint8 with the preset's colour transform applied."""
    if preset.colours is _identity:  # the default style: nothing to compute
        return image
    rgb = image.reshape(-1, 3).astype(np.float64) / 255.0
    out = np.clip(preset.colours(rgb), 0.0, 1.0)
    return np.round(out * 255).astype(np.uint8).reshape(image.shape)


@dataclass(frozen=True, eq=False)
class BaseAppearance:
    """A built world's look before any randomisation: what every re-colouring starts from,
    so that repeated calls do not drift. Kept in ``world.derived`` under this class."""

    palette: np.ndarray  #: (H, W, 3) uint8 atlas texture: palette colours and pattern tiles
    light_diffuse: np.ndarray  #: (nlight, 3)
    ambient: np.ndarray  #: (3,) headlight ambient
    #: texture id -> (H, W, 3) uint8 texture of each patterned floor or wall
    surfaces: dict[int, np.ndarray]


def base_appearance(world) -> BaseAppearance:
    """The world's look before randomisation, recorded on first use."""
    found = world.derived.get(BaseAppearance)
    if found is None:
        model = world.model
        found = world.derived[BaseAppearance] = BaseAppearance(
            _palette_texture(model).copy(), model.light_diffuse.copy(), model.vis.headlight.ambient.copy(),
            {tid: _texture(model, tid).copy() for tid in _surface_textures(model)})
    return found


def randomize_appearance(world, rng: np.random.Generator, *, hue: float = 0.08, saturation: float = 0.25,
                         value: float = 0.2, light: float = 0.3) -> None:
    """Re-colour the palette and jitter lights of a built world, in place.

    Every palette colour gets its own hue shift (up to ``hue`` turns), and saturation and
    value factors within ``1 +- saturation`` / ``1 +- value``; a pattern tile of a colour
    changes as its colour does, and each patterned floor or wall gets a shift of its own;
    lights are scaled by up to ``1 +- light``. Deterministic for a given generator state.
    Call ``upload_textures()`` on renderers of this world afterwards.
    """
    model = world.model
    original = base_appearance(world)
    atlas = world.atlas
    size = atlas.palette.size
    base = original.palette[:size, :size].reshape(-1, 3).astype(np.float64) / 255.0
    rgb = _shifted(base, rng, hue, saturation, value)
    image = original.palette.copy()
    image[:size, :size] = np.round(rgb * 255).astype(np.uint8).reshape(size, size, 3)
    tile = materials.TILE
    for x, y, colour in atlas.tile_boxes():
        # The tile's colour is a palette colour: the tile follows its shift.
        index = atlas.palette.index_rgb8(colour)
        ratio = (rgb[index] + 1e-3) / (base[index] + 1e-3)
        block = original.palette[y:y + tile, x:x + tile].astype(np.float64) * ratio
        image[y:y + tile, x:x + tile] = np.clip(np.round(block), 0, 255).astype(np.uint8)
    _palette_texture(model)[:] = image
    if original.surfaces:
        textures = list(original.surfaces.values())
        mean = np.array([t.reshape(-1, 3).mean(axis=0) for t in textures]) / 255.0
        ratio = (_shifted(mean, rng, hue, saturation, value) + 1e-3) / (mean + 1e-3)
        for tid, texture, r in zip(original.surfaces, textures, ratio, strict=True):
            _texture(model, tid)[:] = np.clip(np.round(texture * r), 0, 255).astype(np.uint8)
    if model.nlight:
        model.light_diffuse[:] = original.light_diffuse * rng.uniform(1 - light, 1 + light, (model.nlight, 1))
    model.vis.headlight.ambient[:] = original.ambient * rng.uniform(1 - light, 1 + light)


def _shifted(rgb: np.ndarray, rng: np.random.Generator, hue: float, saturation: float, value: float) -> np.ndarray:
    """(N, 3) colours each with its own random hue shift and saturation and value factors."""
    n = len(rgb)
    hsv = np.array([colorsys.rgb_to_hsv(*c) for c in rgb]).reshape(n, 3)
    hsv[:, 0] = (hsv[:, 0] + rng.uniform(-hue, hue, n)) % 1.0
    hsv[:, 1] = np.clip(hsv[:, 1] * rng.uniform(1 - saturation, 1 + saturation, n), 0, 1)
    hsv[:, 2] = np.clip(hsv[:, 2] * rng.uniform(1 - value, 1 + value, n), 0, 1)
    return np.array([colorsys.hsv_to_rgb(*c) for c in hsv]).reshape(n, 3)


def _surface_textures(model) -> list[int]:
    """Ids of the patterned floors' and walls' textures (named ``surface_<k>``; the unused
    ones are one texel)."""
    raw = model.names
    names = [raw[a:raw.index(b"\0", a)].decode() for a in model.name_texadr.tolist()]
    return [i for i, name in enumerate(names) if name.startswith("surface_") and model.tex_width[i] > 1]


def _palette_texture(model) -> np.ndarray:
    """A writable view of the palette texture's bytes inside the model."""
    return _texture(model, model.texture("palette").id)


def _texture(model, tid: int) -> np.ndarray:
    """A writable view of a texture's bytes inside the model."""
    adr, w, h, c = model.tex_adr[tid], model.tex_width[tid], model.tex_height[tid], model.tex_nchannel[tid]
    return model.tex_data[adr: adr + w * h * c].reshape(h, w, c)
