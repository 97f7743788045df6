"""Encoding: frames streamed to the bundled ffmpeg, segments joined without re-encoding.

Frames are piped to the ffmpeg bundled with imageio-ffmpeg (one pipe, no frame files,
memory flat), started here with the command imageio-ffmpeg's ``write_frames`` uses, so
that armanim owns the process: it is killed and waited for on any error or interrupt.
ffmpeg's stderr is captured to a temporary file so that a failure becomes a
:class:`~armanim.errors.RenderError` quoting ffmpeg's last lines. Every writer either
closes cleanly or is aborted; nothing here moves files into place (see
:mod:`armanim.render.video.movie`).
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import tempfile
from fractions import Fraction
from pathlib import Path
from typing import IO

import numpy as np

from armanim.errors import RenderError
from armanim.procs.workers import forget, on_stop, undone_on_stop

MP4_CODEC = "libx264"
MP4_PIX_FMT = "yuv420p"  # what the pipe carries too: armanim converts (render/video/planes.py), ffmpeg only encodes
MP4_PARAMS = ["-preset", "ultrafast", "-tune", "animation", "-crf", "20", "-threads", "1"]
"""ultrafast: the same CRF quality, 0.5 s less per 338 frames at 720p, files ~3x veryfast's (1.1 MB).
One encoder thread: ffmpeg is a process of its own beside the one drawing, and the video's workers
fill the cores already; x264's threads cost a fifth more CPU a frame (1.9 ms against 2.2 at 960 x 540)."""
GIF_PALETTE = "palettegen=max_colors=128:stats_mode=full:reserve_transparent=0"
GIF_USE = "[0:v][1:v]paletteuse=dither=bayer:bayer_scale=4:diff_mode=rectangle"
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


def tail(text: str, lines: int = LOG_LINES) -> str:
    """The last non-empty ``lines`` lines of ``text``."""
    kept = [line for line in text.splitlines() if line.strip()]
    return "\n".join(kept[-lines:])


def ffmpeg_command(
    exe: str,
    path: Path,
    size: tuple[int, int],
    fps: Fraction,
    pix_fmt_in: str,
    codec: str,
    pix_fmt_out: str,
    output_params: list[str],
    extra_inputs: tuple[str, ...] = (),
) -> list[str]:
    """The ffmpeg command that reads raw frames on stdin and encodes them into ``path``
    (the command imageio-ffmpeg's ``write_frames`` builds, with ``macro_block_size=1``);
    ``extra_inputs`` are further ``-i`` files (a GIF's palette)."""
    inputs = [arg for name in extra_inputs for arg in ("-i", name)]
    return [
        exe,
        "-y",
        "-f",
        "rawvideo",
        "-vcodec",
        "rawvideo",
        "-s",
        f"{size[0]}x{size[1]}",
        "-pix_fmt",
        pix_fmt_in,
        "-r",
        str(fps),
        "-i",
        "-",
        *inputs,
        "-an",
        "-vcodec",
        codec,
        "-pix_fmt",
        pix_fmt_out,
        "-v",
        "error",
        *output_params,
        str(path),
    ]


def find_ffmpeg() -> str:
    """:func:`ffmpeg_exe`, with a RenderError instead of imageio-ffmpeg's RuntimeError."""
    try:
        return ffmpeg_exe()
    except Exception as err:  # noqa: BLE001  (imageio-ffmpeg raises RuntimeError, or ImportError)
        raise RenderError(
            f"ffmpeg could not be found: {err} (reinstall imageio-ffmpeg, or set IMAGEIO_FFMPEG_EXE)"
        ) from None


