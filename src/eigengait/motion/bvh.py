"""Biovision BVH files: read, write, and forward kinematics in the file's own units and axes.

A clip keeps raw channel values exactly as stored (file length units, degrees, file channel order).
Each joint's local rotation is the product of its rotation channels in the listed order
(intrinsic rotations, column vectors): ``R = R(first) @ R(second) @ R(third)``. A position
channel is the joint's local translation along its axis, in place of the OFFSET's component (the
OFFSET is the rest pose): the files that put position channels on every joint store the bone there
(Bandai Namco's: the Hips channels hold the 90 cm hip height beside a 94 cm OFFSET; added, the legs
would be twice as long). Roots with a zero OFFSET, as CMU's, read the same either way. Conversion
to metres and to the z-up world happens elsewhere, once.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from eigengait.errors import UserInputError
from eigengait.outputs import write_atomically

ROTATION_CHANNELS = ("Xrotation", "Yrotation", "Zrotation")
POSITION_CHANNELS = ("Xposition", "Yposition", "Zposition")
_AXIS = {"X": 0, "Y": 1, "Z": 2}


@dataclass
class BvhJoint:
    """One ROOT or JOINT entry: offset in file units in the parent frame, channels in file order."""

    name: str
    parent: int
    offset: np.ndarray
    channels: list[str]
    end_site: np.ndarray | None = None


@dataclass
class BvhClip:
    """A BVH clip: hierarchy plus raw frames of shape (n_frames, n_channels) in file units and
    degrees."""

    joints: list[BvhJoint]
    frame_time: float
    frames: np.ndarray

    @property
    def n_frames(self) -> int:
        return int(self.frames.shape[0])

    @property
    def duration(self) -> float:
        """Clip length in seconds (frames × frame time)."""
        return self.n_frames * self.frame_time

    def joint_index(self, name: str) -> int:
        for i, joint in enumerate(self.joints):
            if joint.name == name:
                return i
        raise KeyError(name)

    def rest(self) -> "BvhClip":
        """The one-frame rest pose: every rotation zero, every position channel at its OFFSET."""
        row = np.zeros((1, self.frames.shape[1]))
        for joint, cols in zip(self.joints, self.channel_slices()):
            for k, channel in enumerate(joint.channels):
                if channel in POSITION_CHANNELS:
                    row[0, cols.start + k] = joint.offset[_AXIS[channel[0]]]
        return BvhClip(self.joints, self.frame_time, row)

    def channel_slices(self) -> list[slice]:
        """Column range of each joint's channels in ``frames``."""
        slices, start = [], 0
        for joint in self.joints:
            slices.append(slice(start, start + len(joint.channels)))
            start += len(joint.channels)
        return slices


# ------------------------------------------------------------------------------------------ reading


class _Tokens:
    """Whitespace tokens of the HIERARCHY section with their 1-based line numbers."""

    def __init__(self, lines: list[str], path: str):
        self.items: list[tuple[str, int]] = []
        self.path = path
        self.pos = 0
        for number, line in enumerate(lines, start=1):
            for token in line.split():
                self.items.append((token, number))

    def error(
        self, message: str, line: int | None = None, fix: str | None = None
    ) -> UserInputError:
        if line is None:
            line = self.items[min(self.pos, len(self.items) - 1)][1] if self.items else 1
        return UserInputError(
            message,
            file=self.path,
            field=f"line {line}",
            fix=fix or "check the BVH HIERARCHY syntax (ROOT/JOINT/End Site, OFFSET, CHANNELS).",
        )

    def next(self, what: str) -> tuple[str, int]:
        if self.pos >= len(self.items):
            last = self.items[-1][1] if self.items else 1
            raise self.error(
                f"the file ends early: expected {what}.",
                last,
                fix="the file is truncated; re-export or re-download it.",
            )
        item = self.items[self.pos]
        self.pos += 1
        return item

    def expect(self, word: str) -> int:
        token, line = self.next(f"'{word}'")
        if token != word:
            raise self.error(f"expected '{word}' but found '{token}'.", line)
        return line

    def floats(self, count: int, what: str) -> np.ndarray:
        values = []
        for _ in range(count):
            token, line = self.next(what)
            try:
                values.append(float(token))
            except ValueError:
                raise self.error(
                    f"expected a number in {what} but found '{token}'.", line
                ) from None
        return np.array(values, dtype=float)


