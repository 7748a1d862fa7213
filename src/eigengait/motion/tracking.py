"""Track a motion-capture clip in physics: load, retarget, clean the feet, replay as reference, run
the balance controller; or check the retargeted reference without physics (foot skate, floor
penetration, ground clearance, the feet's tilt where the clip's feet stand flat).

Shared by `eigengait track` and the studio's tracking panel.
"""

from __future__ import annotations

from pathlib import Path

from eigengait.inputs import check_range


def reference_poses(
    clip_path: Path,
    character: str,
    mapping: Path | None,
    start_frame: int,
    clean: bool = True,
    levelling: str = "still",
) -> dict:
    """Load and retarget a clip from `start_frame`, its lead-in skipped (`lead_in.py`) and its
    capture glitches repaired (`capture_glitches.py`), bring it
    to 120 frames/s if it is slower (`upsample.py`), clean its feet (unless `clean` is False) and
    start it at its first supported pose (`lead_in.first_supported_pose`); `levelling`: the frames
    the feet are levelled on (`retarget.LEVELLINGS`).

    Returns world, poses (F, nq), first_frame (the clip frame they start at), frame_time (s, of the
    poses), scale (m per file unit), root_factor (`root_scale`), foot_level_deg (`foot_level`),
    flat_foot_tilt_deg (per foot, the final poses' tilt where the clip's foot stands flat,
    `flat_feet`),
    conventions (or None when the skeleton's legs are not found by name), raw and final foot
    reports (`foot_metrics`), glitches (`capture_glitches.Glitch` list)."""
    import numpy as np

    from eigengait.character import load_character
    from eigengait.motion.bvh import read_bvh
    from eigengait.motion.capture_glitches import repair_glitches
    from eigengait.motion.conventions import detect_conventions
    from eigengait.motion.flat_feet import flat_tilt_deg
    from eigengait.motion.foot_cleanup import clean_feet
    from eigengait.motion.foot_metrics import foot_report
    from eigengait.motion.lead_in import first_frame_after_lead_in, first_supported_pose
    from eigengait.motion.retarget import builtin_mapping, load_mapping, retarget
    from eigengait.motion.skeleton_names import LEG_ROLES, find_roles
    from eigengait.motion.soles import sole_points
    from eigengait.motion.upsample import upsampled
    from eigengait.sim.world import build_world

    clip = read_bvh(clip_path)
    # the tracker switches the character's springs off, so joints with no stiffness need none
    char = load_character(character, stiffness="auto")
    world = build_world(char)
    chosen = load_mapping(mapping) if mapping else builtin_mapping(char.name, clip, world)
    first = first_frame_after_lead_in(clip, start_frame)
    clip, glitches = repair_glitches(clip, first)
    retargeted = retarget(clip, world, chosen, start_frame=first, levelling=levelling)
    roles = find_roles(clip)
    conventions = detect_conventions(clip, roles, first) if set(LEG_ROLES) <= set(roles) else None
    raw_qpos, frame_time = upsampled(world.model, retargeted.qpos, retargeted.frame_time)
    qpos = clean_feet(world, raw_qpos, frame_time).qpos if clean else raw_qpos
    soles = sole_points(world, qpos)
    start = min(first_supported_pose(soles), len(qpos) - 2)  # two poses kept
    first += int(round(start * frame_time / clip.frame_time))
    raw_qpos, qpos = raw_qpos[start:], qpos[start:]
    final = foot_report({foot: points[start:] for foot, points in soles.items()}, frame_time)
    clip_frame = np.rint((start + np.arange(len(qpos))) * frame_time / retargeted.frame_time)
    clip_frame = np.minimum(clip_frame.astype(int), len(retargeted.qpos) - 1)
    flat = {foot: frames[clip_frame] for foot, frames in retargeted.flat_frames.items()}
    raw = foot_report(sole_points(world, raw_qpos), frame_time) if clean else final
    return {
        "world": world,
        "qpos": qpos,
        "first_frame": first,
        "frame_time": frame_time,
        "scale": retargeted.scale,
        "root_factor": retargeted.root_factor,
        "levelling": levelling,
        "foot_level_deg": retargeted.foot_level_deg,
        "flat_foot_tilt_deg": flat_tilt_deg(world, qpos, flat),
        "conventions": conventions,
        "raw": raw,
        "final": final,
        "glitches": glitches,
    }