def _stdin(proc: subprocess.Popen | None) -> IO[bytes]:
    """The pipe into an ffmpeg started with ``stdin=PIPE``."""
    assert proc is not None and proc.stdin is not None, "ffmpeg was started with its input piped"
    return proc.stdin


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
    palette : str or Path, optional
        For a GIF: the palette image (:func:`gif_palette`) every frame is mapped to;
        without it ffmpeg's default palette is used.

    Use as a context manager: leaving it normally finishes the file and raises
    :class:`RenderError` if ffmpeg failed; leaving it by an exception (including
    KeyboardInterrupt) kills ffmpeg and waits for it, so no ffmpeg outlives the writer.

    ffmpeg runs in its own session: a Ctrl-C at the terminal reaches armanim, which
    ends ffmpeg itself (ffmpeg would otherwise finish a half video on its own). Its
    stderr goes to a temporary file, quoted in the error if it fails.
    """

    def __init__(self, path, size: tuple[int, int], fps: float, fmt: str, palette=None):
        self.path = Path(path)
        self.palette = palette
        self.size = (int(size[0]), int(size[1]))
        self.out_size = video_size(*self.size, fmt)
        self.fps = Fraction(fps).limit_denominator(1001)
        self.fmt = fmt
        self._proc: subprocess.Popen | None = None
        self._log: IO[bytes] | None = None
        self._undo: int | None = None
        self._planes: np.ndarray | None = None  # an MP4 frame's yuv420p bytes, reused
        self.frames = 0

    def _params(self) -> dict:
        if self.fmt == "mp4":
            return dict(
                codec=MP4_CODEC,
                pix_fmt_in=MP4_PIX_FMT,
                pix_fmt_out=MP4_PIX_FMT,
                output_params=[*MP4_PARAMS, "-f", "mp4"],
            )
        if self.fmt == "gif":
            use = ["-lavfi", GIF_USE] if self.palette is not None else []
            return dict(
                codec="gif",
                pix_fmt_in="rgb24",
                pix_fmt_out="pal8",
                output_params=[*use, "-loop", "0", "-f", "gif"],
                extra_inputs=(str(self.palette),) if self.palette is not None else (),
            )
        raise RenderError(f"unknown video format {self.fmt!r} (expected 'mp4' or 'gif')")

    def open(self) -> FrameWriter:
        """Start ffmpeg."""
        params = self._params()
        cmd = ffmpeg_command(find_ffmpeg(), self.path, self.out_size, self.fps, **params)
        try:
            self._log = tempfile.TemporaryFile(prefix="armanim-ffmpeg-")
            self._proc = subprocess.Popen(
                cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=self._log, start_new_session=True
            )
            self._undo = on_stop(self._proc.kill)  # a worker stopped meanwhile kills its ffmpeg
        except OSError as err:
            self.abort()
            raise RenderError(
                f"ffmpeg could not be started ({cmd[0]}): {err.strerror or err} "
                "(reinstall imageio-ffmpeg, or set IMAGEIO_FFMPEG_EXE to a working ffmpeg)"
            ) from None
        return self

    def write(self, rgba: np.ndarray) -> None:
        """Send one (H, W, 4) uint8 frame of exactly ``size``: an MP4's as its yuv420p planes
        (:mod:`armanim.render.video.planes`: ffmpeg then only encodes), a GIF's as RGB."""
        if self.fmt == "mp4":
            from armanim.render.video.planes import yuv420  # compiled: numba is imported here

            if self._planes is None:
                self._planes = np.empty(self.out_size[0] * self.out_size[1] * 3 // 2, dtype=np.uint8)
            data = yuv420(pad_to(rgba, *self.out_size), self._planes)
        else:
            data = np.ascontiguousarray(pad_to(rgba[..., :3], *self.out_size))
        try:
            _stdin(self._proc).write(data.data.cast("B"))
        except (BrokenPipeError, OSError, ValueError) as err:  # ffmpeg has stopped
            self._fail(err)
        self.frames += 1

    def close(self) -> None:
        """Finish the file; raise :class:`RenderError` if ffmpeg did not succeed."""
        proc = self._proc
        if proc is None:
            return
        try:
            _stdin(proc).close()  # ffmpeg finishes the file and exits
        except (BrokenPipeError, OSError) as err:
            self._fail(err)
        code = proc.wait()
        if code != 0 or not self.path.exists() or self.path.stat().st_size == 0:
            self._fail(None)
        self._proc = None
        self._close_log()

    def abort(self) -> None:
        """Stop ffmpeg at once (after an error or an interrupt) and wait for it; the file is left to the caller."""
        proc, self._proc = self._proc, None
        if proc is not None:
            if proc.poll() is None:
                with contextlib.suppress(OSError):
                    proc.kill()
            with contextlib.suppress(Exception):
                _stdin(proc).close()
            proc.wait()
        self._close_log()

    def _fail(self, err: Exception | None):
        if self._proc is not None:
            with contextlib.suppress(Exception):
                _stdin(self._proc).close()
            with contextlib.suppress(Exception):
                self._proc.wait(timeout=10)
        log = self._read_log()
        self.abort()
        detail = tail(log) or (str(err).splitlines()[0] if err else "no output")
        raise RenderError(f"ffmpeg failed while writing {self.path.name}:\n{detail}") from None

    def _read_log(self) -> str:
        if self._log is None:
            return ""
        self._log.seek(0)
        return self._log.read().decode("utf-8", "replace")

    def _close_log(self) -> None:
        if self._undo is not None:
            forget(self._undo)
            self._undo = None
        if self._log is not None:
            self._log.close()
            self._log = None

    def __enter__(self) -> FrameWriter:
        return self.open()

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


@contextlib.contextmanager
def gif_palette(beside: Path, size: tuple[int, int], frames):
    """Make one 128-colour palette from some RGBA ``frames`` (ffmpeg ``palettegen``) and
    yield its path; the file (beside ``beside``) is removed afterwards.

    One palette for the whole GIF, with ordered dithering and only the changed
    rectangle of each frame stored, keeps a GIF small (an 11 s, 640x360 run is about
    1 MB instead of 6 to 9 MB with a palette per frame).
    """
    exe = find_ffmpeg()
    # a fresh name armanim made (never a user's file that happens to be called so), removed afterwards
    fd, name = tempfile.mkstemp(prefix=f".{Path(beside).name}.", suffix=".palette.png", dir=Path(beside).parent)
    os.close(fd)
    path = Path(name)
    cmd = [
        exe,
        "-y",
        "-v",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgb24",
        "-s",
        f"{size[0]}x{size[1]}",
        "-i",
        "-",
        "-vf",
        GIF_PALETTE,
        "-frames:v",
        "1",
        str(path),
    ]
    try:
        with tempfile.TemporaryFile(prefix="armanim-ffmpeg-") as log:
            proc = subprocess.Popen(
                cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=log, start_new_session=True
            )
            with undone_on_stop(proc.kill):  # a worker stopped meanwhile kills this ffmpeg too
                try:
                    for rgba in frames:
                        _stdin(proc).write(np.ascontiguousarray(rgba[..., :3]).tobytes())
                    _stdin(proc).close()
                except BrokenPipeError:
                    pass
                finally:
                    if proc.poll() is None and not _stdin(proc).closed:
                        proc.kill()
                    code = proc.wait()
            log.seek(0)
            if code != 0 or not path.exists():
                raise RenderError(
                    f"ffmpeg failed while making the GIF palette:\n{tail(log.read().decode('utf-8', 'replace'))}"
                )
        yield path
    finally:
        path.unlink(missing_ok=True)


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
    extra = ["-movflags", "+faststart"] if fmt == "mp4" else []
    cmd = [
        find_ffmpeg(),
        "-y",
        "-v",
        "error",
        "-f",
        "concat",
        "-safe",
        "0",
        "-i",
        str(listing),
        "-c",
        "copy",
        *extra,
        "-f",
        fmt,
        str(path),
    ]
    try:
        listing.write_text("\n".join(lines) + "\n", encoding="utf-8")
        result = subprocess.run(cmd, capture_output=True, text=True, check=False)  # killed on any exception
    except OSError as err:
        if err.filename == cmd[0]:
            raise RenderError(f"ffmpeg could not be started ({cmd[0]}): {err.strerror or err}") from None
        raise
    finally:
        listing.unlink(missing_ok=True)
    if result.returncode != 0:
        raise RenderError(f"ffmpeg failed while joining segments into {path.name}:\n{tail(result.stderr)}")
