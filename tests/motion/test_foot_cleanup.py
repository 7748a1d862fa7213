"""Skate removal by leg IK on a Daz-skeleton walk: the cleaned reference's feet hold still, the
upper body is kept."""

import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.motion.bvh import read_bvh
from eigengait.motion.foot_cleanup import (
    CLEARANCE_M,
    HOVER_CLIMB_SPEED,
    HOVERING_STANCE_M,
    MAX_CORRECTION_SPEED,
    PACE_FRACTION,
    MIN_STANCE_S,
    SOLE_SUPPORT_GAP_M,
    SOLE_SUPPORT_SPEED,
    STANCE_M,
    STANCE_SPEED,
    TOUCHDOWN_M,
    clean_feet,
    foot_corrections,
    root_pace,
)
from eigengait.motion.foot_metrics import CONTACT_M, foot_report
from eigengait.motion.lead_in import first_frame_after_lead_in
from eigengait.motion.retarget import builtin_mapping, retarget
from eigengait.motion.soles import sole_points
from eigengait.sim.world import build_world
from shared_data import MOCAP

SKATE_BOUND_M = 0.03
SKATE_FRACTION = 0.35


@pytest.fixture(scope="module")
def cleaned():
    world = build_world(load_character("walker"))
    clip = read_bvh(MOCAP / "cmu_07_06_walk_daz.bvh")
    poses = retarget(
        clip, world, builtin_mapping("walker", clip), start_frame=first_frame_after_lead_in(clip, 1)
    )
    return world, poses, clean_feet(world, poses.qpos, poses.frame_time)


def test_cleaned_skate_is_a_fraction_of_the_raw_one(cleaned):
    # Measured: raw 0.298 m per stance, cleaned 0.011 m (0.024 m while a foot's hold began and
    # ended at the raw height, 1-2 cm up and moving; 0.069 m when a foot sliding mid-stance without
    # leaving the floor was found as two stances back to back).
    world, poses, result = cleaned
    raw = foot_report(sole_points(world, poses.qpos), poses.frame_time)
    clean = foot_report(sole_points(world, result.qpos), poses.frame_time)
    assert (
        raw.foot_skate_m > SKATE_BOUND_M and clean.foot_skate_m < SKATE_FRACTION * raw.foot_skate_m
    )
    assert clean.foot_skate_m < CONTACT_M  # under the skate measure's own contact band
    # 5.2 mm: the leg pulled toward its retargeted pose leaves a held foot a few mm off its target
    # (leg_ik); 0.1 mm when each frame's IK met its target exactly, with joint-speed spikes
    assert clean.stances >= 4 and clean.floor_penetration_m < 0.01
    assert result.ik_error_m < 0.06


def test_only_the_legs_move(cleaned):
    world, poses, result = cleaned
    model = world.model
    leg = [
        j
        for j in range(model.njnt)
        if any(s in model.joint(j).name for s in ("thigh", "shin", "foot"))
    ]
    legs = np.concatenate([model.jnt_qposadr[j] + np.arange(4) for j in leg])
    others = np.setdiff1d(np.arange(model.nq), legs)
    np.testing.assert_array_equal(result.qpos[:, others], poses.qpos[:, others])
    assert np.abs(result.qpos[:, legs] - poses.qpos[:, legs]).max() > 0.01


def _leg_speeds(model, qpos: np.ndarray, frame_time: float) -> np.ndarray:
    """Rotation speed (deg/s) of each leg joint (ball) between consecutive poses (F - 1, joints)."""
    legs = [j for j in range(model.njnt) if model.joint(j).name.endswith(("thigh", "shin", "foot"))]
    turns = []
    for joint in legs:
        quat = qpos[:, model.jnt_qposadr[joint] : model.jnt_qposadr[joint] + 4]
        cosine = np.abs(np.sum(quat[1:] * quat[:-1], axis=1)).clip(0.0, 1.0)
        turns.append(np.degrees(2 * np.arccos(cosine)) / frame_time)
    return np.stack(turns, axis=1)


def test_the_cleaned_legs_turn_about_as_fast_as_the_retargeted_ones(cleaned):
    # Measured: retargeted 721 deg/s at most, cleaned 985 (2 316 while each frame's IK started
    # from the retargeted pose and its damped steps landed in different leg poses frame to frame).
    world, poses, result = cleaned
    raw = _leg_speeds(world.model, poses.qpos, poses.frame_time).max()
    assert _leg_speeds(world.model, result.qpos, poses.frame_time).max() < 1.5 * raw


