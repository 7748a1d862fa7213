"""The support polygon's share of an ankle torque and the double-support load shares, against
hand-worked cases."""

import numpy as np
import pytest

from eigengait.control.balance.double_support import CONTACT_M, load_shares, pressing_force
from eigengait.control.balance.support import carried_torque, convex_hull, nearest_in_hull

# A sole 0.2 m long (x) and 0.1 m wide (y) whose ankle stands over its centre, at the world origin.
SOLE = np.array([[x, y, 0.0] for x in (-0.1, 0.1) for y in (-0.05, 0.05)])
ANKLE = np.array([0.0, 0.0, 0.08])


def test_hull_of_a_rectangle_with_an_inner_point_is_its_corners():
    hull = convex_hull(np.vstack([SOLE[:, :2], [[0.0, 0.0]]]))
    assert len(hull) == 4 and {tuple(p) for p in hull} == {tuple(p) for p in SOLE[:, :2]}
    assert np.allclose(nearest_in_hull(np.array([0.3, 0.0]), hull), [0.1, 0.0])
    assert np.allclose(nearest_in_hull(np.array([0.02, 0.01]), hull), [0.02, 0.01])


def test_a_torque_within_the_sole_is_carried_whole():
    # 700 N on the sole: a pitch torque of 35 N·m needs the centre of pressure 5 cm from the ankle
    # (inside).
    torque = np.array([0.0, 35.0, 0.0])
    np.testing.assert_allclose(carried_torque(torque, 700.0, ANKLE, SOLE), torque, atol=1e-9)


def test_a_torque_past_the_edge_is_carried_up_to_the_edge():
    # 100 N·m of pitch needs 0.143 m (outside: the toe is at 0.1 m) -> 70 N·m carried; roll 20 N·m
    # needs 2.9 cm sideways (inside) -> carried whole.
    carried = carried_torque(np.array([-20.0, 100.0, 5.0]), 700.0, ANKLE, SOLE)
    np.testing.assert_allclose(carried, [-20.0, 70.0, 0.0], atol=1e-9)


def test_a_line_foot_carries_no_roll():
    line = SOLE[[0, 2]]  # heel and toe on the centre line (y = -0.05 both: a line parallel to x)
    line = line - [0.0, -0.05, 0.0]
    carried = carried_torque(np.array([30.0, 0.0, 0.0]), 700.0, ANKLE, line)
    np.testing.assert_allclose(carried, 0.0, atol=1e-9)


def test_load_shares_follow_the_lever_rule():
    feet = np.array([[0.0, 0.1], [0.0, -0.1]])
    down = np.zeros(2)
    np.testing.assert_allclose(load_shares(np.array([0.0, 0.05, 0.9]), feet, down), [0.75, 0.25])
    np.testing.assert_allclose(load_shares(np.array([0.0, 0.3, 0.9]), feet, down), [1.0, 0.0])
    one_up = np.array([0.0, 2 * CONTACT_M])
    np.testing.assert_allclose(load_shares(np.array([0.0, -0.1, 0.9]), feet, one_up), [1.0, 0.0])
    assert (
        pressing_force(0.5, 700.0, 100.0) == pytest.approx(250.0)
        and pressing_force(0.5, 700.0, 400.0) == 0.0
    )
