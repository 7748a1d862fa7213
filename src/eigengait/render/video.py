"""Render a World's qpos sequence with MuJoCo's offscreen Renderer and write it as MP4 or GIF.

The camera is a free camera looking down at `elevation_deg` so the floor fills the background. By
default it is framed on the relax pose and follows the creature's centre of mass (COM) horizontally
at constant height; a fixed camera (`CameraView(follow=False)`) frames the whole trajectory instead,
so travel shows. Lighting: MuJoCo's headlight softened, and the world's overhead lights moved
horizontally with the COM so the creature's shadow falls under it wherever it goes. Videos are
resampled to exactly the requested frame rate and play in real time unless a speed is given
(`eigengait.motion.resample`); frames carry the simulated time and, on a floor, a disc under each
foot on the ground plus a foot box filled while it touches (`eigengait.render.contacts`). Distances
are in metres, angles in degrees, sizes in pixels. MP4 is H.264 (libx264, yuv420p: plays in browsers
and every player); GIF loops forever (GIF stores frame times in 10 ms steps, so 25 or 20 fps play
exactly).
"""

from __future__ import annotations

import copy
from collections.abc import Iterator
from contextlib import closing
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

from eigengait.body_tree import in_subtree
from eigengait.errors import UserInputError
from eigengait.outputs import replacing
from eigengait.render.offscreen import use_offscreen_gl
from eigengait.sim.world import World

VIDEO_SUFFIXES = (".mp4", ".gif")


@dataclass(frozen=True)
class CameraView:
    """Free-camera placement. MuJoCo azimuth: 90° looks along +y (side view); 135° sees a +x-facing
    creature from its front-right three-quarter. Elevations below −22.5° keep the horizon out of a
    4:3 or square frame. `distance_m=None` fits the creature in the frame so that it spans `fill` of
    the width or height. `follow=True` follows the COM; `False` is a fixed camera framing every pose
    of the trajectory."""

    azimuth_deg: float = 135.0
    elevation_deg: float = -25.0
    distance_m: float | None = None
    fill: float = 0.75
    follow: bool = True

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit forward, right and up vectors of the camera in the world."""
        az, el = np.deg2rad(self.azimuth_deg), np.deg2rad(self.elevation_deg)
        forward = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        right = np.cross(forward, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        return forward, right, np.cross(right, forward)


MAX_SIZE = 8192  # pixels per side of an offscreen image


def visual_model(world: World, width: int, height: int) -> mujoco.MjModel:
    """A copy of the world's model with an offscreen buffer of the requested size and softer
    lighting."""
    if not (16 <= width <= MAX_SIZE and 16 <= height <= MAX_SIZE) or width % 2 or height % 2:
        raise UserInputError(
            f"image size {width}×{height} is not usable",
            field="width/height",
            fix=f"use even sizes from 16 to {MAX_SIZE} pixels (H.264 needs even sizes)",
        )
    model = copy.deepcopy(world.model)
    model.vis.global_.offwidth = max(width, model.vis.global_.offwidth)
    model.vis.global_.offheight = max(height, model.vis.global_.offheight)
    model.vis.headlight.ambient[:] = 0.25
    model.vis.headlight.diffuse[:] = 0.3
    model.vis.headlight.specular[:] = 0.05
    model.vis.quality.shadowsize = 2048
    return model


def creature_geoms(model: mujoco.MjModel, root_body: int) -> np.ndarray:
    """Ids of the geoms on the creature's bodies (everything below `root_body`)."""
    return np.array(
        [g for g in range(model.ngeom) if in_subtree(model, int(model.geom_bodyid[g]), root_body)]
    )


def geom_corners(model: mujoco.MjModel, data: mujoco.MjData, geoms: np.ndarray) -> np.ndarray:
    """World corners (8·len(geoms) × 3, m) of each geom's bounding box at the pose in `data`."""
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    aabb = model.geom_aabb[geoms]
    local = aabb[:, None, :3] + signs[None] * aabb[:, None, 3:]
    rot = data.geom_xmat[geoms].reshape(-1, 3, 3)
    return (np.einsum("gij,gkj->gki", rot, local) + data.geom_xpos[geoms][:, None]).reshape(-1, 3)


