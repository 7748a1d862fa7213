"""Track a motion-capture clip (a BVH file inside the studio folder) in physics with the balance
controller.

The controller is the whole-body QP (`qp`, the default) or the chapter's momentum law
(`momentum`). The robustness slider prices the artificial torque: 0 = physically correct (none),
1 = very stable (the QP's torque on the pelvis nearly free, or the momentum law's stance-foot torque
fully cancelled); beside it, the momentum law's cylinder foot: its radius, COM height and friction
set how much torque a given robustness cancels (control/balance/foot.py). The tracked motion plays
on the stage with the camera following; the report gives the tracking errors and the artificial
torque used.
"""

from __future__ import annotations

import viser

from eigengait.character import builtin_names
from eigengait.control.balance.tracker import CONTROLLERS, TrackerSettings
from eigengait.errors import UserInputError
from eigengait.motion.tracking import run_track
from eigengait.studio.messages import Messages
from eigengait.studio.sandbox import Sandbox
from eigengait.studio.stage import Stage

TRACKING_CHARACTERS = ("walker", "humanoid")


class TrackPanel:
    def __init__(
        self,
        server: viser.ViserServer,
        sandbox: Sandbox,
        stage: Stage,
        messages: Messages,
        gui_order: float,
    ):
        self.sandbox, self.stage, self.messages = sandbox, stage, messages
        self.result = None
        gui = server.gui
        with gui.add_folder("Track mocap (gravity on)", order=gui_order, expand_by_default=False):
            self.clip = gui.add_text("BVH clip", "", hint="a .bvh file inside the studio folder")
            choices = [c for c in TRACKING_CHARACTERS if c in builtin_names()]
            self.character = gui.add_dropdown("character", choices, initial_value=choices[0])
            self.controller = gui.add_dropdown(
                "controller", CONTROLLERS, initial_value=TrackerSettings().controller
            )
            self.robustness = gui.add_slider(
                "robustness",
                min=0.0,
                max=1.0,
                step=0.05,
                initial_value=0.5,
                hint="0 = physically correct … 1 = artificial torque nearly free",
            )
            self.foot_radius = gui.add_number("foot radius (m)", 0.1, min=0.0, max=1.0, step=0.01)
            self.foot_height = gui.add_number(
                "foot COM height (m)", 0.05, min=0.0, max=1.0, step=0.01
            )
            self.foot_friction = gui.add_number(
                "foot friction μ", 1.0, min=0.01, max=10.0, step=0.1
            )
            self.push = gui.add_text(
                "push", "", hint="optional FORCE@TIME (N, s), sideways at the torso"
            )
            self.run = gui.add_button("Track in physics", icon=viser.Icon.RUN)
            self.report = gui.add_markdown("")
        self.run.on_click(messages.guarded(lambda e: self.track_file(self.clip.value, e.client)))

    def track_file(self, text: str, client: viser.ClientHandle | None = None):
        """Retarget and track the clip; show the simulated motion and report its errors."""
        if not str(text).strip():
            raise UserInputError(
                "no clip given", field="BVH clip", fix="type the name of a .bvh file in the folder"
            )
        path = self.sandbox.resolve(str(text).strip(), (".bvh",), must_exist=True)
        push = self.push.value.strip() or None
        foot = {
            "foot_radius_m": float(self.foot_radius.value),
            "foot_com_height_m": float(self.foot_height.value),
            "foot_friction": float(self.foot_friction.value),
        }
        world, reference, result = run_track(
            path,
            self.character.value,
            float(self.robustness.value),
            push,
            None,
            1,
            0.0,
            foot=foot,
            controller=self.controller.value,
        )
        self.result = result
        self.stage.show("tracking", world, result.qpos, 1.0 / result.frame_time, follow=True)
        state = f"fell at {result.fall_time_s:.2f} s" if result.fell else "did not fall"
        self.report.content = (
            f"**{path.name}** on {self.character.value}: tracked {result.duration_s:.2f} s of "
            f"{reference.duration:.2f} s ({state}); joint RMS {result.joint_rms_deg:.1f}°, COM "
            f"error {result.com_error_m:.3f} m, mean artificial torque "
            f"{result.artificial_torque:.1f} N·m ({self.controller.value} controller)."
        )
        if result.recovery_simulations:
            self.report.content += (
                f" Recovery: {result.recoveries} fall(s) searched past in "
                f"{result.recovery_simulations} simulations of sampled balance targets."
            )
        self.messages.info(f"Tracking `{self.sandbox.relative(path)}` in physics.", client)
        return result
