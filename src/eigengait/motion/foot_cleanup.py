"""Remove stance-foot skate and floor penetration from a retargeted pose sequence before it becomes
the reference.

1. Stances per foot: runs of at least MIN_STANCE_S in which the foot's lowest sole point (`soles`)
   is within STANCE_M of the floor (looser than the 2 cm of the skate measure, so a hovering stance
   foot is still found) and the horizontal speed of its sole centre, smoothed over
   SPEED_SMOOTHING_S, is below STANCE_SPEED or, when the body moves faster, below PACE_FRACTION of
   the root's horizontal speed smoothed over PACE_SMOOTHING_S (a sliding stance foot is still
   found; a swing foot passing low over the floor moves faster, at one to three times the body's
   pace). A retargeted runner's stance feet slide at up to 1.5 m/s at 2.2 m/s (CMU 16_36): with
   the walking bound alone two of its four stances were missed and then lifted as swing feet
   (step 3), so that the reference ran on feet 5 cm above the floor. Two such runs between which
   the foot's lowest sole point stays within TOUCH_M of the floor, or leaves it for less than
   `foot_metrics.BOUNCE_S` (a bounce), and its sole centre travels less than JOIN_TRAVEL_M are one
   stance: a retargeted foot sliding fast mid-stance without leaving the floor (CMU 07_06, 05_01:
   1-7 cm between the runs) was otherwise found as two stances back to back, each held where it
   stood at its own middle, and the bounded change between them (step 4) left 10-16 cm of skate in
   a stance; so did a landing heel that bounces 3.6 cm up for 0.03 s (CMU 07_06: 9.9 cm in the
   stance, with the bounce counted in it). A swing that skims the floor travels a stride (1 m in
   05_01, whose swing foot rises 2.0-2.6 cm): joined, the walk played 1.25 times faster lost a step
   and fell. A foot higher than STANCE_M but within HOVERING_STANCE_M, the most the grounding leaves
   under a supporting foot (`grounding.FLIGHT_M`), is in a stance too when it also holds its height
   (its lowest sole point's vertical speed, smoothed likewise, under HOVER_CLIMB_SPEED): retargeted,
   a CMU kick's planted foot hovers 5-9 cm up for 0.7 s, was lifted as a swing, and the body fell as
   the other leg kicked. Measured in that band, over horizontally slow frames: hovering stances (the
   kick, the walk 08_08) rise or sink at 0.07-0.16 m/s (median; 0.33 at the 90th percentile),
   runners' feet landing or leaving at 1.7 m/s. A foot that is the body's only possible support
   (every other foot more than SOLE_SUPPORT_GAP_M up) and holds its height (vertical speed under
   HOVER_CLIMB_SPEED) is in a stance up to SOLE_SUPPORT_SPEED: a CMU dancer's standing foot slides
   at 0.6-1.2 m/s under a high kick at a 0.5-1 m/s pace, was lifted to the swing clearance, and the
   body, standing on nothing, fell.
2. Each stance is held from its start to its end, grown by up to EXTEND_S on each side while the
   foot stays within STANCE_M (touch-down and lift-off). Over the hold, the foot's slip is the
   cumulative horizontal displacement of its touching sole points (those within TOUCH_M of its
   lowest one); the correction keeps the touching part where it is at mid-stance: horizontal
   −(slip(t) − slip(mid)); vertically the lowest sole point is put on the floor in the still part
   and at TOUCHDOWN_M (or its own height, if higher) at the hold's ends, in between linearly: a
   foot sets down and lifts off vertically over the last centimetres, where the skate measure
   (`foot_metrics`, CONTACT_M) counts it as touching. (Holds that began at the raw height let a
   skimming retargeted foot, 1-2 cm up at a walk's swing speed, enter them moving: CMU 05_01's
   cleaned skate 3.3 cm per stance, 0.9 cm now.)
3. After and before a hold the horizontal correction fades linearly to zero over BLEND_S (at most
   half the gap to the next hold). A swing foot lower than CLEARANCE_M is lifted to it, the lift
   growing from TOUCHDOWN_M at the hold's edge over LIFT_S, so a foot skimming the floor is not
   taken for a sliding stance.
4. Where two holds of a foot meet (less than 2 BLEND_S apart: a low shuffle step is found as
   stances back to back), they may ask for different positions, and a jump between them would put a
   velocity spike of metres per second into the reference: within BLEND_S of such a junction the
   horizontal correction changes by at most MAX_CORRECTION_SPEED, and while the held foot moves
   from one position to the other (its sole centre faster than SHIFT_SPEED) it is lifted to
   CLEARANCE_M, as a step: kept on the floor, a CMU laugh's shuffle steps (raw feet 3 cm up) slid
   18 cm along it. Outside the holds' still cores and at junctions the vertical correction changes
   by at most MAX_CORRECTION_SPEED: a foot hovering still up to 8 cm up (a
   stance, put on the floor) comes down over a few frames before its hold, not between two.
5. Each corrected frame: damped least-squares IK (`leg_ik`) moves the hip, knee and ankle so that
   the foot body reaches its reference pose shifted by the correction, orientation kept; root and
   upper body are unchanged. The IK starts from the previous frame's solution when that frame was
   corrected too and is pulled toward the retargeted pose within the leg's redundancy, so the
   corrected legs move continuously (restarted from the retargeted pose each frame they turned at
   up to 8 800°/s where the retargeted legs stay under 1 000°/s).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.body_tree import leg_dofs
from eigengait.motion.foot_metrics import BOUNCE_S, CONTACT_M, runs
from eigengait.motion.grounding import FLIGHT_M
from eigengait.motion.leg_ik import solve_leg
from eigengait.motion.soles import sole_points
from eigengait.sim.world import World

STANCE_M = 0.05
HOVERING_STANCE_M = FLIGHT_M  # m
HOVER_CLIMB_SPEED = 0.5  # m/s
TOUCH_M = 0.02
JOIN_TRAVEL_M = 0.3  # m: less than half a stride
STANCE_SPEED = 0.8  # m/s
PACE_FRACTION = 0.5  # of the root's horizontal speed: the stance speed bound of fast motions
PACE_SMOOTHING_S = 0.25
SPEED_SMOOTHING_S = 0.05
MIN_STANCE_S = 0.1
EXTEND_S = 0.1
BLEND_S = 0.1
CLEARANCE_M = 0.05
TOUCHDOWN_M = CONTACT_M + 0.005  # a held foot's height at its hold's ends
LIFT_S = 0.05
SOLE_SUPPORT_GAP_M = 2 * CLEARANCE_M  # the other feet this far up: this foot is the only support
SOLE_SUPPORT_SPEED = 2 * STANCE_SPEED  # m/s, the stance bound of an only support
MAX_CORRECTION_SPEED = 2.0  # m/s
SHIFT_SPEED = 0.2  # m/s: a held foot moving faster is being shifted between two holds


@dataclass(frozen=True)
class CleanedFeet:
    """Cleaned poses (F, nq), stance frame ranges per foot, largest IK position miss (m)."""

    qpos: np.ndarray
    stances: dict[str, list[tuple[int, int]]]
    ik_error_m: float


def _slip(points: np.ndarray, start: int, end: int) -> np.ndarray:
    """Cumulative horizontal displacement (end − start, 2) of the touching sole points over a
    stance."""
    slip = np.zeros((end - start, 2))
    for i in range(start, end - 1):
        low = min(points[i, :, 2].min(), points[i + 1, :, 2].min())
        touching = (points[i, :, 2] <= low + TOUCH_M) & (points[i + 1, :, 2] <= low + TOUCH_M)
        if not touching.any():  # a foot dropping fast between frames (a 30 Hz clip's landing)
            touching = np.arange(points.shape[1]) == np.argmin(points[i : i + 2, :, 2].max(axis=0))
        step = (points[i + 1, touching, :2] - points[i, touching, :2]).mean(axis=0)
        slip[i - start + 1] = slip[i - start] + step
    return slip


def _smoothed(values: np.ndarray, frames: int) -> np.ndarray:
    """Moving average (F,) over `frames` samples, ends padded with the end values."""
    padded = np.pad(values, (frames // 2, frames - 1 - frames // 2), mode="edge")
    return np.convolve(padded, np.ones(frames) / frames, mode="valid")


def root_pace(world: World, qpos: np.ndarray, frame_time: float) -> np.ndarray:
    """Horizontal speed (m/s) of the root body's free joint per pose of qpos (F, nq) at frame_time
    (s), smoothed over PACE_SMOOTHING_S."""
    model = world.model
    adr = int(model.jnt_qposadr[model.body_jntadr[world.root_body]])
    if len(qpos) < 2:
        return np.zeros(len(qpos))
    speed = np.linalg.norm(np.gradient(qpos[:, adr : adr + 2], frame_time, axis=0), axis=1)
    return _smoothed(speed, max(1, int(round(PACE_SMOOTHING_S / frame_time))))


def _holds(
    low: np.ndarray,
    centre: np.ndarray,
    speed: np.ndarray,
    climb: np.ndarray,
    frame_time: float,
    bound: np.ndarray | float = STANCE_SPEED,
    others_low: np.ndarray | None = None,
) -> list[tuple[int, int, int, int]]:
    """(hold start, core start, core end, hold end) per stance: the still core (speed at most
    `bound`, m/s, per frame or one value, or SOLE_SUPPORT_SPEED where every other foot's lowest
    sole point `others_low` (F,) m is above SOLE_SUPPORT_GAP_M and `climb` is under
    HOVER_CLIMB_SPEED; the foot within STANCE_M, or within HOVERING_STANCE_M with its vertical speed
    `climb` (F,) m/s under HOVER_CLIMB_SPEED; at least MIN_STANCE_S long
    unless it touches either end of the clip, where its true length is unknown: a run clip that
    starts 0.09 s before a foot lifts otherwise began on a foot lifted as a swing, and fell) grown
    while the foot stays within STANCE_M; `centre` (F, 2) the sole centre's horizontal position
    (m)."""
    shortest = max(1, int(round(MIN_STANCE_S / frame_time)))
    low_enough = (low <= STANCE_M) | ((low <= HOVERING_STANCE_M) & (climb < HOVER_CLIMB_SPEED))
    slow = speed <= bound
    if others_low is not None:
        alone = (others_low > SOLE_SUPPORT_GAP_M) & (climb < HOVER_CLIMB_SPEED)
        slow |= alone & (speed <= SOLE_SUPPORT_SPEED)
    still = [
        (a, b)
        for a, b in runs(low_enough & slow, frame_time, 0.0)
        if b - a >= shortest or a == 0 or b == len(low)
    ]
    cores = _joined(still, low, centre, frame_time)
    grow, out = int(round(EXTEND_S / frame_time)), []
    for k, (a, b) in enumerate(cores):
        first = out[-1][3] if out else 0
        last = cores[k + 1][0] if k + 1 < len(cores) else len(low)
        start, end = a, b
        while start > max(first, a - grow) and low[start - 1] <= STANCE_M:
            start -= 1
        while end < min(last, b + grow) and low[end] <= STANCE_M:
            end += 1
        out.append((start, a, b, end))
    return out


def _joined(
    cores: list[tuple[int, int]], low: np.ndarray, centre: np.ndarray, frame_time: float
) -> list[tuple[int, int]]:
    """Still cores [start, end) with each pair between which the foot's lowest sole height `low`
    (F,) m stays within TOUCH_M of the floor, or leaves it for less than BOUNCE_S (frames of
    `frame_time` s), and its sole centre `centre` (F, 2) m travels less than JOIN_TRAVEL_M joined
    into one: a foot that slides or bounces without stepping is one stance, however fast its raw
    sole slides; one that skims the floor a stride forward has stepped."""
    out: list[tuple[int, int]] = []
    for a, b in cores:
        end = out[-1][1] if out else 0
        lifted = np.count_nonzero(low[end:a] > TOUCH_M) * frame_time
        if (
            out
            and lifted < BOUNCE_S
            and np.linalg.norm(centre[a] - centre[end - 1]) < JOIN_TRAVEL_M
        ):
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def _ramp(n: int) -> np.ndarray:
    """n weights falling linearly from just below 1 to just above 0."""
    return 1.0 - np.arange(1, n + 1) / (n + 1)


def foot_corrections(
    points: np.ndarray,
    frame_time: float,
    pace: np.ndarray | None = None,
    others_low: np.ndarray | None = None,
) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """Per-frame correction (F, 3) of one foot (m, world) and its stances (holds), from its sole
    points (F, k, 3), the body's pace (F,) m/s (`root_pace`; None: the walking bound
    STANCE_SPEED alone) and the other feet's lowest sole height (F,) m (None: no other foot)."""
    low, centre = points[..., 2].min(axis=1), points.mean(axis=1)[:, :2]
    n, width = len(points), max(1, int(round(SPEED_SMOOTHING_S / frame_time)))
    speed = _smoothed(np.linalg.norm(np.gradient(centre, frame_time, axis=0), axis=1), width)
    climb = np.abs(_smoothed(np.gradient(low, frame_time), width))
    bound = STANCE_SPEED if pace is None else np.maximum(STANCE_SPEED, PACE_FRACTION * pace)
    holds = _holds(low, centre, speed, climb, frame_time, bound, others_low)
    correction = np.zeros((n, 3))
    held = np.zeros(n, bool)
    blend = max(1, int(round(BLEND_S / frame_time)))
    for k, (start, a, b, end) in enumerate(holds):
        slip = _slip(points, start, end)
        correction[start:end, :2] = -(slip - slip[(a + b) // 2 - start])
        weight = np.concatenate([_ramp(a - start)[::-1], np.ones(b - a), _ramp(end - b)])
        height = (1.0 - weight) * np.maximum(low[start:end], TOUCHDOWN_M)
        correction[start:end, 2] = height - low[start:end]
        held[start:end] = True
        before = min(blend, (start - holds[k - 1][3]) // 2 if k else start)
        after = min(blend, (holds[k + 1][0] - end) // 2 if k + 1 < len(holds) else n - end)
        correction[start - before : start, :2] += correction[start, :2] * _ramp(before)[::-1, None]
        correction[end : end + after, :2] += correction[end - 1, :2] * _ramp(after)[:, None]
    lift = int(round(LIFT_S / frame_time))
    gap = np.full(n, lift, float)
    for start, _, _, end in holds:
        gap = np.minimum(gap, np.abs(np.arange(n) - np.clip(np.arange(n), start, end - 1)))
    swing = ~held & (low < CLEARANCE_M)
    rise = TOUCHDOWN_M + (CLEARANCE_M - TOUCHDOWN_M) * np.minimum(gap / max(lift, 1), 1.0)
    correction[swing, 2] += np.maximum(rise[swing] - low[swing], 0.0)
    junctions = np.zeros(n, bool)
    for (_, _, _, end), (start, _, _, _) in zip(holds, holds[1:]):
        if start - end < 2 * blend:
            junctions[max(end - blend, 0) : start + blend] = True
    correction[:, :2] = _limit_rate(correction[:, :2], MAX_CORRECTION_SPEED * frame_time, junctions)
    _lift_shifts(correction, centre, low, junctions, frame_time)
    outside_cores = np.ones(n, bool)
    for _, a, b, _ in holds:
        outside_cores[a:b] = False
    correction[:, 2:] = _limit_rate(
        correction[:, 2:], MAX_CORRECTION_SPEED * frame_time, outside_cores | junctions
    )
    return correction, [(start, end) for start, _, _, end in holds]


def _lift_shifts(
    correction: np.ndarray,
    centre: np.ndarray,
    low: np.ndarray,
    junctions: np.ndarray,
    frame_time: float,
) -> None:
    """Raise (in place) the lowest sole point to CLEARANCE_M wherever, within `junctions` (F,), the
    corrected sole centre (`centre` (F, 2) + correction, m) moves faster than SHIFT_SPEED."""
    moved = np.linalg.norm(np.diff(centre + correction[:, :2], axis=0), axis=1) / frame_time
    shifting = np.zeros(len(low), bool)
    shifting[1:] |= moved > SHIFT_SPEED
    shifting[:-1] |= moved > SHIFT_SPEED
    shifting &= junctions
    raised = low + correction[:, 2]
    correction[shifting, 2] += np.maximum(CLEARANCE_M - raised[shifting], 0.0)


def _limit_rate(values: np.ndarray, largest_step: float, free: np.ndarray) -> np.ndarray:
    """Rows (F, k) of which the `free` ones (F,) change by at most `largest_step` (norm) from their
    neighbour: a forward pass then a backward pass; the other rows are kept."""
    out = values.copy()
    for step_dir, order in ((1, range(1, len(out))), (-1, range(len(out) - 2, -1, -1))):
        for i in order:
            if not free[i]:
                continue
            prev = out[i - step_dir]
            change = out[i] - prev
            size = float(np.linalg.norm(change))
            if size > largest_step:
                out[i] = prev + change * (largest_step / size)
    return out


def _qpos_of_dofs(model: mujoco.MjModel, dofs: np.ndarray) -> np.ndarray:
    """The qpos indices of the joints that own `dofs`."""
    joints = sorted({int(model.dof_jntid[d]) for d in dofs})
    sizes = {int(mujoco.mjtJoint.mjJNT_BALL): 4, int(mujoco.mjtJoint.mjJNT_FREE): 7}
    return np.concatenate(
        [
            np.arange(
                model.jnt_qposadr[j], model.jnt_qposadr[j] + sizes.get(int(model.jnt_type[j]), 1)
            )
            for j in joints
        ]
    )


def clean_feet(world: World, qpos: np.ndarray, frame_time: float) -> CleanedFeet:
    """Skate-free copy of poses qpos (F, nq) at frame_time (s); see the module doc."""
    model = world.model
    data = mujoco.MjData(model)
    soles = sole_points(world, qpos)
    feet = {f: int(model.geom_bodyid[g[0]]) for f, g in world.foot_spheres.items()}
    pace = root_pace(world, qpos, frame_time)
    lows = {f: soles[f][..., 2].min(axis=1) for f in feet}
    plan = {
        f: foot_corrections(
            soles[f],
            frame_time,
            pace,
            np.min([lows[o] for o in feet if o != f], axis=0) if len(feet) > 1 else None,
        )
        for f in feet
    }
    out, worst = qpos.copy(), 0.0
    chains = {f: np.array(d) for f, d in leg_dofs(model, world.root_body, feet).items()}
    leg_qpos = {f: _qpos_of_dofs(model, chain) for f, chain in chains.items()}
    for i in range(len(qpos)):
        moving = [f for f in feet if np.any(plan[f][0][i])]
        if not moving:
            continue
        data.qpos[:] = qpos[i]
        mujoco.mj_kinematics(model, data)
        targets = {
            f: (data.xpos[feet[f]] + plan[f][0][i], data.xmat[feet[f]].reshape(3, 3).copy())
            for f in moving
        }
        for f in moving:
            if i > 0 and np.any(plan[f][0][i - 1]):  # from the previous frame's solution
                data.qpos[leg_qpos[f]] = out[i - 1, leg_qpos[f]]
            error = solve_leg(model, data, feet[f], chains[f], *targets[f], preferred=qpos[i])
            worst = max(worst, error)
        out[i] = data.qpos
    return CleanedFeet(qpos=out, stances={f: plan[f][1] for f in feet}, ik_error_m=worst)
