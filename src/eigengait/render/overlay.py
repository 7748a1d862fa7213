"""Text drawn onto rendered frames: the simulated time and which feet are on the ground.

Sizes are in pixels and scale with the frame height (legible from 120 px up); colours are RGB 0–1.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from PIL import Image, ImageDraw, ImageFont


@lru_cache(maxsize=8)
def _font(size: int) -> ImageFont.FreeTypeFont:
    return ImageFont.load_default(size=size)


def annotate(
    frame: np.ndarray,
    time_s: float | None,
    feet: list[tuple[str, bool, tuple[float, float, float]]] = (),
) -> np.ndarray:
    """The frame (H × W × 3 uint8) with "t = …s" at the top left and, at the top right, one box per
    foot (name, on the ground, colour): filled while the foot touches the ground, outlined while it
    is in the air. Foot names are shortened to their initials ("front_left" → "FL") when the full
    names do not fit."""
    image = Image.fromarray(frame)
    draw = ImageDraw.Draw(image)
    size = max(10, round(frame.shape[0] / 24))
    font, pad = _font(size), max(3, size // 3)
    left = pad
    if time_s is not None:
        left = _label(draw, (pad, pad), f"t = {time_s:5.2f} s", font, pad) + pad
    names = [name for name, _, _ in feet]
    if sum(draw.textlength(n, font=font) + 3 * pad for n in names) > frame.shape[1] - left:
        names = ["".join(word[:1] for word in n.split("_")).upper() for n in names]
    x = frame.shape[1] - pad
    for name, (_, on, colour) in reversed(list(zip(names, feet))):
        rgb = tuple(int(255 * c) for c in colour)
        width = draw.textlength(name, font=font) + 2 * pad
        box = (x - width, pad, x, pad + size + 2 * pad)
        draw.rectangle(
            box, fill=rgb if on else (255, 255, 255), outline=rgb, width=max(2, size // 8)
        )
        draw.text((box[0] + pad, pad + pad), name, font=font, fill=(255, 255, 255) if on else rgb)
        x = box[0] - pad
    return np.asarray(image)


def _label(draw: ImageDraw.ImageDraw, xy: tuple[int, int], text: str, font, pad: int) -> int:
    """Dark text on a white box at `xy`; returns the box's right edge (px)."""
    left, top, right, bottom = draw.textbbox((xy[0] + pad, xy[1] + pad), text, font=font)
    draw.rectangle((xy[0], xy[1], right + pad, bottom + pad), fill=(255, 255, 255))
    draw.text((xy[0] + pad, xy[1] + pad), text, font=font, fill=(20, 20, 20))
    return right + pad
