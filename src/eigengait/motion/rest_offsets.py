"""The constant rotation between each mapped BVH joint and its character body (the retarget's
rest offset A in W(t) = Rw(t) · A · B⁰, `retarget.py`).

* From the BVH rest pose (all rotations zero), when it stands (`conventions.rest_stands`, as CMU's
  T-poses do): the smallest rotation taking the body's bone direction onto the joint's; the root
  takes none.
* From the motion otherwise (Bandai Namco's rest pose lays every bone along its joint's x axis, so
  it says nothing of how the skeleton stands): A takes the body's bone and the character's left
  (the relax pose faces +x) onto the joint's bone and its mean lateral direction: the direction
  from the right thigh to the left one, seen in the joint's own frame and averaged over the clip
  (for the root, whose thighs it carries, a constant). A foot instead takes its pose at the frame,
  among those it stands on the floor (`planted_frames`), where its levelled bone comes closest to
  the body's heel-to-toe line: its bone may point down at the toes (Bandai Namco's ankle-to-toe
  bone does by 40° in stance) and its sole is flat there.

Bones are directions in world axes (z up) in each joint's own frame; a foot's is levelled.
"""

from __future__ import annotations

import numpy as np

from eigengait.geometry import min_arc

LEFT = np.array([0.0, 1.0, 0.0])  # the character's left in its relax pose (world)
UP = np.array([0.0, 0.0, 1.0])
FORWARD = np.cross(LEFT, UP)  # the character's forward in its relax pose (world): +x
PLANTED_SHARE = 0.05  # of a foot joint's height range: the frames it stands at its lowest


def planted_frames(height: np.ndarray, share: float = PLANTED_SHARE) -> np.ndarray:
    """(F,) bool: the frames in which a foot joint at `height` (F,) is within `share` of its height
    range above its lowest: its stance, where its sole is flat."""
    low = height.min()
    return height <= low + share * max(height.max() - low, 1e-12)


def rest_offsets(
    world_rot: np.ndarray,
    bones: dict[int, np.ndarray],
    body_bones: dict[int, np.ndarray],
    feet: dict[int, np.ndarray],
    root: int,
    left: np.ndarray | None,
) -> dict[int, np.ndarray]:
    """Offset A (3 × 3) per mapped BVH joint.

    world_rot: (F, J, 3, 3) the joints' global rotations in world axes; bones: joint → its bone in
    its own frame; body_bones: joint → its body's relax bone (world); feet: joints whose bones are
    levelled, each with the frames (F,) bool it is planted in; root: the root joint; left: (F, 3)
    unit directions from the right thigh to the left one (world) when the rest pose does not
    stand, None when it does."""
    offsets = {}
    for b, bone in bones.items():
        if left is None:
            seen = _level(bone) if b in feet else bone
            offsets[b] = np.eye(3) if b == root else min_arc(body_bones[b], seen)
        elif b in feet:
            seen = _level(world_rot[:, b] @ bone)
            target = body_bones[b] / np.linalg.norm(body_bones[b])
            cosine = seen @ target / np.maximum(np.linalg.norm(seen, axis=1), 1e-12)
            t = int(np.argmax(np.where(feet[b], cosine, -np.inf)))
            offsets[b] = world_rot[t, b].T @ min_arc(body_bones[b], seen[t])
        else:
            mine, clips = _twist_reference(body_bones[b], left)
            lateral = np.einsum("fji,fj->i", world_rot[:, b], clips)
            offsets[b] = _frame(bone, lateral) @ _frame(body_bones[b], mine).T
    return offsets


def _twist_reference(body_bone: np.ndarray, left: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The direction that fixes a bone's twist: the character's left (world) and the clip's (F, 3),
    unless the body's relax bone lies within 45° of left (an arm held out sideways, as the CMU
    humanoid's zero pose holds it, whose twist left leaves free), then forward: left × up."""
    unit = body_bone / np.linalg.norm(body_bone)
    if abs(unit @ LEFT) < np.cos(np.pi / 4):
        return LEFT, left
    forward = np.cross(left, UP)
    return FORWARD, forward / np.linalg.norm(forward, axis=1, keepdims=True)


def _frame(bone: np.ndarray, lateral: np.ndarray) -> np.ndarray:
    """Orthonormal frame (columns) of a bone direction and a lateral direction made square to
    it."""
    x = bone / np.linalg.norm(bone)
    y = lateral - (lateral @ x) * x
    y /= np.linalg.norm(y)
    return np.stack([x, y, np.cross(x, y)], axis=1)


def _level(v: np.ndarray) -> np.ndarray:
    out = np.array(v, float)
    out[..., 2] = 0.0
    return out
