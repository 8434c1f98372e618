"""Headless Chromium for playback pages: launch flags, a page on a static HTML file, screenshots.

Playwright cannot download its own browser here, so Debian's ``chromium`` is launched by path; WebGL goes
through SwiftShader (software) or meshcat draws a blank canvas.
"""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

CHROMIUM_ARGS: tuple[str, ...] = (
    "--no-sandbox",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--ignore-gpu-blocklist",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-default-apps",
)

# JavaScript run in the page.  ``viewer`` is the global meshcat.Viewer the static HTML creates.
JS_NODE_COUNT = """() => {
  if (!window.viewer || !viewer.scene_tree) return -1;
  let n = 0;
  const walk = (node) => { n += 1; for (const c of Object.values(node.children)) walk(c); };
  walk(viewer.scene_tree);
  return n;
}"""

JS_SEEK = """(t) => {
  const a = viewer.animator;
  if (!a || a.actions.length === 0) return null;
  if (!a.playing) { a.play(); }
  a.pause();
  const time = (t === null || t === undefined) ? a.duration : Math.max(0, Math.min(a.duration, t));
  a.seek(time);
  viewer.render();
  return time;
}"""

JS_TWO_FRAMES = "() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(true))))"


def chromium_path() -> str | None:
    """Path of the Chromium executable: ``$CLIMB_OMPL_CHROMIUM``, ``chromium`` on PATH, or ``None``."""
    env = os.environ.get("CLIMB_OMPL_CHROMIUM")
    if env and Path(env).is_file():
        return env
    for cand in ("chromium", "chromium-browser"):
        found = shutil.which(cand)
        if found:
            return found
    return "/usr/bin/chromium" if Path("/usr/bin/chromium").is_file() else None


@dataclass
class PageLog:
    """What a page reported while loading: console messages, uncaught errors, network requests."""

    console: list[tuple[str, str]] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    requests: list[str] = field(default_factory=list)
    #: the page's own URL
    page_url: str = ""

    @property
    def console_errors(self) -> list[str]:
        """Console messages of type ``error`` plus uncaught page errors."""
        return [text for kind, text in self.console if kind == "error"] + self.errors

    @property
    def external_requests(self) -> list[str]:
        """Requests for anything but the page itself and ``data:``/``blob:`` URLs (should be none; a file beside the
        page, such as a mesh's texture, counts too)."""
        return [u for u in self.requests if u != self.page_url and not u.startswith(("data:", "blob:", "about:"))]


@contextlib.contextmanager
def open_page(html: str | Path, *, size: tuple[int, int] = (1280, 800), settle_ms: int = 300,
              timeout_s: float = 30.0) -> Iterator[tuple[Any, PageLog]]:
    """Open a static meshcat HTML file in headless Chromium and wait until its scene is built.

    Yields ``(page, log)``: the Playwright page and a :class:`PageLog`.  Requests to anything but
    ``file:``/``data:`` URLs are blocked (and logged): a self-contained page needs none.

    Raises:
        VizError: Playwright or Chromium is missing, or the page never builds a meshcat viewer.
    """
    from climb_ompl.errors import VizError

    exe = chromium_path()
    if exe is None:
        raise VizError("no Chromium found (apt-get install chromium, or set CLIMB_OMPL_CHROMIUM)")
    try:
        from playwright.sync_api import Error as PlaywrightError
        from playwright.sync_api import sync_playwright
    except ImportError:
        raise VizError("screenshots need the 'playwright' Python package (pip install playwright)") from None
    path = Path(html).resolve()
    if not path.is_file():
        raise VizError(f"{html}: no such HTML file")
    log = PageLog(page_url=path.as_uri())
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=exe, args=list(CHROMIUM_ARGS), headless=True)
        try:
            page = browser.new_page(viewport={"width": size[0], "height": size[1]})
            page.on("console", lambda m: log.console.append((m.type, m.text)))
            page.on("pageerror", lambda e: log.errors.append(str(e)))

            def route(r: Any) -> None:
                log.requests.append(r.request.url)
                if r.request.url.startswith(("file:", "data:", "blob:", "about:")):
                    r.continue_()
                else:
                    r.abort()

            page.route("**/*", route)
            page.goto(path.as_uri(), wait_until="load", timeout=timeout_s * 1000)
            try:
                page.wait_for_function("() => window.viewer && viewer.scene_tree && viewer.scene_tree.children"
                                       " && viewer.scene_tree.children.meshcat", timeout=timeout_s * 1000)
            except PlaywrightError:
                raise VizError(f"{html}: no meshcat scene appeared (errors: {log.console_errors})") from None
            _wait_stable(page, settle_ms, timeout_s)
            yield page, log
        finally:
            browser.close()


def _wait_stable(page: Any, settle_ms: int, timeout_s: float) -> None:
    """Wait until the scene tree stops growing (the static page replays its commands asynchronously)."""
    last, stable, waited = -2, 0, 0
    while waited < timeout_s * 1000 and stable < 3:
        n = page.evaluate(JS_NODE_COUNT)
        stable = stable + 1 if n == last else 0
        last = n
        page.wait_for_timeout(settle_ms // 3 or 1)
        waited += settle_ms // 3 or 1


def screenshot(html: str | Path, png: str | Path, *, time: float | None = None,
               size: tuple[int, int] = (1280, 800), note: Callable[[str], None] | None = None) -> Path:
    """A PNG of a static playback page, with the animation paused at ``time`` seconds (default: the end).

    A ``time`` past the animation's end shows the end; ``note`` (when given) is told so, with the animation's
    length.

    Raises:
        VizError: no Chromium or Playwright, or the page has no meshcat scene.
    """
    from climb_ompl._io import atomic_write

    with open_page(html, size=size) as (page, _log):
        shown = page.evaluate(JS_SEEK, time)  # the time sought, clamped to the animation; null without one
        if time is not None and note is not None:
            if shown is None:
                note(f"the page has no animation: time {time:g} s is ignored")
            elif time > shown + 1e-9:
                note(f"time {time:g} s is past the animation's end ({shown:.3g} s at this speed): "
                     "the screenshot shows the end")
        page.evaluate(JS_TWO_FRAMES)
        data = page.screenshot(type="png")
    return atomic_write(png, data)