def _stand_move_stand(lift_m: float, frame_time: float = 0.01, n: int = 200) -> np.ndarray:
    """Sole points (n, 2, 3) of a foot that stands, moves 0.2 m forward in 0.2 s (1 m/s: faster
    than a stance) with its sole `lift_m` up at the middle of the move, and stands again."""
    points = np.zeros((n, 2, 3))
    points[:, 1, 0] = 0.18
    slide = np.concatenate([np.zeros(60), np.linspace(0.0, 0.2, 20), np.full(n - 80, 0.2)])
    lift = np.zeros(n)
    lift[60:80] = lift_m * np.sin(np.linspace(0.0, np.pi, 20))
    points[..., 0] += slide[:, None]
    points[..., 2] += lift[:, None]
    return points


def test_holds_that_meet_are_joined_without_a_jump():
    # A shuffle step (the sole 3 cm up between two stances, found back to back) asks for positions
    # 0.2 m apart: the correction's step at the junction is bounded by MAX_CORRECTION_SPEED.
    frame_time = 0.01
    correction, holds = foot_corrections(_stand_move_stand(0.03), frame_time)
    assert len(holds) == 2
    steps = np.linalg.norm(np.diff(correction[:, :2], axis=0), axis=1)
    assert steps.max() <= MAX_CORRECTION_SPEED * frame_time + 1e-9


def test_a_foot_that_slides_without_leaving_the_floor_is_one_stance_held_still():
    # The same move with the sole on the floor throughout (a retargeted foot sliding 0.2 m
    # mid-stance): one stance, and the corrected sole stays where it stood at mid-stance.
    points = _stand_move_stand(0.0)
    correction, holds = foot_corrections(points, 0.01)
    assert len(holds) == 1 and holds[0] == (0, len(points))
    held = points[..., :2] + correction[:, None, :2]
    np.testing.assert_allclose(held, np.broadcast_to(held[100], held.shape), atol=1e-9)


def test_a_swing_that_skims_the_floor_a_stride_forward_is_a_step():
    # The same as above but 1 m forward in 0.35 s (a walk's swing, 2.9 m/s) with the sole never
    # more than 1.8 cm up (CMU 05_01's right foot): two stances, the second held 1 m ahead.
    frame_time, n = 1 / 120, 240
    points = np.zeros((n, 2, 3))
    points[:, 1, 0] = 0.18
    swing = slice(80, 122)
    x = np.concatenate([np.zeros(80), np.linspace(0.0, 1.0, 42), np.ones(n - 122)])
    points[..., 0] += x[:, None]
    points[swing, :, 2] = 0.018 * np.sin(np.linspace(0.0, np.pi, 42))[:, None]
    correction, holds = foot_corrections(points, frame_time)
    assert len(holds) == 2
    held = points[..., :2] + correction[:, None, :2]
    assert held[-1, 0, 0] - held[0, 0, 0] == pytest.approx(1.0, abs=1e-9)


