"""Contact memory: contacts missing from one reading are bridged, longer gaps are not."""

import numpy as np

from eigengait.control.balance.contact_memory import ContactMemory

ROWS = np.array([[0.1, 0.0, 0.0, 400.0], [0.3, 0.0, 0.0, 250.0]])  # position (m), normal force (N)
NONE = np.zeros((0, 4))


def test_a_foot_keeps_its_last_contacts_for_the_bridged_readings_and_then_leaves():
    memory = ContactMemory(steps=2)
    assert memory.bridged({"left": ROWS, "right": NONE})["left"] is ROWS
    for _ in range(2):  # two readings without the left foot's contacts
        seen = memory.bridged({"left": NONE, "right": NONE})
        np.testing.assert_array_equal(seen["left"], ROWS)
        assert len(seen["right"]) == 0  # a foot never seen touching stays off
    assert len(memory.bridged({"left": NONE, "right": NONE})["left"]) == 0


def test_fresh_contacts_replace_the_remembered_ones_and_restart_the_count():
    memory = ContactMemory(steps=1)
    memory.bridged({"left": ROWS})
    assert len(memory.bridged({"left": NONE})["left"]) == 2
    newer = ROWS * [1, 1, 1, 0.5]
    assert memory.bridged({"left": newer})["left"] is newer
    np.testing.assert_array_equal(memory.bridged({"left": NONE})["left"], newer)
    assert len(memory.bridged({"left": NONE})["left"]) == 0
