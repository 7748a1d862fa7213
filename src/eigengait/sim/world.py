"""Build the simulated world of a character.

* Springs rest at the relax pose; damping = `damping_ratio` × stiffness (0.1 s by default).
  Isotropic joints use MuJoCo's native `stiffness`/`damping`; anisotropic ball joints (kx, ky, kz in
  the joint frame) use three passive actuators whose bias is −k_i·θ_i − d_i·θ̇_i, θ_i the
  rotation-vector component about joint axis i.
* One motor per internal degree of freedom (`ctrl` = torque in N·m about that dof's axis, joint
  frame), in qvel order: this is where controllers put their torques, within `motor_limits`
  (stiffness × `strength`, if the character states one). With an `activation_time` τ (WorldOptions),
  each motor's torque follows its command through a first-order lag, as a muscle's force follows its
  excitation (MuJoCo's exact filter, its state in `data.act`): a step in the command reaches 63 % of
  its size after τ seconds. Without it, torques act at once.
* Every body collides with the ground (not with itself); feet get toe and heel contact spheres from
  their sites. `contact="feet"` lets only the spheres collide, and `set_stance_foot` restricts that
  to one foot (the thesis's filtering).
* Sensors: the COM and COM velocity of the whole creature, and the world position of every foot's
  toe and heel (`World.view` reads them, and the recorded states, by name).
* Everything added is named with a reserved prefix (`eigengait:`, `motor:`, `spring:`, `contact:`,
  `pos:`), which `character/scene.py` forbids in models, so it cannot clash with the model's own
  names.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Literal

import mujoco
import numpy as np

from eigengait.body_tree import in_subtree
from eigengait.character.loader import Character
from eigengait.character.relax import DEFAULT_POSE, posed_spec
from eigengait.character.scene import compile_spec
from eigengait.errors import UserInputError
from eigengait.sim.recording import RolloutView
from eigengait.sim.root import RootLayout, root_layout

BODY_GROUP, FOOT_GROUP, FLOOR_AFFINITY = 1, 2, 3
FLOOR = "eigengait:floor"
GRAVITY = 9.81
MAX_ACTIVATION_TIME = 1.0  # s


@dataclass(frozen=True)
class WorldOptions:
    """gravity on/off; timestep in s; which geoms touch the ground; place the feet on the ground;
    the motors' activation time constant in s (None: torques act at once)."""

    gravity: bool = True
    timestep: float = 0.0005
    contact: Literal["all", "feet", "none"] = "all"
    floor: bool = True
    activation_time: float | None = None

    def __post_init__(self):
        if not 0 < self.timestep <= 0.05:
            raise UserInputError(
                f"timestep {self.timestep} s is out of range",
                field="timestep",
                fix="use a step between 1e-5 and 0.05 s (default 0.0005)",
            )
        if self.activation_time is not None and not 0 < self.activation_time <= MAX_ACTIVATION_TIME:
            raise UserInputError(
                f"activation time {self.activation_time} s is out of range",
                field="activation_time",
                fix=(
                    f"use a time constant above 0 and at most {MAX_ACTIVATION_TIME} s (muscles: "
                    "0.01-0.05 s), or none"
                ),
            )


