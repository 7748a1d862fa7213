"""Track a motion-capture clip in physics: load, retarget, replay as reference, run the balance controller.

Shared by `eigengait track` and the studio's tracking panel.
"""

from __future__ import annotations

from pathlib import Path

from eigengait.errors import UserInputError


def parse_push(text: str):
    """'150@1.0' → Push of 150 N along +y at t = 1.0 s."""
    from eigengait.control.balance.tracker import Push

    force, sep, time = text.partition("@")
    try:
        if not sep:
            raise ValueError
        value, at = float(force), float(time)
    except ValueError:
        raise UserInputError(f"cannot read push '{text}'.", field="--push",
                             fix="write FORCE@TIME, e.g. 150@1.0 (newtons, seconds).") from None
    if at < 0:
        raise UserInputError(f"push time {at} s is negative.", field="--push", fix="use a time within the clip.")
    return Push(force=(0.0, value, 0.0), time_s=at)


def run_track(clip_path: Path, character: str, robustness: float, push: str | None, mapping: Path | None,
              start_frame: int, tolerance: float) -> tuple[object, object, object]:
    """Load, retarget, replay and track; returns (world, reference, result)."""
    from eigengait.character import load_character
    from eigengait.control.balance.reference import kinematic_replay
    from eigengait.control.balance.tracker import TrackerSettings, track
    from eigengait.motion.bvh import read_bvh
    from eigengait.motion.retarget import builtin_mapping, load_mapping, retarget
    from eigengait.sim.world import build_world

    if not 0.0 <= robustness <= 1.0:
        raise UserInputError(f"robustness {robustness} is out of range.", field="--robustness",
                             fix="use a value between 0 (physically correct) and 1 (fully compensated).")
    if not 0.0 <= tolerance <= 1.0:
        raise UserInputError(f"tolerance {tolerance} is out of range.", field="--tolerance",
                             fix="use a value between 0 (never switch balance off) and 1.")
    push_spec = parse_push(push) if push else None
    clip = read_bvh(clip_path)
    char = load_character(character)
    world = build_world(char)
    chosen = load_mapping(mapping) if mapping else builtin_mapping(char.name, clip)
    poses = retarget(clip, world, chosen, start_frame=start_frame)
    reference = kinematic_replay(world, poses.qpos, poses.frame_time)
    result = track(world, reference, robustness, TrackerSettings(tolerance=tolerance), push=push_spec)
    return world, reference, result
