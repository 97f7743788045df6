"""Encoding: frames streamed to the bundled ffmpeg, segments joined without re-encoding.

Frames go through ``imageio_ffmpeg.write_frames`` (one pipe, no frame files, memory
flat). ffmpeg's stderr is captured to a temporary file so that a failure becomes a
:class:`~armanim.errors.RenderError` quoting ffmpeg's last lines. Every writer either
closes cleanly or is aborted; nothing here moves files into place (see
:mod:`armanim.render.video`).
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import tempfile
from fractions import Fraction
from pathlib import Path

import numpy as np

from armanim.errors import RenderError

MP4_CODEC = "libx264"
MP4_PIX_FMT = "yuv420p"
MP4_PARAMS = ["-preset", "fast", "-tune", "animation", "-crf", "20"]
GIF_FILTER = "split[a][b];[a]palettegen=stats_mode=single:reserve_transparent=0[p];[b][p]paletteuse=new=1"
LOG_LINES = 12  # lines of ffmpeg's output quoted in an error


def ffmpeg_exe() -> str:
    """Path of the ffmpeg bundled with imageio-ffmpeg."""
    import imageio_ffmpeg

    return imageio_ffmpeg.get_ffmpeg_exe()


def video_size(width: int, height: int, fmt: str) -> tuple[int, int]:
    """Encoded size: MP4 (yuv420p) needs even sides, so odd ones grow by one pixel.

    >>> video_size(161, 120, "mp4"), video_size(161, 121, "gif")
    ((162, 120), (161, 121))
    """
    if fmt == "mp4":
        return width + width % 2, height + height % 2
    return width, height


def pad_to(frame: np.ndarray, width: int, height: int) -> np.ndarray:
    """Pad a (H, W, C) frame on the right and bottom by repeating its edge pixels."""
    h, w = frame.shape[:2]
    if (w, h) == (width, height):
        return frame
    return np.pad(frame, ((0, height - h), (0, width - w), (0, 0)), mode="edge")


@contextlib.contextmanager
def stderr_to(fd: int):
    """Point file descriptor 2 at ``fd`` for the duration (children started inherit it)."""
    sys.stderr.flush()
    saved = os.dup(2)
    os.dup2(fd, 2)
    try:
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def tail(text: str, lines: int = LOG_LINES) -> str:
    """The last non-empty ``lines`` lines of ``text``."""
    kept = [line for line in text.splitlines() if line.strip()]
    return "\n".join(kept[-lines:])


class FrameWriter:
    """Stream RGBA frames into an MP4 (libx264, yuv420p) or a GIF through ffmpeg.

    Parameters
    ----------
    path : str or Path
        Output file (written directly: callers write to a temporary path).
    size : (int, int)
        Width and height of the frames that will be written.
    fps : float
        Frames per second; passed to ffmpeg as an exact fraction.
    fmt : {"mp4", "gif"}

    Use as a context manager: leaving it normally finishes the file and raises
    :class:`RenderError` if ffmpeg failed; leaving it by an exception kills ffmpeg.
    """

    def __init__(self, path, size: tuple[int, int], fps: float, fmt: str):
        self.path = Path(path)
        self.size = (int(size[0]), int(size[1]))
        self.out_size = video_size(*self.size, fmt)
        self.fps = Fraction(fps).limit_denominator(1001)
        self.fmt = fmt
        self._gen = None
        self._proc = None
        self._log = None
        self.frames = 0

    def _params(self) -> dict:
        if self.fmt == "mp4":
            return dict(codec=MP4_CODEC, pix_fmt_in="rgba", pix_fmt_out=MP4_PIX_FMT, quality=None,
                        output_params=[*MP4_PARAMS, "-f", "mp4"])
        if self.fmt == "gif":
            return dict(codec="gif", pix_fmt_in="rgb24", pix_fmt_out="pal8", quality=None,
                        output_params=["-vf", GIF_FILTER, "-loop", "0", "-f", "gif"])
        raise RenderError(f"unknown video format {self.fmt!r} (expected 'mp4' or 'gif')")

    def open(self) -> "FrameWriter":
        """Start ffmpeg."""
        import imageio_ffmpeg

        params = self._params()
        self._log = tempfile.TemporaryFile(prefix="armanim-ffmpeg-")
        self._gen = imageio_ffmpeg.write_frames(
            str(self.path), self.out_size, fps=self.fps, macro_block_size=1,
            ffmpeg_log_level="error", **params,
        )
        try:
            with stderr_to(self._log.fileno()):
                self._gen.send(None)  # starts ffmpeg, which inherits the log as stderr
        except Exception as err:
            self._fail(err)
        frame = getattr(self._gen, "gi_frame", None)
        self._proc = frame.f_locals.get("p") if frame is not None else None
        return self

    def write(self, rgba: np.ndarray) -> None:
        """Send one (H, W, 4) uint8 frame of exactly ``size``."""
        frame = rgba if self.fmt == "mp4" else rgba[..., :3]
        frame = np.ascontiguousarray(pad_to(frame, *self.out_size))
        try:
            self._gen.send(frame)
        except Exception as err:  # a broken pipe: ffmpeg has stopped
            self._fail(err)
        self.frames += 1

    def close(self) -> None:
        """Finish the file; raise :class:`RenderError` if ffmpeg did not succeed."""
        if self._gen is None:
            return
        gen, self._gen = self._gen, None
        try:
            gen.close()  # closes ffmpeg's stdin and waits for it
        except Exception as err:
            self._fail(err)
        code = self._proc.returncode if self._proc is not None else 0
        if code != 0 or not self.path.exists() or self.path.stat().st_size == 0:
            self._fail(None)
        self._close_log()

    def abort(self) -> None:
        """Stop ffmpeg at once (after an error or an interrupt); the file is left to the caller."""
        if self._proc is not None and self._proc.poll() is None:
            self._proc.kill()
            self._proc.wait()
        if self._gen is not None:
            gen, self._gen = self._gen, None
            with contextlib.suppress(Exception):
                gen.close()
        self._close_log()

    def _fail(self, err: Exception | None):
        if self._proc is not None:
            with contextlib.suppress(Exception):
                self._proc.wait(timeout=10)
        log = self._read_log()
        self.abort()
        detail = tail(log) or (str(err).splitlines()[0] if err else "no output")
        raise RenderError(f"ffmpeg failed while writing {self.path.name}:\n{detail}") from err

    def _read_log(self) -> str:
        if self._log is None:
            return ""
        self._log.seek(0)
        return self._log.read().decode("utf-8", "replace")

    def _close_log(self) -> None:
        if self._log is not None:
            self._log.close()
            self._log = None

    def __enter__(self) -> "FrameWriter":
        return self.open()

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


def concat_segments(segments: list[Path], path: Path, fmt: str) -> None:
    """Join encoded segments into ``path`` without re-encoding (ffmpeg concat, ``-c copy``).

    Parameters
    ----------
    segments : list of Path
        Files of the same codec, size and fps, in playing order.
    path : Path
        Output file (written directly).
    fmt : {"mp4", "gif"}
    """
    listing = path.with_name(path.name + ".concat.txt")
    lines = ["file '" + str(Path(s).resolve()).replace("'", "'\\''") + "'" for s in segments]
    listing.write_text("\n".join(lines) + "\n", encoding="utf-8")
    extra = ["-movflags", "+faststart"] if fmt == "mp4" else []
    cmd = [ffmpeg_exe(), "-y", "-v", "error", "-f", "concat", "-safe", "0", "-i", str(listing),
           "-c", "copy", *extra, "-f", fmt, str(path)]
    try:
        result = subprocess.run(cmd, capture_output=True, text=True, check=False)
    finally:
        listing.unlink(missing_ok=True)
    if result.returncode != 0:
        raise RenderError(f"ffmpeg failed while joining segments into {path.name}:\n{tail(result.stderr)}")
