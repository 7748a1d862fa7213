"""Contact memory: contacts that vanish for a step or two are bridged, longer gaps are not."""

import numpy as np

from eigengait.control.balance.contact_memory import ContactMemory

ROWS = np.array([[0.1, 0.0, 0.0, 400.0], [0.3, 0.0, 0.0, 250.0]])  # position (m), normal force (N)
NONE = np.zeros((0, 4))


def test_a_foot_keeps_its_last_contacts_for_the_hold_and_then_leaves():
    memory = ContactMemory(hold=0.002)
    assert memory.bridged({"left": ROWS, "right": NONE}, 0.0)["left"] is ROWS
    step = 0.0005
    for k in range(1, 5):  # 0.5-2 ms later, the left foot reads no contact
        seen = memory.bridged({"left": NONE, "right": NONE}, k * step)
        np.testing.assert_array_equal(seen["left"], ROWS)
        assert len(seen["right"]) == 0  # a foot never seen touching stays off
    assert len(memory.bridged({"left": NONE, "right": NONE}, 5 * step)["left"]) == 0


def test_fresh_contacts_replace_the_remembered_ones():
    memory = ContactMemory(hold=0.002)
    memory.bridged({"left": ROWS}, 0.0)
    newer = ROWS * [1, 1, 1, 0.5]
    assert memory.bridged({"left": newer}, 0.0005)["left"] is newer
    np.testing.assert_array_equal(memory.bridged({"left": NONE}, 0.001)["left"], newer)
