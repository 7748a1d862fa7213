"""Sideways pushes for the balance controller, written as the pushes of a played gait.

The text is `FORCE@TIME[,FORCE@TIME…]` (N, s), read by `control.playback.parse_pushes`, the one
parser of the push syntax. Each push is a force of FORCE newtons along world +y on one body, held
for 0.1 s from TIME.
"""

from __future__ import annotations

from collections.abc import Sequence

from eigengait.control.balance.tracker import BodyPush
from eigengait.control.playback import parse_pushes


def sideways_pushes(texts: Sequence[str], body: str) -> tuple[BodyPush, ...]:
    """Pushes on `body` from one or more push texts (each may list several pushes), in time
    order."""
    pushes = [p for text in texts for p in parse_pushes(text)]
    return tuple(
        BodyPush(force=(0.0, p.force, 0.0), time_s=p.time, body=body)
        for p in sorted(pushes, key=lambda p: p.time)
    )


__all__ = ["sideways_pushes"]
