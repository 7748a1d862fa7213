"""Mode palette: one tile per vibration mode, its two extremes as translucent ghosts over the relax
pose.

Each tile shows the relax pose solid light grey, the pose at −A in orange and at +A in teal, where A
turns the mode's most-moving joint by `max_rotation_deg` (so every mode is equally visible; the
animation default follows the equal-energy rule instead, see `eigengait.modal.shape_kinematics`).
The extremes are rendered separately and blended onto the relax image, the nearer one on top where
they overlap (no depth fight between coincident surfaces); each body's ghost is the more opaque the
more that body moves (travel or own joint rotation), so the moving parts stand out and still parts
stay grey.
A dark arrow on the floor points where the character faces (+x); in the ground phase a red ball
marks the pinned toe. Tiles run left to right, top to bottom, in mode order (mode 1 = lowest
frequency), each labelled with its number and frequency in Hz. Sizes are in pixels.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from eigengait.body_tree import body_joints
from eigengait.errors import UserInputError
from eigengait.outputs import replacing
from eigengait.modal.modeset import ModeSet
from eigengait.modal.shape_kinematics import (
    DEFAULT_MAX_ROTATION_DEG,
    displaced_qpos,
    peak_rotation_amplitudes,
)
from eigengait.render.video import CameraView, FrameRenderer, creature_geoms, geom_corners
from eigengait.sim.world import World

MINUS_RGBA = (1.0, 0.5, 0.05, 1.0)
PLUS_RGBA = (0.0, 0.62, 0.55, 1.0)
SOLID_RGBA = (0.86, 0.86, 0.88, 1.0)
# for a geom that does not move … one that moves fully (see _ghost_opacity)
GHOST_OPACITY = (0.0, 0.8)
MOVING_TRAVEL = 0.08  # fraction of the creature's height: travel that counts as fully moving
MOVING_ROTATION = 0.5  # fraction of the peak joint rotation that counts as fully moving
ARROW_RGBA = (0.15, 0.15, 0.15, 1.0)
PINNED_RGBA = (0.85, 0.05, 0.05, 1.0)
BACKGROUND = 255
PALETTE_VIEW = CameraView(azimuth_deg=140.0, elevation_deg=-25.0, fill=0.85)


@dataclass(frozen=True)
class PaletteLayout:
    """Pixel geometry: a title band, then rows of (label band + tile)."""

    count: int
    columns: int
    tile_width: int = 240
    tile_height: int = 240
    label_height: int = 30
    title_height: int = 78

    @property
    def rows(self) -> int:
        return -(-self.count // self.columns)

    @property
    def cell_height(self) -> int:
        return self.label_height + self.tile_height

    @property
    def size(self) -> tuple[int, int]:
        """(height, width) of the whole image."""
        return self.title_height + self.rows * self.cell_height, self.columns * self.tile_width

    def tile_origin(self, index: int) -> tuple[int, int]:
        """(row, column) pixel of the top-left corner of tile `index` (0-based), below its label."""
        row, col = divmod(index, self.columns)
        return self.title_height + row * self.cell_height + self.label_height, col * self.tile_width


def palette_layout(count: int, columns: int | None = None, tile_px: int = 240) -> PaletteLayout:
    """Layout for `count` tiles; by default about 1.2 times as many columns as rows."""
    columns = columns or max(1, min(count, int(np.ceil(np.sqrt(count * 1.2)))))
    return PaletteLayout(count=count, columns=columns, tile_width=tile_px, tile_height=tile_px)


def mode_tiles(
    world: World,
    modes: ModeSet,
    count: int,
    tile_px: int = 240,
    max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG,
) -> list[np.ndarray]:
    """One RGB tile (tile_px × tile_px × 3) per mode 1..count: relax pose with ±A ghosts (module
    doc).

    Each tile's camera aims at the relax pose's centre and steps back just enough to keep both
    extremes in view.
    """
    amplitudes = peak_rotation_amplitudes(world, modes, max_rotation_deg)[:count]
    displacement = modes.shapes[:, :count] * amplitudes
    minus = displaced_qpos(world, -displacement.T)
    plus = displaced_qpos(world, displacement.T)
    relax = _corners(world, world.model.qpos0)
    centre = (relax.min(axis=0) + relax.max(axis=0)) / 2
    tiles = []
    with FrameRenderer(world, tile_px, tile_px, PALETTE_VIEW) as renderer:
        for i in range(count):
            renderer.fit(
                np.vstack([relax, _corners(world, minus[i]), _corners(world, plus[i])]), centre
            )
            base = _render(
                renderer, world.model.qpos0, SOLID_RGBA, lambda: _add_cues(renderer, relax, modes)
            )
            layers = [
                _ghost(renderer, relax, extreme, rgba, max_rotation_deg)
                for extreme, rgba in ((minus[i], MINUS_RGBA), (plus[i], PLUS_RGBA))
            ]
            tiles.append(_blend(base, layers))
    return tiles


def _ghost(
    renderer: FrameRenderer,
    relax: np.ndarray,
    extreme: np.ndarray,
    rgba: tuple,
    max_rotation_deg: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One extreme as a layer: its image, per-pixel opacity (H × W × 1) and depth (m, inf off the
    creature)."""
    segments = _segments(renderer, extreme)
    alpha = _ghost_opacity(renderer, relax, extreme, max_rotation_deg)[segments][..., None]
    renderer.renderer.enable_depth_rendering()
    try:
        depth = renderer.render(extreme)
    finally:
        renderer.renderer.disable_depth_rendering()
    return (
        _render(renderer, extreme, rgba).astype(float),
        alpha,
        np.where(segments >= 0, depth, np.inf),
    )