MAX_DEPTH = 200  # joints from the root to the deepest leaf; real skeletons have fewer than 30


def _parse_joint(
    tokens: _Tokens, joints: list[BvhJoint], parent: int, name: str, depth: int = 0
) -> None:
    if depth > MAX_DEPTH:
        raise tokens.error(
            f"the hierarchy is deeper than {MAX_DEPTH} joints at '{name}'.",
            fix="check the file's nesting of braces; a real skeleton is far shallower.",
        )
    tokens.expect("{")
    tokens.expect("OFFSET")
    offset = tokens.floats(3, f"the OFFSET of '{name}'")
    tokens.expect("CHANNELS")
    count_token, line = tokens.next("the channel count")
    try:
        count = int(count_token)
    except ValueError:
        raise tokens.error(
            f"expected a channel count for '{name}' but found '{count_token}'.", line
        ) from None
    channels = []
    for _ in range(count):
        channel, line = tokens.next(f"a channel name of '{name}'")
        if channel not in ROTATION_CHANNELS + POSITION_CHANNELS:
            raise tokens.error(
                f"unknown channel '{channel}' in joint '{name}'.",
                line,
                fix="channels must be X/Y/Z followed by 'rotation' or 'position'.",
            )
        channels.append(channel)
    joint = BvhJoint(name=name, parent=parent, offset=offset, channels=channels)
    index = len(joints)
    joints.append(joint)
    while True:
        token, line = tokens.next(f"'}}' closing joint '{name}'")
        if token == "}":
            return
        if token == "JOINT":
            child, _ = tokens.next("a joint name")
            _parse_joint(tokens, joints, index, child, depth + 1)
        elif token == "End":
            tokens.expect("Site")
            tokens.expect("{")
            tokens.expect("OFFSET")
            joint.end_site = tokens.floats(3, f"the End Site OFFSET of '{name}'")
            tokens.expect("}")
        else:
            raise tokens.error(f"unexpected '{token}' inside joint '{name}'.", line)


def _header_value(line: str, key: str, path: str, number: int) -> str:
    head, _, value = line.partition(":")
    if head.strip().lower() != key.lower() or not value.strip():
        raise UserInputError(
            f"expected '{key}: <value>' but found '{line.strip()}'.",
            file=path,
            field=f"line {number}",
            fix="the MOTION section starts with 'Frames:' and 'Frame Time:'.",
        )
    return value.strip()


