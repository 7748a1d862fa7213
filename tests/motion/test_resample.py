import numpy as np
import pytest

from eigengait.errors import UserInputError
from eigengait.motion.resample import at_frame_rate, frame_times, quaternion_addresses, resample


@pytest.fixture(scope="module")
def humanoid_world():
    from eigengait.character import load_character
    from eigengait.sim.world import build_world

    return build_world(load_character("humanoid"))


def test_frames_fall_exactly_on_the_requested_times(humanoid_world):
    model = humanoid_world.model
    source_fps = 1 / (33 * 0.0005)
    count = 122  # ≈ 2.0 s at 60.606 samples/s
    qpos = np.repeat(model.qpos0[None], count, axis=0)
    qpos[:, 0] = np.arange(count) / source_fps  # root x moves at 1 m/s
    out = at_frame_rate(model, qpos, source_fps, 60.0)
    assert len(out) == int((count - 1) / source_fps * 60) + 1
    np.testing.assert_allclose(out[:, 0], np.arange(len(out)) / 60.0, atol=1e-12)
    slow = at_frame_rate(model, qpos, source_fps, 60.0, speed=0.5)
    np.testing.assert_allclose(slow[:, 0], np.arange(len(slow)) / 120.0, atol=1e-12)


def test_quaternions_stay_unit_and_take_the_short_way(humanoid_world):
    model = humanoid_world.model
    adr = quaternion_addresses(model)
    assert len(adr) == 1 + 10  # the free root and ten ball joints
    a, b = model.qpos0.copy(), model.qpos0.copy()
    # a 0.4 rad turn, stored with a flipped sign
    b[adr[1] : adr[1] + 4] = -np.array([np.cos(0.2), np.sin(0.2), 0, 0])
    mid = resample(model, np.array([a, b]), [0.0, 1.0], [0.5])[0]
    quat = mid[adr[1] : adr[1] + 4]
    assert np.linalg.norm(quat) == pytest.approx(1.0)
    # half of the short 0.4 rad arc
    assert 2 * np.arccos(abs(quat[0])) == pytest.approx(0.2, abs=1e-3)


def test_bad_rates_are_refused():
    with pytest.raises(UserInputError):
        frame_times(1.0, 0.0)
    with pytest.raises(UserInputError):
        frame_times(1.0, 30.0, speed=-1.0)
