"""The balance controller's law, stateless: joint PD (E1–E2) plus balance through the momentum
Jacobian (E3–E29), with the tunable stance-foot compensation (E30–E32).

`balance_torque(model, data, rig, target)` reads the simulation's current state (`data` after
`mj_forward`) and one reference frame, and returns what to apply: joint torques for the motors and,
per stance foot, the artificial torque (world axes, N·m) that cancels part of the balance torque
reaching that foot. It keeps nothing between calls; the `BalanceRig` holds only the model's
addresses, the gains and the foot model, fixed for a run. The simulation loop (`tracker.Tracker`)
samples the reference, applies the result and steps the physics.

1. joint PD: τ_pd = k_s e + k_d ω_d (`pd.pd_torques` for balls, `pd.hinge_pd_torques` for hinges,
   with ω_a = 0): the −k_d ω_a term is the joint damping, which MuJoCo integrates implicitly
   (the caller sets `dof_damping` = k_d and switches the passive springs off); a loaded foot's ankle
   targets the shin's world tilt (`stance_ankle`) where the reference foot stands about flat;
2. stance feet = feet touching the floor (`foot_contacts`, or the caller's reading of them: the
   tracker bridges contacts that vanish for a step, `contact_memory`); their normal forces weight
   the balance torques of each foot-rooted Jacobian (`momentum.momentum_jacobian`; double support
   blends the two roots, each foot's share of the virtual force acting about the feet's
   load-weighted centre, so that the legs do not squeeze the feet apart; flight has no balance
   torque);
3. virtual force/torque at the COM (`virtual.py`) → τ_eq = Jᵀ w;
4. the balance torque that reaches each stance foot is split at its support polygon (`support.py`):
   the part its contacts carry with the foot's share of the virtual force's vertical part (at most
   its measured normal force) is left to them, the excess is partly cancelled by an external torque
   on that foot, the artificial torque, and what remains of it is taken off the ankle (it would tip
   the foot); if the cancelled fraction is below `tolerance` the balance torques are switched off;
5. feet that the reference has on the floor but that carry less than their share are pressed down
   (`double_support.py`), and those of them still carrying little load are held from sliding
   (`planting.py`).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.body_tree import in_subtree, leg_dofs
from eigengait.control.balance.double_support import load_shares, pressing_force
from eigengait.control.balance.foot import FootModel, compensation
from eigengait.control.balance.momentum import (
    centroidal_inertia,
    centroidal_momentum_matrix,
    momentum_jacobian,
)
from eigengait.control.balance.pd import hinge_pd_torques, pd_torques
from eigengait.control.balance.planting import planting_torque
from eigengait.control.balance.stance_ankle import (
    flatness,
    heading_turn,
    levelled,
    stance_ankle_targets,
)
from eigengait.control.balance.support import carried_torque
from eigengait.control.balance.virtual import (
    VirtualGains,
    friction_bounded,
    virtual_force,
    virtual_torque,
)
from eigengait.geometry import quat_mul, quat_to_mat
from eigengait.sim.feet import sole_up
from eigengait.sim.world import FLOOR, GRAVITY, World


@dataclass(frozen=True)
class BalanceRig:
    """What the law needs to know about one world, fixed for a run: addresses in MuJoCo's arrays,
    the PD gains k_s (N·m/rad) and k_d (N·m·s/rad) per dof (nv), the virtual-wrench gains, the foot
    model and the tolerance."""

    root_body: int
    root_qpos: int  # first qpos entry of the free root (position, then quaternion)
    root_dofs: np.ndarray  # the free root's 6 dofs
    joint_dofs: np.ndarray  # the internal (motor) dofs, in motor order
    ball_qpos: np.ndarray  # (n_ball, 4)
    ball_dof: np.ndarray  # (n_ball, 3)
    hinge_qpos: np.ndarray
    hinge_dof: np.ndarray
    foot_bodies: dict[str, int]
    # every body that touches as a foot (the foot body and any below it, as toes) -> its foot
    foot_of_body: dict[int, str]
    foot_spheres: dict[str, list[int]]
    foot_dofs: dict[str, list[int]]  # internal dofs of each foot's body
    # qpos address of the ball joint turning each foot (feet on other joints: absent)
    foot_ball_qpos: dict[str, int]
    # internal dofs between the root body and each foot body (the foot's included)
    leg_dofs: dict[str, list[int]]
    # world up in each foot body's frame in the relax pose (qpos0)
    foot_rest_up: dict[str, np.ndarray]
    floor: int  # floor geom id
    mass: float  # kg
    k_s: np.ndarray
    k_d: np.ndarray
    foot: FootModel
    virtual: VirtualGains
    tolerance: float = 0.0


@dataclass(frozen=True)
class BalanceCommand:
    """One control step's output: torques (nv, N·m; the motors take `torque[rig.joint_dofs]`), the
    artificial torque (world, N·m) to put on each stance foot's body (foot name → (3,)), their total
    magnitude (N·m) and whether the character is in flight."""

    torque: np.ndarray
    foot_torques: dict[str, np.ndarray]
    artificial: float
    airborne: bool  # no foot touches the floor


def joint_layout(model: mujoco.MjModel, joints: list[int]) -> dict[str, np.ndarray]:
    """Ball and hinge joints among `joints`, with their qpos and dof addresses (the rig's
    ball_/hinge_ fields)."""
    ball = [j for j in joints if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_BALL)]
    hinge = [j for j in joints if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE)]
    return {
        "ball": ball,
        "hinge": hinge,
        "ball_qpos": np.array([model.jnt_qposadr[j] + np.arange(4) for j in ball], int).reshape(
            -1, 4
        ),
        "ball_dof": np.array([model.jnt_dofadr[j] + np.arange(3) for j in ball], int).reshape(
            -1, 3
        ),
        "hinge_qpos": np.array([model.jnt_qposadr[j] for j in hinge], int),
        "hinge_dof": np.array([model.jnt_dofadr[j] for j in hinge], int),
    }


def joint_gains(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    ball: list[int],
    hinge: list[int],
    named_gains: dict,
    damping_time: float,
    stiffness_scale: float,
    damping_ratio: float,
) -> tuple[np.ndarray, np.ndarray]:
    """PD gains per dof (nv): a joint whose name ends with a key of `named_gains` gets that k_s and
    k_d = damping_time × k_s; any other joint k_s = stiffness_scale × m g l and k_d = 2 ζ
    √(k_s m l²), with m the mass and l the COM distance of the joint's subtree (positions from
    `data`)."""
    k_s, k_d = np.zeros(model.nv), np.zeros(model.nv)
    for j in ball + hinge:
        n = 3 if j in ball else 1
        dofs = model.jnt_dofadr[j] + np.arange(n)
        name = model.joint(j).name
        named = [v for k, v in named_gains.items() if name.endswith(k)]
        if named:
            k_s[dofs] = named[0]
            k_d[dofs] = damping_time * named[0]
            continue
        mass, arm = _subtree_mass_and_arm(model, data, int(model.jnt_bodyid[j]))
        kp = stiffness_scale * mass * GRAVITY * arm
        k_s[dofs] = kp
        k_d[dofs] = 2.0 * damping_ratio * np.sqrt(kp * mass * arm * arm)
    return k_s, k_d


def _subtree_mass_and_arm(
    model: mujoco.MjModel, data: mujoco.MjData, body: int
) -> tuple[float, float]:
    ids = [b for b in range(body, model.nbody) if in_subtree(model, b, body)]
    mass = model.body_mass[ids]
    com = (mass[:, None] * data.xipos[ids]).sum(0) / mass.sum()
    return float(mass.sum()), max(
        float(np.linalg.norm(com - data.xanchor[model.body_jntadr[body]])), 0.05
    )


def balance_rig(
    world: World,
    model: mujoco.MjModel,
    k_s: np.ndarray,
    k_d: np.ndarray,
    foot: FootModel,
    virtual: VirtualGains,
    tolerance: float = 0.0,
) -> BalanceRig:
    """The rig of `world`'s character on `model` (the world's model or a copy of it) with the given
    gains."""
    joints = joint_layout(model, world.internal_qpos_joints)
    root_joint = int(model.body_jntadr[world.root_body])
    joint_dofs = np.asarray(world.internal_qvel)
    foot_bodies = {f: int(model.geom_bodyid[g[0]]) for f, g in world.foot_spheres.items()}
    internal = set(joint_dofs)
    return BalanceRig(
        root_body=world.root_body,
        root_qpos=int(model.jnt_qposadr[root_joint]),
        root_dofs=int(model.jnt_dofadr[root_joint]) + np.arange(6),
        joint_dofs=joint_dofs,
        ball_qpos=joints["ball_qpos"],
        ball_dof=joints["ball_dof"],
        hinge_qpos=joints["hinge_qpos"],
        hinge_dof=joints["hinge_dof"],
        foot_bodies=foot_bodies,
        foot_of_body={
            b: f
            for f, foot in foot_bodies.items()
            for b in range(model.nbody)
            if in_subtree(model, b, foot)
        },
        foot_spheres=dict(world.foot_spheres),
        foot_dofs={
            f: [d for d in range(model.nv) if model.dof_bodyid[d] == b and d in internal]
            for f, b in foot_bodies.items()
        },
        leg_dofs={
            f: [d for d in dofs if d in internal]
            for f, dofs in leg_dofs(model, world.root_body, foot_bodies).items()
        },
        foot_rest_up={f: sole_up(world, f) for f in foot_bodies},
        foot_ball_qpos={
            f: int(model.jnt_qposadr[model.body_jntadr[b]])
            for f, b in foot_bodies.items()
            if model.body_jntnum[b] == 1
            and model.jnt_type[model.body_jntadr[b]] == mujoco.mjtJoint.mjJNT_BALL
        },
        floor=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, FLOOR),
        mass=float(model.body_subtreemass[world.root_body]),
        k_s=k_s,
        k_d=k_d,
        foot=foot,
        virtual=virtual,
        tolerance=tolerance,
    )


def foot_contacts(
    model: mujoco.MjModel, data: mujoco.MjData, rig: BalanceRig
) -> dict[str, np.ndarray]:
    """Per foot, its floor contacts that push (k, 4): world position (m) and normal force (N); a
    body below a foot (toes on their own joint, as dm_control's CMU humanoid's) touches as its
    foot."""
    found: dict[str, list] = {f: [] for f in rig.foot_bodies}
    wrench = np.zeros(6)
    body_to_foot = rig.foot_of_body
    for i in range(data.ncon):
        c = data.contact[i]
        if rig.floor not in (c.geom1, c.geom2):
            continue
        other = int(model.geom_bodyid[c.geom2 if c.geom1 == rig.floor else c.geom1])
        if other in body_to_foot:
            mujoco.mj_contactForce(model, data, i, wrench)
            if wrench[0] > 0.0:
                found[body_to_foot[other]].append([*c.pos, wrench[0]])
    return {f: np.array(rows).reshape(-1, 4) for f, rows in found.items()}


def normal_forces(contacts: dict[str, np.ndarray]) -> dict[str, float]:
    """Per foot, the total normal force (N) of its `foot_contacts`."""
    return {f: float(c[:, 3].sum()) for f, c in contacts.items()}


def stance_forces(model: mujoco.MjModel, data: mujoco.MjData, rig: BalanceRig) -> dict[str, float]:
    """Normal contact force (N) between the floor and each foot body."""
    return normal_forces(foot_contacts(model, data, rig))


def pd_torque(data: mujoco.MjData, rig: BalanceRig, target: dict[str, np.ndarray]) -> np.ndarray:
    """Joint PD torques (nv, N·m) toward the target's qpos and qvel; the −k_d ω_a term is left to
    the implicit joint damping, so the actual velocity enters as zero."""
    tau = np.zeros(len(rig.k_s))
    if len(rig.ball_qpos):
        dof = rig.ball_dof
        tau[dof] = pd_torques(
            data.qpos[rig.ball_qpos],
            target["qpos"][rig.ball_qpos],
            0.0,
            target["qvel"][dof],
            rig.k_s[dof],
            rig.k_d[dof],
        )
    if len(rig.hinge_qpos):
        dof, adr = rig.hinge_dof, rig.hinge_qpos
        tau[dof] = hinge_pd_torques(
            data.qpos[adr],
            target["qpos"][adr],
            0.0,
            target["qvel"][dof],
            rig.k_s[dof],
            rig.k_d[dof],
        )
    return tau


def pd_target(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    rig: BalanceRig,
    target: dict[str, np.ndarray],
    contacts: dict[str, np.ndarray],
) -> np.ndarray:
    """The PD's target qpos: the reference's, with the loaded feet's ankles tracking the shins'
    world orientation (`stance_ankle`; the reference's turned about the vertical to the character's
    heading) as far as the reference foot stands flat; the reference's own when it has no body
    orientations."""
    qpos = target["qpos"]
    if target.get("body_quat") is None or not rig.foot_ball_qpos:
        return qpos
    qpos = qpos.copy()
    feet = rig.foot_ball_qpos
    parents = {f: int(model.body_parentid[rig.foot_bodies[f]]) for f in feet}
    turn = heading_turn(target["body_quat"][rig.root_body], data.xquat[rig.root_body])
    normals = normal_forces(contacts)
    ankles = stance_ankle_targets(
        {f: model.body_quat[rig.foot_bodies[f]] for f in feet},
        {f: quat_mul(turn, target["body_quat"][p]) for f, p in parents.items()},
        {f: levelled(data.xquat[rig.foot_bodies[f]], rig.foot_rest_up[f]) for f in feet},
        {f: qpos[a : a + 4] for f, a in feet.items()},
        {f: normals[f] / (rig.mass * GRAVITY) for f in feet},
        {f: flatness(target["body_quat"][rig.foot_bodies[f]], rig.foot_rest_up[f]) for f in feet},
    )
    for f, adr in feet.items():
        qpos[adr : adr + 4] = ankles[f]
    return qpos


def equilibrium_torque(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    rig: BalanceRig,
    target: dict[str, np.ndarray],
    contacts: dict[str, np.ndarray],
) -> tuple[np.ndarray, dict[str, np.ndarray], float]:
    """τ_eq (nv), the artificial torque (world, N·m) per stance foot and their total magnitude; all
    zero in flight or when the cancelled fraction is below the tolerance. `contacts`:
    `foot_contacts`."""
    root = rig.root_body
    tau = np.zeros(model.nv)
    forces = normal_forces(contacts)
    stance = {f: n for f, n in forces.items() if n > 1e-6}
    if not stance:
        return tau, {}, 0.0
    total = sum(stance.values())
    points = {f: data.geom_xpos[rig.foot_spheres[f]][:, :2].mean(axis=0) for f in stance}
    support = np.mean(list(points.values()), axis=0)
    mujoco.mj_subtreeVel(model, data)
    com, com_vel, angmom = (
        data.subtree_com[root],
        data.subtree_linvel[root],
        data.subtree_angmom[root],
    )
    gains = rig.virtual
    force = virtual_force(
        com,
        com_vel,
        support,
        target["com"],
        target["com_vel"],
        target["support"],
        rig.mass,
        GRAVITY,
        gains,
        friction_bounded(target["com_acc"], rig.foot.friction, GRAVITY),
    )
    quat = data.qpos[rig.root_qpos + 3 : rig.root_qpos + 7]
    quat_ref = target["qpos"][rig.root_qpos + 3 : rig.root_qpos + 7]
    omega = quat_to_mat(quat) @ data.qvel[rig.root_dofs[3:]]
    omega_ref = quat_to_mat(quat_ref) @ target["qvel"][rig.root_dofs[3:]]
    torque = virtual_torque(
        quat,
        quat_ref,
        omega,
        omega_ref,
        angmom,
        target["angular_momentum"],
        gains,
        target["angular_momentum_rate"],
    )
    wrench = np.concatenate([torque, force])
    momentum = centroidal_momentum_matrix(model, data, root)
    inertia = centroidal_inertia(model, data, root)
    # each stance foot's chain carries its share of the wrench, the moment of its share of the force
    # taken about the feet's load-weighted centre rather than about that foot: without it the two
    # legs of a double stance each held the whole moment of their vertical load about their own
    # foot (±31 N·m of hip roll standing still), squeezed the feet apart through friction and
    # tipped the load onto one foot within 3 s at robustness 0
    centres = {f: contacts[f][:, :3].mean(axis=0) for f in stance}
    centre = sum(normal / total * centres[f] for f, normal in stance.items())
    for f, normal in stance.items():
        share = wrench.copy()
        share[:3] += np.cross(centres[f] - centre, force)
        jac = momentum_jacobian(
            model,
            data,
            root,
            rig.foot_bodies[f],
            rig.root_dofs,
            rig.joint_dofs,
            momentum=momentum,
            inertia=inertia,
        )
        tau[rig.joint_dofs] += normal / total * (jac.T @ share)
    artificial, ratios = {}, []
    jacr = np.zeros((3, model.nv))
    for f, normal in stance.items():
        body = rig.foot_bodies[f]
        mujoco.mj_jacBody(model, data, None, jacr, body)
        dofs = rig.foot_dofs[f]
        foot_torque = jacr[:, dofs] @ tau[dofs]
        # the foot carries what the support the balance asks of it can carry, not what its measured
        # force can: an ankle torque on a foot standing on one edge raises that edge's force, and a
        # carried torque that followed it ran away (the run's push-off: 1.4 to 8.7 kN in 7 ms)
        supported = min(normal, max(force[2], 0.0) * normal / total)
        excess = foot_torque - carried_torque(
            foot_torque, supported, data.xpos[body], contacts[f][:, :3]
        )
        artificial[f], ratio = compensation(excess, rig.foot)
        ratios.append(ratio)
        if dofs:  # the excess not cancelled would tip the foot: the ankle does not apply it
            left = excess + artificial[f]
            left[2] = 0.0
            tau[dofs] -= np.linalg.lstsq(jacr[:, dofs], left, rcond=None)[0]
    if min(ratios) < rig.tolerance:
        return np.zeros(model.nv), {}, 0.0
    magnitude = 0.0
    for torque_f in artificial.values():
        magnitude += float(np.linalg.norm(torque_f))
    return tau, artificial, magnitude


def balance_torque(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    rig: BalanceRig,
    target: dict[str, np.ndarray],
    contacts: dict[str, np.ndarray] | None = None,
) -> BalanceCommand:
    """The controller's output for the state in `data` (positions, velocities and contacts computed,
    as after `mj_forward`) and one reference frame `target` (qpos, qvel, com, com_vel, com_acc,
    angular_momentum, angular_momentum_rate, support; `reference.Reference` sampled at the current
    time); `contacts`: the feet's contacts as the caller reads them (default `foot_contacts`).
    Writes only MuJoCo's derived quantities (subtree velocities) into `data`."""
    if contacts is None:
        contacts = foot_contacts(model, data, rig)
    tau_pd = pd_torque(data, rig, {**target, "qpos": pd_target(model, data, rig, target, contacts)})
    tau_eq, foot_torques, artificial = equilibrium_torque(model, data, rig, target, contacts)
    airborne = not any(len(c) for c in contacts.values())
    return BalanceCommand(
        tau_pd
        + tau_eq
        + press_torque(model, data, rig, target, contacts)
        + plant_torque(model, data, rig, target, contacts),
        foot_torques,
        artificial,
        airborne,
    )