@dataclass
class World:
    """A compiled world and the index maps controllers and objectives need."""

    character: Character
    pose: str | dict
    options: WorldOptions
    model: mujoco.MjModel
    spec: mujoco.MjSpec = field(repr=False)
    root_body: int = 0
    internal_qvel: np.ndarray = None  # qvel indices of internal dofs, model order
    internal_qpos_joints: list[int] = None  # joint ids of internal joints, model order
    foot_spheres: dict[str, list[int]] = field(default_factory=dict)  # foot -> contact geom ids
    # "<foot>_toe"/"<foot>_heel" -> sensordata adr
    foot_sensor: dict[str, int] = field(default_factory=dict)
    root: RootLayout = None  # where the root's coordinates are in qpos/qvel

    @property
    def nmotor(self) -> int:
        return len(self.internal_qvel)

    @property
    def com_sensor(self) -> int:
        return 0

    @property
    def comvel_sensor(self) -> int:
        return 3

    @cached_property
    def view(self) -> RolloutView:
        """Named reads of this world's recorded states and sensordata (`sim/recording.py`)."""
        return RolloutView.of(self)

    def applied_motor_torques(self, states: np.ndarray, commands: np.ndarray) -> np.ndarray:
        """Torques (N·m, … × nmotor) the motors applied: their filtered activations, read from
        full-physics states (… × state size, after each step) when the motors have an activation
        time, else the commands."""
        if not self.model.na:
            return commands
        return self.view.act(states)[..., : self.nmotor]

    @property
    def dof_stiffness(self) -> np.ndarray:
        """Spring stiffness (N·m/rad) of each internal dof, in motor order."""
        return np.concatenate(
            [np.atleast_1d(self.character.stiffness[j]) for j in self.character.joints]
        )

    @property
    def motor_limits(self) -> np.ndarray:
        """Largest torque (N·m) of each motor: its dof's stiffness × the character's `strength`
        (rad), so a joint is as strong as its spring at that deflection (light, soft limbs cannot be
        driven like the legs); unlimited (inf) when the character states no strength."""
        strength = self.character.meta.strength
        return np.full(self.nmotor, np.inf) if strength is None else strength * self.dof_stiffness

    def foot_radius(self, foot: str) -> float:
        """Radius (m) of the foot's contact spheres."""
        return float(self.model.geom_size[self.foot_spheres[foot][0], 0])

    def foot_point_sensors(self, foot: str) -> list[int]:
        """sensordata addresses of the world positions of the foot's contact-sphere centres
        (toe, then heel)."""
        points = self.character.feet[foot]
        return [self.foot_sensor[site] for site in (points.toe, points.heel) if site]

    def new_data(self) -> mujoco.MjData:
        data = mujoco.MjData(self.model)
        mujoco.mj_forward(self.model, data)
        return data

    def mjcf(self) -> str:
        """The model as MJCF text, exactly as compiled and simulated."""
        return self.spec.to_xml()

    def mass(self) -> float:
        return float(self.model.body_subtreemass[self.root_body])

    @property
    def standing_com_height(self) -> float:
        """Height (m) of the whole creature's COM standing at the relax pose."""
        return float(self.new_data().subtree_com[self.root_body][2])

    def set_stance_foot(self, foot: str | None) -> None:
        """Thesis filtering: only `foot`'s spheres collide (None: all feet). Needs
        contact='feet'."""
        for name, geoms in self.foot_spheres.items():
            on = foot is None or name == foot
            self.model.geom_contype[geoms] = FOOT_GROUP if on else 0


def _coefficients(linear: float) -> np.ndarray:
    """MuJoCo's joint stiffness/damping coefficient vector with only the linear term set."""
    return np.array([linear, 0.0, 0.0])


def _add_springs(spec: mujoco.MjSpec, character: Character) -> None:
    ratio = character.meta.damping_ratio
    for name in character.joints:
        joint = spec.joint(name)
        k = character.stiffness[name]
        # as written in the MJCF (the spec is unedited so far)
        user_damping = float(np.atleast_1d(joint.damping)[0])
        if np.ptp(k) == 0:
            joint.stiffness = _coefficients(k[0])
            joint.damping = _coefficients(user_damping if user_damping > 0 else ratio * k[0])
            continue
        joint.stiffness = _coefficients(0.0)
        joint.damping = _coefficients(0.0)
        for axis in range(3):
            act = spec.add_actuator()
            act.name = f"spring:{name}:{'xyz'[axis]}"
            act.target = name
            act.trntype = mujoco.mjtTrn.mjTRN_JOINT
            act.gear = np.eye(6)[axis]
            act.gainprm[0] = 0.0
            act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
            act.biasprm[:3] = [0.0, -k[axis], -ratio * k[axis]]
            act.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE


def _add_motors(spec: mujoco.MjSpec, character: Character, tau: float | None) -> None:
    for name in character.joints:
        for axis in range(character.joint_dofs[name]):
            act = spec.add_actuator()
            act.name = (
                f"motor:{name}:{'xyz'[axis]}"
                if character.joint_dofs[name] == 3
                else f"motor:{name}"
            )
            act.target = name
            act.trntype = mujoco.mjtTrn.mjTRN_JOINT
            act.gear = np.eye(6)[axis] if character.joint_dofs[name] == 3 else np.eye(6)[0]
            act.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
            if tau is not None:
                act.dyntype = mujoco.mjtDyn.mjDYN_FILTEREXACT
                act.dynprm[0] = tau
                # the force of a step uses the activation at its end, as recorded
                act.actearly = True


def _set_contacts(spec: mujoco.MjSpec, character: Character, contact: str) -> None:
    for geom in spec.geoms:
        geom.contype = BODY_GROUP if contact == "all" else 0
        geom.conaffinity = 0
    for foot, f in character.feet.items():
        for point in filter(None, (f.toe, f.heel)):
            site = spec.site(point)
            body = site.parent
            g = body.add_geom()
            g.name = f"contact:{point}"
            g.type = mujoco.mjtGeom.mjGEOM_SPHERE
            g.size = [float(site.size[0]), 0, 0]
            g.pos = site.pos
            g.contype = 0 if contact == "none" else FOOT_GROUP
            g.conaffinity = 0
            g.density = 0.0
            g.rgba = [0.9, 0.3, 0.2, 1]


def _hide_model_planes(spec: mujoco.MjSpec) -> None:
    """A user's model may bring its own ground planes: they make no contacts (`_set_contacts`) but
    would be drawn in the plane of eigengait's floor and flicker through it, so they are made
    invisible."""
    for geom in spec.worldbody.geoms:
        if geom.type == mujoco.mjtGeom.mjGEOM_PLANE:
            geom.material = ""
            geom.rgba = [0.0, 0.0, 0.0, 0.0]


