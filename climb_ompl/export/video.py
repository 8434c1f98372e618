"""A climb plan's 3-D playback as a video: the playback page (:func:`climb_ompl.viz.play`) rendered frame by frame in
headless Chromium (:mod:`climb_ompl.viz._browser`) and encoded with imageio (MP4 through its ffmpeg plugin, H.264;
GIF through Pillow), with the climb's clock written over each frame.

Frame ``k`` shows the plan at ``k * speedup / fps`` seconds of the climb (the page plays a timed plan on its own
clock, :func:`climb_ompl.viz._plans.timeline`).  The file is encoded beside its target and renamed into place when
complete: a failure leaves nothing behind.
"""

from __future__ import annotations

import io
import math
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from climb_ompl._io import _file_mode, output_target
from climb_ompl.errors import InputError

#: Formats this module writes and the imageio keyword arguments of each.
FORMATS = ("mp4", "gif")

_JS_STAMP = """(text) => {
  let el = document.getElementById('climb-clock');
  if (!el) {
    el = document.createElement('div');
    el.id = 'climb-clock';
    el.style.cssText = 'position:fixed;left:12px;bottom:10px;font:bold 20px monospace;color:#111;' +
      'background:rgba(255,255,255,0.75);padding:2px 8px;border-radius:4px;z-index:1000';
    document.body.appendChild(el);
  }
  el.textContent = text;
  document.querySelectorAll('.dg').forEach((e) => { e.style.display = 'none'; });  // the controls panel
  return true;
}"""


def frame_times(duration: float, fps: float, speedup: float) -> list[float]:
    """Climb times of the video's frames, seconds: every ``speedup / fps`` from 0, and the end."""
    step = speedup / fps
    n = int(math.floor(duration / step + 1e-9))
    return [k * step for k in range(n + 1)] + ([duration] if duration - n * step > 1e-9 else [])


def write_video(plan: dict[str, Any] | str | Path, out: str | os.PathLike[str], *, fps: float = 10.0,
                speedup: float = 10.0, size: tuple[int, int] = (640, 400), robot: Any = None,
                progress: Callable[[int, int], None] | None = None) -> Path:
    """Render the plan's playback to ``out`` (``.mp4`` or ``.gif``, by its suffix).

    Args:
        plan: a plan dict or plan file of any kind the playback draws.
        fps: frames per second of the video.  speedup: seconds of climb per second of video.
        size: width and height in pixels (even numbers for MP4).
        progress: called with ``(frames done, frames)``.

    Raises:
        InputError: an output path that cannot be written, or a suffix that is not ``.mp4`` or ``.gif``.
        VizError: no Chromium or Playwright.
    """
    import imageio.v2 as imageio

    from climb_ompl import viz
    from climb_ompl.viz._browser import JS_SEEK, JS_TWO_FRAMES, open_page

    target, why = output_target(out)
    kind = target.suffix.lower().lstrip(".")
    if why is None and kind not in FORMATS:
        why = f"a video file name ends in .mp4 or .gif, got {target.name!r}"
    if why is None and not os.access(target.parent if str(target.parent) else ".", os.W_OK):
        why = f"folder {str(target.parent)!r} is not writable"
    if why is not None:
        raise InputError(out, "output", why)
    with tempfile.TemporaryDirectory(prefix="climb-video-") as tmp:
        html = viz.play(plan, html=Path(tmp) / "play.html", robot=robot)
        fd, part = tempfile.mkstemp(prefix=f".{target.name}.", suffix=f".{kind}", dir=target.parent or ".")
        os.close(fd)
        try:
            with open_page(html, size=size) as (page, _log):
                duration = page.evaluate("() => viewer.animator ? viewer.animator.duration : 0") or 0.0
                times = frame_times(float(duration), fps, speedup)
                opts = {"fps": fps, "codec": "libx264", "macro_block_size": 2, "quality": 7} if kind == "mp4" else \
                    {"duration": 1000.0 / fps, "loop": 0}
                with imageio.get_writer(part, format="FFMPEG" if kind == "mp4" else "GIF", **opts) as writer:
                    for k, t in enumerate(times):
                        page.evaluate(JS_SEEK, t)
                        page.evaluate(_JS_STAMP, f"t = {t:7.2f} s  (x{speedup:g})")
                        page.evaluate(JS_TWO_FRAMES)
                        writer.append_data(imageio.imread(io.BytesIO(page.screenshot(type="png")))[..., :3])
                        if progress is not None:
                            progress(k + 1, len(times))
            os.chmod(part, _file_mode(target))  # as a plain open would make it, not mkstemp's 0600
            os.replace(part, target)
        finally:
            if os.path.exists(part):
                os.unlink(part)
    return target


__all__ = ["FORMATS", "frame_times", "write_video"]