def fit_camera(
    points: np.ndarray,
    view: CameraView,
    aspect: float,
    fovy_deg: float,
    centre: np.ndarray | None = None,
) -> tuple[np.ndarray, float]:
    """Look-at point (m) and distance (m) that frame the world points with the view's direction and
    fill.

    Without `centre` the camera aims at the middle of the points' image; with it, at `centre`'s
    image (the frame then widens to keep every point in view around it).
    """
    forward, right, up = view.axes()
    origin = points.mean(axis=0) if centre is None else centre
    rel = points - origin
    x, y, depth = rel @ right, rel @ up, rel @ forward
    if centre is None:
        shift_x, shift_y = (x.max() + x.min()) / 2, (y.max() + y.min()) / 2
    else:
        shift_x = shift_y = 0.0
    half_x, half_y = np.abs(x - shift_x).max(), np.abs(y - shift_y).max()
    tan_half = np.tan(np.deg2rad(fovy_deg) / 2)
    half_span = max(half_y / tan_half, half_x / (tan_half * aspect))
    return origin + right * shift_x + up * shift_y, half_span / view.fill - depth.min()


class FrameRenderer:
    """Offscreen renderer of a world's poses; use as a context manager (it owns a GL context).

    The camera is fitted to the relax pose (refit with `fit`, or `fit_trajectory` for a fixed
    camera) and, if the view follows, moves with the COM horizontally at constant height. The
    world's lights always move with the COM.
    """

    def __init__(
        self, world: World, width: int = 640, height: int = 480, view: CameraView = CameraView()
    ):
        self.world = world
        self.model = visual_model(world, width, height)
        self.data = mujoco.MjData(self.model)
        self.pose_data = mujoco.MjData(self.model)  # for poses measured but not drawn
        use_offscreen_gl()
        self.renderer = mujoco.Renderer(self.model, height=height, width=width)
        self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = True
        self.geoms = creature_geoms(self.model, world.root_body)
        self.world_lights = np.flatnonzero(self.model.light_bodyid == 0)
        self.view = view
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.azimuth = view.azimuth_deg
        self.camera.elevation = view.elevation_deg
        mujoco.mj_forward(self.model, self.data)
        self.relax_com = self.data.subtree_com[world.root_body].copy()
        self.fit(geom_corners(self.model, self.data, self.geoms))

    def fit(self, points: np.ndarray, centre: np.ndarray | None = None) -> None:
        """Aim the camera so the world points (m) fill the view (see `fit_camera`)."""
        width, height = self.renderer.width, self.renderer.height
        lookat, distance = fit_camera(
            points, self.view, width / height, self.model.vis.global_.fovy, centre
        )
        self.camera.distance = self.view.distance_m or distance
        self.height_m = float(lookat[2])
        self.lookat_offset = lookat[:2] - self.relax_com[:2]
        self.camera.lookat[:] = lookat

    def fit_trajectory(self, qpos: np.ndarray, samples: int = 40) -> None:
        """Frame up to `samples` evenly spread poses of a trajectory (T × nq) at once, for a fixed
        camera."""
        picks = qpos[np.unique(np.linspace(0, len(qpos) - 1, samples).astype(int))]
        self.fit(np.vstack([self._corners(q) for q in picks]))

    def _corners(self, qpos: np.ndarray) -> np.ndarray:
        self.pose_data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.pose_data)
        return geom_corners(self.model, self.pose_data, self.geoms)

    def __enter__(self) -> "FrameRenderer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self.renderer.close()

    def render(
        self, qpos: np.ndarray, solid_rgba: tuple | None = None, contact_marks: bool = False
    ) -> np.ndarray:
        """RGB image (height × width × 3, uint8) of the pose (arguments: `update_scene`)."""
        self.update_scene(qpos, solid_rgba, contact_marks)
        return self.renderer.render()

    def update_scene(
        self, qpos: np.ndarray, solid_rgba: tuple | None = None, contact_marks: bool = False
    ) -> None:
        """Build the scene of the pose; `add_marker` may add to it before `self.renderer.render()`
        draws it.

        `solid_rgba` recolours the creature in one flat colour. `contact_marks` draws a disc on the
        floor under each foot touching it, in the foot's colour.
        """
        self.data.qpos[:] = qpos
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)
        com = self.data.subtree_com[self.world.root_body]
        self.data.light_xpos[self.world_lights, :2] = (
            self.model.light_pos[self.world_lights, :2] + com[:2]
        )
        if self.view.follow:
            self.camera.lookat[:] = [*(com[:2] + self.lookat_offset), self.height_m]
        self.renderer.update_scene(self.data, self.camera)
        if solid_rgba is not None:
            self._recolour(solid_rgba)
        if contact_marks:
            self._add_contact_marks()

    def add_marker(
        self, kind: int, size: tuple, pos: np.ndarray, rgba: tuple, mat: np.ndarray = np.eye(3)
    ) -> None:
        """Add one decorative geom (an `mjtGeom` type; size and position in m) to the scene being
        drawn."""
        scene = self.renderer.scene
        if scene.ngeom >= scene.maxgeom:
            return
        mujoco.mjv_initGeom(
            scene.geoms[scene.ngeom],
            kind,
            np.asarray(size, float),
            np.asarray(pos, float),
            np.asarray(mat, float).ravel(),
            np.asarray(rgba, np.float32),
        )
        scene.ngeom += 1

    def _add_contact_marks(self) -> None:
        from eigengait.render.contacts import contact_points, foot_colour

        for index, point in enumerate(contact_points(self.world, self.data).values()):
            if point is not None:
                self.add_marker(
                    mujoco.mjtGeom.mjGEOM_CYLINDER,
                    (0.07, 0.002, 0),
                    [point[0], point[1], 0.002],
                    (*foot_colour(index), 0.85),
                )

    def _recolour(self, rgba: tuple) -> None:
        scene = self.renderer.scene
        for i in range(scene.ngeom):
            geom = scene.geoms[i]
            if geom.objtype == mujoco.mjtObj.mjOBJ_GEOM and geom.objid in self.geoms:
                geom.rgba[:] = rgba