def kinematic_summary(ref: dict, clean: bool) -> dict:
    """JSON-ready report of a retargeted reference played without physics (`reference_poses`
    output)."""
    conventions = ref["conventions"]
    return {
        "kinematic": True,
        "first_frame": ref["first_frame"],
        "frames": len(ref["qpos"]),
        "duration_s": round((len(ref["qpos"]) - 1) * ref["frame_time"], 4),
        "frame_time_s": ref["frame_time"],
        "retarget_scale_m_per_unit": round(ref["scale"], 6),
        "root_scale_factor": round(ref["root_factor"], 4),
        "levelling": ref["levelling"],
        "foot_level_deg": {foot: round(angle, 2) for foot, angle in ref["foot_level_deg"].items()},
        "flat_foot_tilt_deg": {
            foot: round(angle, 1) for foot, angle in ref["flat_foot_tilt_deg"].items()
        },
        "source": conventions.summary() if conventions else None,
        "feet_cleaned": clean,
        **ref["final"].summary(),
        "raw": ref["raw"].summary(),
        "capture_glitches": [
            {"joint": g.joint, "start_s": g.start_s, "end_s": g.end_s} for g in ref["glitches"]
        ],
    }


def run_track(
    clip_path: Path,
    character: str,
    robustness: float,
    push: str | None,
    mapping: Path | None,
    start_frame: int,
    tolerance: float,
    clean: bool = True,
    foot: dict | None = None,
    controller: str = "qp",
    recoveries: int | None = None,
    levelling: str = "still",
) -> tuple[object, object, object]:
    """Load, retarget, clean the feet (unless `clean` is False), replay and track; returns (world,
    reference, result); result.foot_skate_m and foot_skate_max_m are the simulated motion's skate
    (m, mean per stance and worst stance, `foot_metrics`).

    `push`: pushes as text, FORCE@TIME[,FORCE@TIME…] in N and s (`control.playback.parse_pushes`),
    sideways (+y) on the torso; `foot`: the foot model as `TrackerSettings` keyword arguments
    (foot_radius_m, foot_com_height_m, foot_friction), default the settings'; `controller`:
    `TrackerSettings.controller`; `recoveries`: falls searched past (`tracker` module doc,
    "Recovery"; None: TRACK_RECOVERIES); `levelling`: as for `reference_poses`."""
    from eigengait.control.balance.pushes import sideways_pushes
    from eigengait.control.balance.reference import kinematic_replay
    from eigengait.control.balance.tracker import (
        TRACK_RECOVERIES,
        TrackerSettings,
        check_controller,
        track,
    )

    check_range(
        robustness,
        "robustness",
        0,
        1,
        fix="use a value between 0 (physically correct) and 1 (fully compensated).",
    )
    check_range(
        tolerance, "tolerance", 0, 1, fix="use a value between 0 (never switch balance off) and 1."
    )
    check_controller(controller)
    if recoveries is not None:
        check_range(recoveries, "recoveries", 0, 1000, fix="use 0 (none) or a small count.")
    pushes = sideways_pushes([push], "torso") if push else ()
    ref = reference_poses(clip_path, character, mapping, start_frame, clean, levelling)
    world = ref["world"]
    reference = kinematic_replay(world, ref["qpos"], ref["frame_time"])
    result = track(
        world,
        reference,
        robustness,
        TrackerSettings(
            tolerance=tolerance,
            controller=controller,
            recoveries=TRACK_RECOVERIES if recoveries is None else recoveries,
            **(foot or {}),
        ),
        pushes=pushes,
    )
    measure_simulated_feet(world, result)
    return world, reference, result


def measure_simulated_feet(world, result) -> None:
    """Set a tracking result's foot_skate_m and foot_skate_max_m (m, mean per stance and worst
    stance, `foot_metrics`) from its recorded poses."""
    from eigengait.motion.foot_metrics import foot_report
    from eigengait.motion.soles import sole_points

    feet = foot_report(sole_points(world, result.qpos), result.frame_time)
    result.foot_skate_m, result.foot_skate_max_m = feet.foot_skate_m, feet.foot_skate_max_m
