"""The locomotion targets a shipped gait is judged by (docs/locomotion.md, "Shipped gaits against
the targets"): every gait 20 cycles without falling, no joint jump over 15° and no root jump over
6 cm between 60 Hz frames, stance slip ≤ 3 cm, root pitch and roll within ±30°; per gait a speed,
flight and cadence or footfall pattern; the run and the trot survive 4 of 5 sideways pushes of
0.5 N·s/kg in cycle 3.
"""

from __future__ import annotations

from eigengait.control.gait_metrics import phase_distance

PUSHED = ("humanoid-basic-run", "dog-trot")  # the gaits with a push target
MAX_TILT_DEG = 30.0  # root pitch and roll, every gait
MAX_SLIP_M = 0.03  # mean stance-foot slip per stance, every gait


def targets(name: str, m: dict, pushes: list[bool] | None) -> dict[str, bool]:
    """Target -> met, for the shipped gait `name` played 20 cycles with summary `m` (`play`'s
    quality figures) and `pushes` (survived per push, None: not pushed)."""
    tilt = max(abs(v) for v in m["torso_pitch_deg"] + m["torso_roll_deg"])
    out = {
        "20 cycles": m["cycles_completed"] == 20 and not m["fell"],
        "jump ≤ 15°": (m["max_frame_jump_deg"] or 0) <= 15,
        "root jump ≤ 6 cm": (m["max_root_jump_m"] or 0) <= 0.06,
        "slip ≤ 3 cm": m["stance_slip_max_m"] is not None and m["stance_slip_max_m"] <= MAX_SLIP_M,
        "tilt ≤ 30°": tilt <= MAX_TILT_DEG,
    }
    speed, flight = m["mean_speed_mps"], m["flight_fraction"]
    if name == "humanoid-basic-run":
        out.update(
            {
                "speed ≥ 1.2": speed >= 1.2,
                "flight ≥ 0.10": flight >= 0.10,
                "cadence 140–200": m["cadence_spm"] is not None and 140 <= m["cadence_spm"] <= 200,
            }
        )
    elif name == "monster-run":
        out.update({"speed ≥ 1.2": speed >= 1.2, "flight > 0": flight > 0})
    elif name == "kangaroo-hop":
        out.update({"speed ≥ 0.8": speed >= 0.8, "flight ≥ 0.15": flight >= 0.15})
    elif name == "dog-trot":
        f = m["footfall"]
        known = None not in f.values()
        out.update(
            {
                "speed ≥ 0.5": speed >= 0.5,
                "diagonal pairs together": known
                and phase_distance(f["front_left"], f["rear_right"]) <= 0.1
                and phase_distance(f["front_right"], f["rear_left"]) <= 0.1,
                "pairs half a cycle apart": known
                and abs(phase_distance(f["front_left"], f["front_right"]) - 0.5) <= 0.15,
            }
        )
    if name in PUSHED:
        out["pushes ≥ 4/5"] = pushes is not None and sum(pushes) >= 4
    return out