def iter_frames(
    world: World,
    qpos: np.ndarray,
    width: int = 640,
    height: int = 480,
    view: CameraView = CameraView(),
    progress: bool = False,
    times: np.ndarray | None = None,
) -> Iterator[np.ndarray]:
    """Frames of a qpos sequence (T × nq), one RGB uint8 image at a time, with a progress bar if
    asked.

    With `times` (s, one per pose) every frame is annotated: the time, and on a floor the feet on
    the ground.
    """
    from eigengait.render.contacts import contact_points, foot_colour, has_floor
    from eigengait.render.overlay import annotate

    marks = times is not None and has_floor(world) and bool(world.foot_spheres)
    with FrameRenderer(world, width, height, view) as renderer, _progress(progress) as bar:
        if not view.follow:
            renderer.fit_trajectory(qpos)
        task = bar.add_task("rendering", total=len(qpos))
        for i, q in enumerate(qpos):
            frame = renderer.render(q, contact_marks=marks)
            if times is not None:
                feet = (
                    [
                        (name, point is not None, foot_colour(k))
                        for k, (name, point) in enumerate(
                            contact_points(world, renderer.data).items()
                        )
                    ]
                    if marks
                    else []
                )
                frame = annotate(frame, float(times[i]), feet)
            yield frame
            bar.advance(task)


def _progress(visible: bool) -> Progress:
    from rich.console import Console

    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total} frames"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        disable=not visible,
        transient=True,
    )


def video_path(path: str | Path) -> Path:
    """The path, if its suffix names a format we write (.mp4 or .gif)."""
    path = Path(path)
    if path.suffix.lower() not in VIDEO_SUFFIXES:
        raise UserInputError(
            f"cannot write video format '{path.suffix}'",
            file=path,
            fix="name the file .mp4 or .gif",
        )
    return path


def write_video(frames: Iterator[np.ndarray], path: str | Path, fps: float) -> int:
    """Write frames to an .mp4 (H.264, yuv420p) or .gif (looping) chosen by suffix; returns the
    frame count.

    The video is written under a temporary name and renamed when complete
    (`eigengait.outputs.replacing`)."""
    path = video_path(path)
    count = 0
    # closed on errors too
    with replacing(path) as temporary, closing(_video_writer(temporary, fps)) as writer:
        for frame in frames:
            writer.append_data(frame)
            count += 1
    return count


def _video_writer(path: Path, fps: float):
    import imageio.v2 as imageio

    if path.suffix.lower() == ".mp4":
        return imageio.get_writer(
            path,
            format="FFMPEG",
            fps=fps,
            codec="libx264",
            pixelformat="yuv420p",
            quality=8,
            macro_block_size=2,
            ffmpeg_log_level="error",
        )
    return imageio.get_writer(path, format="GIF", mode="I", duration=1000.0 / fps, loop=0)


def render_video(
    world: World,
    qpos: np.ndarray,
    source_fps: float,
    path: str | Path,
    width: int = 640,
    height: int = 480,
    view: CameraView = CameraView(),
    progress: bool = False,
    fps: float = 30.0,
    speed: float = 1.0,
    annotate: bool = True,
) -> int:
    """Render a qpos sequence (T × nq) recorded at `source_fps` to a video file at exactly `fps`
    frames per second, showing `speed` simulated seconds per second of video (1 = real time);
    returns the frame count.

    `annotate` stamps each frame with its simulated time and marks the feet on the ground (see
    `iter_frames`).
    """
    from eigengait.motion.resample import at_frame_rate, frame_times

    video_path(path)
    frames = at_frame_rate(world.model, qpos, source_fps, fps, speed)
    times = frame_times((len(qpos) - 1) / source_fps, fps, speed) if annotate else None
    return write_video(iter_frames(world, frames, width, height, view, progress, times), path, fps)