def press_torque(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    rig: BalanceRig,
    target: dict[str, np.ndarray],
    contacts: dict[str, np.ndarray],
) -> np.ndarray:
    """Leg torques (nv) pressing down the feet that carry less than their reference share
    (`double_support`); zero when the target has no foot heights."""
    tau = np.zeros(model.nv)
    if target.get("foot_height") is None:
        return tau
    feet = list(rig.foot_bodies)
    shares = load_shares(target["com"], target["foot_points"], target["foot_height"])
    jacp = np.zeros((3, model.nv))
    normals = normal_forces(contacts)
    load = max(rig.mass * GRAVITY, sum(normals.values()))
    for foot, share in zip(feet, shares):
        force = pressing_force(share, load, normals[foot])
        if force > 0.0:
            mujoco.mj_jacBody(model, data, jacp, None, rig.foot_bodies[foot])
            chain = rig.leg_dofs[foot]
            tau[chain] += jacp[2, chain] * -force
    return tau


def plant_torque(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    rig: BalanceRig,
    target: dict[str, np.ndarray],
    contacts: dict[str, np.ndarray],
) -> np.ndarray:
    """Leg torques (nv) stopping the slide of lightly loaded feet that the reference has down
    (`planting`); zero when the target has no foot transitions."""
    if target.get("foot_transition") is None:
        return np.zeros(model.nv)
    normals = normal_forces(contacts)
    return planting_torque(
        model,
        data,
        target["foot_transition"] > 0.5,
        target["foot_velocity"],
        normals,
        rig.foot_bodies,
        rig.foot_spheres,
        rig.leg_dofs,
        rig.mass,
        GRAVITY,
    )


def apply_foot_torques(data: mujoco.MjData, rig: BalanceRig, command: BalanceCommand) -> None:
    """Put the command's artificial torques on the feet (`xfrc_applied`, torque part); other feet
    get none."""
    data.xfrc_applied[list(set(rig.foot_bodies.values())), 3:] = 0.0
    for foot, torque in command.foot_torques.items():
        data.xfrc_applied[rig.foot_bodies[foot], 3:] = torque


__all__ = [
    "BalanceCommand",
    "BalanceRig",
    "apply_foot_torques",
    "balance_rig",
    "balance_torque",
    "equilibrium_torque",
    "foot_contacts",
    "joint_gains",
    "joint_layout",
    "pd_target",
    "plant_torque",
    "press_torque",
    "pd_torque",
    "stance_forces",
]
