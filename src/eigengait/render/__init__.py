"""Images and videos: mode palettes and rendered animations of a World's poses."""

from eigengait.render.video import CameraView, FrameRenderer, iter_frames, render_video, write_video

__all__ = ["CameraView", "FrameRenderer", "iter_frames", "render_video", "write_video"]
