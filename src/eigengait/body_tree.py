"""Walks up a MuJoCo model's body tree (body 0 is the world); a body's own joints and hinges."""

from __future__ import annotations

from collections.abc import Iterator

import mujoco


def ancestors(model: mujoco.MjModel, body: int) -> Iterator[int]:
    """`body` itself, then each of its parents in turn, up to but not including the world (0)."""
    body = int(body)
    while body > 0:
        yield body
        body = int(model.body_parentid[body])


def in_subtree(model: mujoco.MjModel, body: int, root: int) -> bool:
    """Whether `body` is `root` (a body, not the world) or one of its descendants."""
    return int(root) in ancestors(model, body)


def body_joints(model: mujoco.MjModel, body: int) -> range:
    """Joint ids of `body`'s own joints, in the model's order."""
    start = int(model.body_jntadr[body])
    return range(start, start + int(model.body_jntnum[body]))


def body_hinges(model: mujoco.MjModel, body: int) -> list[int]:
    """The body's joints in the model's order when all of them are hinges, else none (a hip on
    hip_x, hip_z, hip_y turns as one body part)."""
    joints = list(body_joints(model, body))
    hinge = mujoco.mjtJoint.mjJNT_HINGE
    return joints if all(int(model.jnt_type[j]) == hinge for j in joints) else []


def limb_dofs(model: mujoco.MjModel, end_body: int, other_ends: list[int]) -> list[int]:
    """Dof indices, sorted, of the joints on the chain from `end_body` (included) up to the first
    body that also carries one of `other_ends` (excluded), or up to the world: a leg's own joints.
    Where the free root is the chest (dm_control's suite humanoid) the spine between it and the
    hips moves both legs, so it belongs to neither."""
    shared = {b for other in other_ends for b in ancestors(model, other)}
    chain = []
    for body in ancestors(model, end_body):
        if body in shared:
            break
        chain.append(body)
    return sorted(d for d in range(model.nv) if int(model.dof_bodyid[d]) in chain)


def leg_dofs(model: mujoco.MjModel, root_body: int, feet: dict[str, int]) -> dict[str, list[int]]:
    """Each foot's own joints (`limb_dofs`, foot name -> dof indices): from the foot body up to
    the root or the first body that also carries another of `feet` (name -> body)."""
    return {
        foot: limb_dofs(model, body, [root_body, *(b for f, b in feet.items() if f != foot)])
        for foot, body in feet.items()
    }
