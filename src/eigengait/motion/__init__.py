"""Motion capture: BVH files, retargeting onto characters, and kinematic replay of reference
motion."""

from eigengait.motion.bvh import BvhClip, BvhJoint, global_transforms, read_bvh, write_bvh

__all__ = ["BvhClip", "BvhJoint", "global_transforms", "read_bvh", "write_bvh"]
