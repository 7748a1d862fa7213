"""The locomotion targets a shipped gait is judged by, on hand-made summaries."""

from eigengait.control.gait_targets import targets

GOOD = {
    "cycles_completed": 20,
    "fell": False,
    "max_frame_jump_deg": 12.0,
    "max_root_jump_m": 0.02,
    "stance_slip_max_m": 0.02,
    "torso_pitch_deg": [-10.0, 12.0],
    "torso_roll_deg": [-8.0, 9.0],
    "mean_speed_mps": 0.6,
    "flight_fraction": 0.2,
    "cadence_spm": 170.0,
}


def test_a_trot_meets_the_footfall_targets_and_a_bound_does_not():
    trot = {"front_left": 0.02, "rear_right": 0.97, "front_right": 0.51, "rear_left": 0.45}
    bound = {"front_left": 0.5, "front_right": 0.52, "rear_left": 0.0, "rear_right": 0.03}
    met = targets("dog-trot", {**GOOD, "footfall": trot}, [True] * 4 + [False])
    assert all(met.values()) and len(met) == 9
    met = targets("dog-trot", {**GOOD, "footfall": bound}, [True] * 5)
    assert not met["diagonal pairs together"] and not met["pairs half a cycle apart"]
    # a foot that never touched down has no footfall phase; without pushes nothing was survived
    unknown = {**trot, "rear_left": None}
    met = targets("dog-trot", {**GOOD, "footfall": unknown}, None)
    assert not met["diagonal pairs together"] and not met["pairs half a cycle apart"]
    assert not met["pushes ≥ 4/5"]


def test_each_shared_target_fails_on_its_own_figure():
    run = dict(GOOD, mean_speed_mps=1.3)
    assert all(targets("humanoid-basic-run", run, [True] * 5).values())
    for key, bad, target in (
        ("max_frame_jump_deg", 15.5, "jump ≤ 15°"),
        ("max_root_jump_m", 0.07, "root jump ≤ 6 cm"),
        ("stance_slip_max_m", 0.031, "slip ≤ 3 cm"),
        ("torso_roll_deg", [-31.0, 5.0], "tilt ≤ 30°"),
        ("cadence_spm", 205.0, "cadence 140–200"),
        ("mean_speed_mps", 1.19, "speed ≥ 1.2"),
    ):
        met = targets("humanoid-basic-run", {**run, key: bad}, [True] * 5)
        assert [t for t, ok in met.items() if not ok] == [target], key
    assert not targets("humanoid-basic-run", run, [True] * 3 + [False] * 2)["pushes ≥ 4/5"]
    assert set(targets("kangaroo-hop", GOOD, None)) == {
        "20 cycles",
        "jump ≤ 15°",
        "root jump ≤ 6 cm",
        "slip ≤ 3 cm",
        "tilt ≤ 30°",
        "speed ≥ 0.8",
        "flight ≥ 0.15",
    }
