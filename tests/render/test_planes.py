"""A frame's yuv420p planes (render/video/planes.py) against ffmpeg's own conversion (swscale), the
one the video used before armanim converted its frames itself."""

from __future__ import annotations

import subprocess

import numpy as np

from armanim.render.video.encode import ffmpeg_exe
from armanim.render.video.planes import yuv420


def _swscale(rgba: np.ndarray) -> np.ndarray:
    height, width = rgba.shape[:2]
    proc = subprocess.run(
        [
            ffmpeg_exe(),
            "-v",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgba",
            "-s",
            f"{width}x{height}",
            "-i",
            "-",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "yuv420p",
            "-",
        ],
        input=rgba.tobytes(),
        capture_output=True,
        check=True,
    )
    return np.frombuffer(proc.stdout, dtype=np.uint8)


def test_the_planes_are_swscale_s():
    """Luma within 1 of swscale's everywhere; chroma (a mean of 2 x 2 pixels here, swscale's own
    filter there) within 1 on smooth colour, and both planes laid out as ffmpeg reads them."""
    height, width = 48, 64
    y, x = np.mgrid[0:height, 0:width]
    rgba = np.zeros((height, width, 4), dtype=np.uint8)
    rgba[..., 0] = (255 * x / (width - 1)).astype(np.uint8)
    rgba[..., 1] = (255 * y / (height - 1)).astype(np.uint8)
    rgba[..., 2] = (128 + 100 * np.sin(x / 9.0) * np.cos(y / 7.0)).astype(np.uint8)
    rgba[..., 3] = 255
    ours, theirs = yuv420(rgba).astype(int), _swscale(rgba).astype(int)
    assert ours.shape == theirs.shape == (height * width * 3 // 2,)
    luma = height * width
    assert np.abs(ours[:luma] - theirs[:luma]).max() <= 1
    assert np.abs(ours[luma:] - theirs[luma:]).max() <= 1


def test_a_drawn_frame_s_planes_are_swscale_s_but_at_sharp_edges():
    """A frame of flat colours with sharp edges (what the pictures are): luma within 1 everywhere,
    chroma the same but for a few samples along edges, where the two chroma filters differ."""
    rng = np.random.default_rng(3)
    rgba = np.full((60, 80, 4), 255, dtype=np.uint8)
    for _ in range(12):
        r0, c0 = rng.integers(0, 50), rng.integers(0, 70)
        rgba[r0 : r0 + rng.integers(4, 20), c0 : c0 + rng.integers(4, 20), :3] = rng.integers(0, 256, 3)
    ours, theirs = yuv420(rgba).astype(int), _swscale(rgba).astype(int)
    luma = 60 * 80
    assert np.abs(ours[:luma] - theirs[:luma]).max() <= 1
    chroma = np.abs(ours[luma:] - theirs[luma:])
    assert np.mean(chroma <= 1) > 0.9 and chroma.mean() < 1.0