def _blend(base: np.ndarray, layers: list[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> np.ndarray:
    """Blend two ghost layers onto the base image, per pixel the farther first, so the nearer one
    shows on top where the two extremes overlap (as they would in space)."""
    (image_a, alpha_a, depth_a), (image_b, alpha_b, depth_b) = layers
    a_behind = (depth_a >= depth_b)[..., None]
    far_image, far_alpha = (
        np.where(a_behind, image_a, image_b),
        np.where(a_behind, alpha_a, alpha_b),
    )
    near_image, near_alpha = (
        np.where(a_behind, image_b, image_a),
        np.where(a_behind, alpha_b, alpha_a),
    )
    out = base * (1 - far_alpha) + far_image * far_alpha
    out = out * (1 - near_alpha) + near_image * near_alpha
    return out.round().astype(np.uint8)


def _render(renderer: FrameRenderer, qpos: np.ndarray, rgba: tuple, cues=None) -> np.ndarray:
    """The pose in one flat colour, with the extra scene geoms `cues()` adds (camera as fitted)."""
    renderer.update_scene(qpos, solid_rgba=rgba)
    if cues is not None:
        cues()
    return renderer.renderer.render()


def _segments(renderer: FrameRenderer, qpos: np.ndarray) -> np.ndarray:
    """Per pixel, the index into `renderer.geoms` of the creature geom seen there, or −1."""
    renderer.renderer.enable_segmentation_rendering()
    try:
        ids = renderer.render(qpos)
    finally:
        renderer.renderer.disable_segmentation_rendering()
    lookup = np.full(renderer.model.ngeom + 1, -1)
    lookup[renderer.geoms] = np.arange(len(renderer.geoms))
    is_geom = ids[..., 1] == mujoco.mjtObj.mjOBJ_GEOM
    return np.where(is_geom, lookup[np.where(is_geom, ids[..., 0], -1)], -1)


def _ghost_opacity(
    renderer: FrameRenderer, relax: np.ndarray, extreme: np.ndarray, max_rotation_deg: float
) -> np.ndarray:
    """Opacity per creature geom (and 0 for a last entry, indexed by −1), from how much the geom
    moves between the relax pose and the extreme: the larger of its travel (box corners, relative to
    MOVING_TRAVEL of the creature's height) and its own joint's rotation (relative to
    MOVING_ROTATION of the mode's peak rotation)."""
    model = renderer.model
    corners = _corners(renderer.world, extreme)
    height = float(np.ptp(relax[:, 2]))
    travel = np.linalg.norm(corners - relax, axis=1).reshape(-1, 8).max(axis=1) / (
        MOVING_TRAVEL * height
    )
    turn = np.array(
        [_joint_turn_deg(model, int(model.geom_bodyid[g]), extreme) for g in renderer.geoms]
    )
    moving = np.clip(np.maximum(travel, turn / (MOVING_ROTATION * max_rotation_deg)), 0, 1)
    low, high = GHOST_OPACITY
    return np.r_[low + (high - low) * moving, 0.0]


def _joint_turn_deg(model: mujoco.MjModel, body: int, qpos: np.ndarray) -> float:
    """Largest rotation (degrees) of the body's own ball or hinge joints away from the relax pose
    (qpos0)."""
    turns = [0.0]
    for j in body_joints(model, body):
        adr = model.jnt_qposadr[j]
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
            dot = abs(float(qpos[adr : adr + 4] @ model.qpos0[adr : adr + 4]))
            turns.append(np.degrees(2 * np.arccos(min(dot, 1.0))))
        elif model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE:
            turns.append(np.degrees(abs(qpos[adr] - model.qpos0[adr])))
    return max(turns)


def _add_cues(renderer: FrameRenderer, relax: np.ndarray, modes: ModeSet) -> None:
    """A facing arrow on the floor in front of the relax pose and, for a pinned toe, a red ball on
    it."""
    low, high = relax.min(axis=0), relax.max(axis=0)
    size = float(high[2] - low[2])
    start = [high[0] + 0.05 * size, (low[1] + high[1]) / 2, low[2] + 0.01]
    # the arrow's z axis along +x
    to_x = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
    renderer.add_marker(
        mujoco.mjtGeom.mjGEOM_ARROW,
        (0.035 * size, 0.035 * size, 0.3 * size),
        start,
        ARROW_RGBA,
        to_x,
    )
    for foot in modes.pinned_feet:
        site = renderer.model.site(renderer.world.character.feet[foot].toe).id
        renderer.add_marker(
            mujoco.mjtGeom.mjGEOM_SPHERE,
            (0.04 * size,) * 3,
            renderer.data.site_xpos[site],
            PINNED_RGBA,
        )


def _corners(world: World, qpos: np.ndarray) -> np.ndarray:
    data = mujoco.MjData(world.model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(world.model, data)
    return geom_corners(world.model, data, creature_geoms(world.model, world.root_body))


def palette_title(modes: ModeSet) -> str:
    where = f"{modes.phase} phase" + (f", {modes.pinned_text()}" if modes.foot else "")
    pose = "" if modes.relax_pose == "default" else f", relax pose {modes.relax_pose}"
    return f"{modes.character} — {where}{pose}"


def palette_image(
    world: World,
    modes: ModeSet,
    count: int | None = None,
    columns: int | None = None,
    tile_px: int = 240,
    max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG,
) -> np.ndarray:
    """The palette of modes 1..count (default all) as an RGB uint8 image of size
    `palette_layout(...).size`."""
    count = modes.count if count is None else count
    if not 1 <= count <= modes.count:
        raise UserInputError(
            f"cannot show {count} modes",
            field="count",
            fix=f"{modes.character} has {modes.count} modes in the {modes.phase} phase",
        )
    layout = palette_layout(count, columns, tile_px)
    canvas = np.full((*layout.size, 3), BACKGROUND, dtype=np.uint8)
    for i, tile in enumerate(mode_tiles(world, modes, count, tile_px, max_rotation_deg)):
        top, left = layout.tile_origin(i)
        canvas[top : top + tile_px, left : left + tile_px] = tile
    return _draw_labels(canvas, layout, modes, max_rotation_deg)


def _draw_labels(
    canvas: np.ndarray, layout: PaletteLayout, modes: ModeSet, max_rotation_deg: float
) -> np.ndarray:
    """Title, legend and per-tile labels drawn with matplotlib onto the canvas, same pixel size."""
    from eigengait.figures import agg_figure

    height, width = canvas.shape[:2]
    dpi = 100
    fig = agg_figure(width / dpi, height / dpi, dpi)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.imshow(canvas, interpolation="nearest")
    ax.set_axis_off()

    def text(x: float, y: float, s: str, **style) -> None:
        fig.text(x / width, 1 - y / height, s, va="center", **style)

    text(
        width / 2,
        layout.title_height * 0.36,
        palette_title(modes),
        ha="center",
        fontsize=17,
        weight="bold",
    )
    text(
        width / 2,
        layout.title_height * 0.74,
        "grey: relax pose   ·   orange: −A   ·   teal: +A   (opaque where the body moves)   ·   "
        "arrow: facing"
        + ("   ·   red ball: pinned toe" if modes.foot else "")
        + f"   ·   A turns the most-moving joint {max_rotation_deg:g}°",
        ha="center",
        fontsize=10.5,
        color="#444444",
    )
    for i in range(layout.count):
        top, left = layout.tile_origin(i)
        y = top - layout.label_height / 2
        text(left + 10, y, f"mode {i + 1}", ha="left", fontsize=12, weight="bold")
        text(
            left + layout.tile_width - 10,
            y,
            f"{modes.frequencies_hz[i]:.2f} Hz",
            ha="right",
            fontsize=11,
            color="#333333",
        )
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
    return image


def write_palette(
    world: World,
    modes: ModeSet,
    path: str | Path,
    count: int | None = None,
    columns: int | None = None,
    tile_px: int = 240,
    max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG,
) -> np.ndarray:
    """Render the palette and save it as PNG; returns the image."""
    import imageio.v3 as iio

    image = palette_image(world, modes, count, columns, tile_px, max_rotation_deg)
    with replacing(path) as temporary:
        iio.imwrite(temporary, image)
    return image
