"""The shared fall rule: COM drop, upside-down root, a body on the floor."""

import numpy as np

from eigengait.sim.falls import COM_DROP, has_fallen


def test_each_condition_alone_is_a_fall():
    assert not has_fallen(0.9, 1.0)
    assert has_fallen(COM_DROP * 1.0 - 1e-6, 1.0)
    assert not has_fallen(COM_DROP * 1.0 + 1e-6, 1.0)
    assert has_fallen(0.9, 1.0, up_z=-0.01)
    assert has_fallen(0.9, 1.0, body_on_floor=True)


def test_rows_of_a_batch_are_judged_elementwise():
    com = np.array([[1.0, 0.4], [0.9, 0.9]])
    up = np.array([[1.0, 1.0], [-1.0, 0.5]])
    np.testing.assert_array_equal(has_fallen(com, 1.0, up), [[False, True], [True, False]])