def read_bvh(path: str | Path) -> BvhClip:
    """Read a BVH file (any channel order, End Sites, tabs, '.0083333'-style numbers).

    Raises:
        UserInputError: naming the file and line for a malformed or truncated file.
    """
    path = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise UserInputError(
            f"cannot read the BVH file ({exc.strerror}).", file=path, fix="check the path."
        ) from None
    lines = text.splitlines()
    motion_line = next((i for i, line in enumerate(lines) if line.strip() == "MOTION"), None)
    if motion_line is None:
        raise UserInputError(
            "no MOTION section.",
            file=path,
            field=f"line {len(lines)}",
            fix="the file is truncated or not a BVH file.",
        )
    tokens = _Tokens(lines[:motion_line], path)
    token, line = tokens.next("'HIERARCHY'")
    if token != "HIERARCHY":
        raise tokens.error(
            f"a BVH file starts with 'HIERARCHY', found '{token}'.", line, fix="is this a BVH file?"
        )
    tokens.expect("ROOT")
    root, _ = tokens.next("the root joint name")
    joints: list[BvhJoint] = []
    _parse_joint(tokens, joints, -1, root)
    if tokens.pos != len(tokens.items):
        token, line = tokens.items[tokens.pos]
        raise tokens.error(
            f"unexpected '{token}' after the root joint (only one ROOT is supported).", line
        )

    header = [(i, lines[i]) for i in range(motion_line + 1, len(lines)) if lines[i].strip()][:2]
    if len(header) < 2:
        raise UserInputError(
            "the MOTION section ends before 'Frames:' and 'Frame Time:'.",
            file=path,
            field=f"line {len(lines)}",
            fix="the file is truncated; re-export it.",
        )
    (frames_at, frames_text), (time_at, time_text) = header
    try:
        n_frames = int(_header_value(frames_text, "Frames", path, frames_at + 1))
        frame_time = float(_header_value(time_text, "Frame Time", path, time_at + 1))
    except ValueError:
        raise UserInputError(
            "'Frames' must be an integer and 'Frame Time' a number.",
            file=path,
            field=f"line {frames_at + 1}",
            fix="fix the MOTION header.",
        ) from None
    if n_frames < 1 or not frame_time > 0:
        raise UserInputError(
            f"need at least one frame and a positive frame time (got {n_frames}, {frame_time}).",
            file=path,
            field=f"line {frames_at + 1}",
            fix="fix the MOTION header.",
        )

    n_channels = sum(len(j.channels) for j in joints)
    rows = []
    for number in range(time_at + 1, len(lines)):
        values = lines[number].split()
        if not values:
            continue
        if len(values) != n_channels:
            raise UserInputError(
                f"frame {len(rows)} has {len(values)} values, the hierarchy declares {n_channels}.",
                file=path,
                field=f"line {number + 1}",
                fix="the file is truncated or corrupted; re-export it.",
            )
        rows.append(values)
        if len(rows) == n_frames:
            break
    if len(rows) < n_frames:
        raise UserInputError(
            f"the file declares {n_frames} frames but holds only {len(rows)}.",
            file=path,
            field=f"line {len(lines)}",
            fix="the file is truncated; re-export or re-download it.",
        )
    try:
        frames = np.array(rows, dtype=float)
    except ValueError:
        bad = next(i for i, row in enumerate(rows) if not _all_numbers(row))
        raise UserInputError(
            f"frame {bad} holds a value that is not a number.",
            file=path,
            field=f"frame {bad}",
            fix="fix or re-export the file.",
        ) from None
    if not np.all(np.isfinite(frames)):
        raise UserInputError(
            "the motion data holds NaN or infinite values.",
            file=path,
            field="MOTION",
            fix="re-export the clip.",
        )
    return BvhClip(
        joints=joints, frame_time=frame_time, frames=frames.reshape(n_frames, n_channels)
    )


def _all_numbers(row: list[str]) -> bool:
    try:
        [float(v) for v in row]
    except ValueError:
        return False
    return True


# ------------------------------------------------------------------------------------------ writing


def _fmt(values: np.ndarray) -> str:
    return " ".join(f"{v:.10g}" for v in values)


def write_bvh(clip: BvhClip, path: str | Path) -> None:
    """Write a clip as BVH text (tab-indented hierarchy, 10 significant digits)."""
    children: dict[int, list[int]] = {}
    for i, joint in enumerate(clip.joints):
        children.setdefault(joint.parent, []).append(i)
    out = ["HIERARCHY"]

    def emit(index: int, depth: int) -> None:
        joint, pad = clip.joints[index], "\t" * depth
        out.append(f"{pad}{'ROOT' if joint.parent < 0 else 'JOINT'} {joint.name}")
        out.append(f"{pad}{{")
        out.append(f"{pad}\tOFFSET {_fmt(joint.offset)}")
        out.append(f"{pad}\tCHANNELS {len(joint.channels)} {' '.join(joint.channels)}".rstrip())
        for child in children.get(index, []):
            emit(child, depth + 1)
        if joint.end_site is not None:
            out.extend(
                [
                    f"{pad}\tEnd Site",
                    f"{pad}\t{{",
                    f"{pad}\t\tOFFSET {_fmt(joint.end_site)}",
                    f"{pad}\t}}",
                ]
            )
        out.append(f"{pad}}}")

    for root in children.get(-1, []):
        emit(root, 0)
    out += ["MOTION", f"Frames: {clip.n_frames}", f"Frame Time: {clip.frame_time:.10g}"]
    out += [_fmt(row) for row in clip.frames]
    write_atomically(path, "\n".join(out) + "\n")