def _soles(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Sole points (F, 2, 3) of a level foot 18 cm long whose heel point follows x (F,) forward and
    both points z (F,) up (m)."""
    points = np.zeros((len(x), 2, 3))
    points[:, 0, 0], points[:, 1, 0] = x, x + 0.18
    points[..., 2] = z[:, None]
    return points


def _runner_foot(frame_time: float) -> np.ndarray:
    """Sole points (F, 2, 3) of a runner's foot: 0.25 s on the floor sliding at 1.1 m/s (a
    retargeted stance), 0.3 s of swing 8 cm up at 4.4 m/s, 0.25 s on the floor again."""
    n_stance, n_swing = int(round(0.25 / frame_time)), int(round(0.3 / frame_time))
    speed = np.concatenate([np.full(n_stance, 1.1), np.full(n_swing, 4.4), np.full(n_stance, 1.1)])
    x = np.cumsum(speed) * frame_time
    z = np.concatenate([np.zeros(n_stance), np.full(n_swing, 0.08), np.zeros(n_stance)])
    return _soles(x, z)


def test_a_runners_sliding_stance_is_found_at_its_pace():
    # At 2.4 m/s the bound is PACE_FRACTION × 2.4 = 1.2 m/s: both sliding stances are found and
    # held (not lifted as swing feet); with the walking bound (0.8 m/s) neither is, and the feet on
    # the floor are lifted to the swing clearance.
    frame_time = 1 / 120
    points = _runner_foot(frame_time)
    pace = np.full(len(points), 2.4)
    assert PACE_FRACTION * 2.4 > 1.1
    correction, holds = foot_corrections(points, frame_time, pace)
    assert len(holds) == 2
    assert holds[0][0] == 0 and holds[1][1] == len(points)
    # on the floor, nothing lifted to the swing clearance: only the holds' ends rise to touchdown
    assert np.abs(correction[:, 2]).max() <= TOUCHDOWN_M
    assert all(abs(correction[(start + end) // 2, 2]) < 1e-9 for start, end in holds)
    walking, none = foot_corrections(points, frame_time)
    assert none == [] and walking[10, 2] == pytest.approx(CLEARANCE_M)


def test_root_pace_is_the_roots_horizontal_speed(cleaned):
    world, poses, _ = cleaned
    qpos = np.tile(poses.qpos[0], (100, 1))
    qpos[:, 0] = 1.5 * np.arange(100) * 0.01  # 1.5 m/s along x, 2 m/s up: not counted
    qpos[:, 2] += 2.0 * np.arange(100) * 0.01
    np.testing.assert_allclose(root_pace(world, qpos, 0.01), 1.5, rtol=1e-9)


def test_a_short_stance_is_kept_only_at_the_clips_ends():
    # A foot on the floor for 0.06 s (less than MIN_STANCE_S) at the clip's start, at its middle
    # and at its end, 10 cm up in between: the runs at the ends, whose true length is unknown, are
    # stances; the one in the middle (a brush of the floor) is not.
    frame_time, n = 1 / 120, 240
    points = np.zeros((n, 2, 3))
    points[:, 1, 0] = 0.18
    points[..., 2] = 0.1
    for down in (slice(0, 7), slice(117, 124), slice(n - 7, n)):
        points[down, :, 2] = 0.0
    assert 7 * frame_time < MIN_STANCE_S
    _, holds = foot_corrections(points, frame_time)
    assert [(a, b) for a, b in holds] == [(0, 7), (n - 7, n)]


def _planted_then_landing(frame_time: float, height: float, drop_speed: float) -> np.ndarray:
    """Sole points (F, 2, 3) of a foot standing still `height` m up for 0.5 s (a planted foot the
    retargeting left hovering), then, after a 0.3 s swing 15 cm up, coming straight down onto the
    floor at `drop_speed` m/s and standing there 0.3 s."""
    hover, swing, stand = (int(round(s / frame_time)) for s in (0.5, 0.3, 0.3))
    drop = int(round(0.15 / drop_speed / frame_time))
    z = np.concatenate([np.full(hover, height), np.full(swing, 0.15)])
    z = np.concatenate([z, np.linspace(0.15, 0.0, drop), np.zeros(stand)])
    x = np.concatenate([np.zeros(hover), np.linspace(0.0, 1.0, swing), np.ones(drop + stand)])
    return _soles(x, z)


def test_a_foot_hovering_still_above_the_stance_band_is_a_stance_put_on_the_floor():
    frame_time = 1 / 120
    height = 0.065
    assert STANCE_M < height < HOVERING_STANCE_M
    points = _planted_then_landing(frame_time, height, drop_speed=1.5)
    correction, holds = foot_corrections(points, frame_time)
    assert holds[0][0] == 0 and holds[0][1] >= int(round(0.45 / frame_time))
    assert correction[30, 2] == pytest.approx(-height)  # held on the floor, mid-hover


def test_a_foot_dropping_through_the_band_is_held_only_below_the_stance_band():
    # Landing at 1.5 m/s (a runner's foot, measured 1.7 m/s) it passes 8 -> 5 cm in 20 ms; the
    # hold begins where the foot is within STANCE_M, not above.
    frame_time = 1 / 120
    assert 1.5 > HOVER_CLIMB_SPEED
    points = _planted_then_landing(frame_time, 0.065, drop_speed=1.5)
    _, holds = foot_corrections(points, frame_time)
    landing_start = holds[-1][0]
    assert points[landing_start, :, 2].min() <= STANCE_M + 1e-9


def test_the_only_foot_near_the_floor_is_a_stance_while_it_slides():
    # A dancer's standing foot sliding at 1.2 m/s at a 0.8 m/s pace (above both stance bounds)
    # while the other foot kicks 0.6 m up: the only possible support, held still; the same slide
    # with the other foot on the floor too is not (two low feet, one of them may be skimming).
    frame_time, n = 1 / 120, 60
    points = _soles(1.2 * frame_time * np.arange(n), np.zeros(n))
    pace = np.full(n, 0.8)
    assert 1.2 > max(STANCE_SPEED, PACE_FRACTION * 0.8) and 1.2 <= SOLE_SUPPORT_SPEED
    kick = np.full(n, 0.6)
    assert kick.min() > SOLE_SUPPORT_GAP_M
    correction, holds = foot_corrections(points, frame_time, pace, kick)
    assert holds == [(0, n)]
    held = points[..., :2] + correction[:, None, :2]
    np.testing.assert_allclose(held, np.broadcast_to(held[n // 2], held.shape), atol=1e-9)
    _, none = foot_corrections(points, frame_time, pace, np.zeros(n))
    assert none == []


def test_a_hovering_stance_is_brought_down_no_faster_than_the_correction_bound():
    # A swing 12 cm up at 2 m/s, then the foot hovering still 6.5 cm up (a stance, held on the
    # floor): the foot is brought down at most MAX_CORRECTION_SPEED, before the hold, not in one
    # frame (a Bandai Namco walk's foot was dropped 7.9 cm between two frames).
    frame_time, height = 1 / 120, 0.065
    swing, hover = 60, 60
    x = np.concatenate(
        [2.0 * frame_time * np.arange(swing), np.full(hover, 2.0 * frame_time * swing)]
    )
    z = np.concatenate([np.full(swing, 0.12), np.full(hover, height)])
    correction, holds = foot_corrections(_soles(x, z), frame_time)
    start = holds[0][0]
    assert swing <= start < swing + hover // 4
    assert np.abs(np.diff(correction[:, 2])).max() <= MAX_CORRECTION_SPEED * frame_time + 1e-9
    assert correction[swing + hover // 2, 2] == pytest.approx(-height)
    assert correction[start - 1, 2] < -0.03  # already coming down before the hold


def test_a_bounced_landing_is_one_hold():
    # A heel that lands, bounces 3.6 cm up for 0.03 s (a speed bump splits the still run) and comes
    # down 1 cm further on: one hold, held still, not two held at different places.
    frame_time = 1 / 120
    x = np.zeros(120)
    z = np.zeros(120)
    bounce = slice(50, 54)
    x[bounce], z[bounce] = np.linspace(0.0, 0.01, 4) + 0.03, 0.036
    x[54:] = 0.01
    points = _soles(x, z)
    correction, holds = foot_corrections(points, frame_time)
    assert len(holds) == 1
    cleaned = points + correction[:, None, :]
    assert foot_report({"left": cleaned}, frame_time).foot_skate_m < 0.003


def test_a_shuffle_step_between_back_to_back_holds_is_lifted():
    # A foot that shuffles 15 cm sideways in 0.1 s at 3 cm up between two still stances: two holds
    # that meet. The shift between their positions is lifted to the swing clearance instead of
    # sliding along the floor, so each stance is still.
    frame_time = 1 / 120
    n_still, n_shift = 60, 12
    y = np.concatenate([np.zeros(n_still), np.linspace(0.0, 0.15, n_shift), np.full(n_still, 0.15)])
    z = np.concatenate([np.zeros(n_still), np.full(n_shift, 0.03), np.zeros(n_still)])
    points = _soles(np.zeros(len(y)), z)
    points[..., 1] = y[:, None]
    correction, holds = foot_corrections(points, frame_time)
    assert len(holds) == 2
    cleaned = points + correction[:, None, :]
    report = foot_report({"left": cleaned}, frame_time)
    assert report.stances == 2 and report.foot_skate_max_m < 0.005
    moving = np.flatnonzero(np.abs(np.diff(cleaned[:, 0, 1])) > 1e-6) + 1
    assert moving.size and cleaned[moving, :, 2].min() > CONTACT_M  # off the floor as it moves
    assert cleaned[moving, :, 2].max() == pytest.approx(CLEARANCE_M)
    step = np.abs(np.diff(correction, axis=0)).max()
    assert step <= MAX_CORRECTION_SPEED * frame_time + 1e-9  # lifted without a jump