def _add_floor_and_sensors(
    spec: mujoco.MjSpec, character: Character, root_name: str, floor: bool
) -> None:
    if floor:
        _hide_model_planes(spec)
        tex = spec.add_texture(
            name="eigengait:grid",
            type=mujoco.mjtTexture.mjTEXTURE_2D,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
            width=256,
            height=256,
            rgb1=[0.82, 0.84, 0.86],
            rgb2=[0.70, 0.72, 0.75],
        )
        mat = spec.add_material(name=FLOOR)
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex.name
        mat.texrepeat = [1, 1]
        mat.texuniform = True
        g = spec.worldbody.add_geom(
            name=FLOOR, type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05], material=FLOOR
        )
        g.contype, g.conaffinity = 0, FLOOR_AFFINITY
        g.friction = [1.0, 0.005, 0.0001]
    spec.worldbody.add_light(
        pos=[0, 0, 6],
        dir=[0, 0, -1],
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        diffuse=[0.7, 0.7, 0.7],
    )
    cam = spec.worldbody.add_camera(
        name="eigengait:side", pos=[0.5, -4.0, 1.3], xyaxes=[1, 0, 0, 0, 0.3, 1]
    )
    cam.mode = mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM
    for kind in (mujoco.mjtSensor.mjSENS_SUBTREECOM, mujoco.mjtSensor.mjSENS_SUBTREELINVEL):
        s = spec.add_sensor(type=kind, objtype=mujoco.mjtObj.mjOBJ_BODY, objname=root_name)
        s.name = (
            "eigengait:com"
            if kind == mujoco.mjtSensor.mjSENS_SUBTREECOM
            else "eigengait:com_velocity"
        )
    for f in character.feet.values():
        for point in filter(None, (f.toe, f.heel)):
            spec.add_sensor(
                name=f"pos:{point}",
                type=mujoco.mjtSensor.mjSENS_FRAMEPOS,
                objtype=mujoco.mjtObj.mjOBJ_SITE,
                objname=point,
            )


def _lowest_point(model: mujoco.MjModel, data: mujoco.MjData, geoms: list[int]) -> float:
    """Lowest world z (m) over the given geoms (boxes by their corners, others by bounding
    sphere)."""
    low = np.inf
    for g in geoms:
        centre, rot, size = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
            corners = (
                np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
                * size
            )
            low = min(low, float((centre + corners @ rot.T)[:, 2].min()))
        elif model.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE:
            low = min(low, float(centre[2] - size[0]))
        elif model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE:
            low = min(low, float(centre[2] - model.geom_rbound[g]))
    return low


def build_world(
    character: Character, pose: str | dict = DEFAULT_POSE, options: WorldOptions = WorldOptions()
) -> World:
    """Compile the character at `pose` into a world, standing with its lowest point on the floor."""
    spec = posed_spec(character, pose)
    root = spec.body(character.scene.root)
    spec.option.timestep = options.timestep
    spec.option.gravity = [0, 0, -GRAVITY if options.gravity else 0.0]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    # motors first: ctrl[:nmotor] are the joint torques
    _add_motors(spec, character, options.activation_time)
    _add_springs(spec, character)
    _set_contacts(spec, character, options.contact)
    _add_floor_and_sensors(spec, character, root.name, options.floor)
    model = compile_spec(spec)

    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    sphere_ids = [i for i in range(model.ngeom) if model.geom(i).name.startswith("contact:")]
    root_id = model.body(root.name).id
    body_geoms = [
        i for i in range(model.ngeom) if in_subtree(model, int(model.geom_bodyid[i]), root_id)
    ]
    low = _lowest_point(model, data, sphere_ids or body_geoms)
    root.pos = np.asarray(root.pos) - [0, 0, low]
    model = compile_spec(spec)

    internal_joints = [model.joint(j).id for j in character.joints]
    qvel = np.concatenate(
        [
            model.jnt_dofadr[j] + np.arange(character.joint_dofs[n])
            for j, n in zip(internal_joints, character.joints)
        ]
    ).astype(int)
    feet = {
        foot: [model.geom(f"contact:{p}").id for p in filter(None, (f.toe, f.heel))]
        for foot, f in character.feet.items()
    }
    sensors = {
        model.sensor(i).name[len("pos:") :]: int(model.sensor_adr[i])
        for i in range(model.nsensor)
        if model.sensor(i).name.startswith("pos:")
    }
    return World(
        character=character,
        pose=pose,
        options=options,
        model=model,
        spec=spec,
        root_body=root_id,
        internal_qvel=qvel,
        internal_qpos_joints=internal_joints,
        foot_spheres=feet,
        foot_sensor=sensors,
        root=root_layout(model, root_id),
    )