# ------------------------------------------------------------------------------- forward kinematics


def axis_rotation(axis: str, degrees: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) about the file axis 'X', 'Y' or 'Z' by ``degrees``."""
    angle = np.radians(np.asarray(degrees, dtype=float))
    c, s = np.cos(angle), np.sin(angle)
    rot = np.zeros(angle.shape + (3, 3))
    i = _AXIS[axis]
    j, k = (i + 1) % 3, (i + 2) % 3
    rot[..., i, i] = 1.0
    rot[..., j, j] = c
    rot[..., k, k] = c
    rot[..., k, j] = s
    rot[..., j, k] = -s
    return rot


def local_transforms(clip: BvhClip) -> tuple[np.ndarray, np.ndarray]:
    """Per-frame local rotations (F, J, 3, 3) and translations (F, J, 3) of every joint, file
    units."""
    n, m = clip.n_frames, len(clip.joints)
    rotations = np.broadcast_to(np.eye(3), (n, m, 3, 3)).copy()
    translations = np.zeros((n, m, 3))
    for index, (joint, cols) in enumerate(zip(clip.joints, clip.channel_slices())):
        translations[:, index] = joint.offset
        values = clip.frames[:, cols]
        for k, channel in enumerate(joint.channels):
            axis = channel[0]
            if channel.endswith("rotation"):
                rotations[:, index] = rotations[:, index] @ axis_rotation(axis, values[:, k])
            else:
                translations[:, index, _AXIS[axis]] = values[:, k]
    return rotations, translations


def global_transforms(clip: BvhClip) -> tuple[np.ndarray, np.ndarray]:
    """Per-frame global joint rotations (F, J, 3, 3) and positions (F, J, 3), file units and
    axes."""
    local_rot, local_pos = local_transforms(clip)
    rotations = np.empty_like(local_rot)
    positions = np.empty_like(local_pos)
    for index, joint in enumerate(clip.joints):
        if joint.parent < 0:
            rotations[:, index] = local_rot[:, index]
            positions[:, index] = local_pos[:, index]
        else:
            parent_rot = rotations[:, joint.parent]
            rotations[:, index] = parent_rot @ local_rot[:, index]
            positions[:, index] = positions[:, joint.parent] + np.einsum(
                "fij,fj->fi", parent_rot, local_pos[:, index]
            )
    return rotations, positions


def end_site_positions(
    clip: BvhClip, rotations: np.ndarray, positions: np.ndarray
) -> dict[int, np.ndarray]:
    """Global End Site positions (F, 3) keyed by the owning joint index, from
    ``global_transforms``."""
    return {
        i: positions[:, i] + rotations[:, i] @ joint.end_site
        for i, joint in enumerate(clip.joints)
        if joint.end_site is not None
    }


def frame_points(clip: BvhClip, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Global positions (file units) in the given raw frames (F, channels) of the clip's joints
    (F, J, 3) and of its joints followed by its End Sites (F, J + E, 3)."""
    some = BvhClip(clip.joints, clip.frame_time, frames)
    rotations, positions = global_transforms(some)
    ends = [p[:, None] for p in end_site_positions(some, rotations, positions).values()]
    return positions, np.concatenate([positions, *ends], axis=1)
