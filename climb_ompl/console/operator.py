"""A scripted operator: the console's page in headless Chromium (Playwright), driven as a person would: a click on a
hold in the 3-D view, the panel's buttons, the preview slider; with the page's own timestamps of what it shows.

Used by the browser tests and ``climb-ompl bench console``.  Chromium is Debian's, launched by path
(:func:`climb_ompl.viz._browser.chromium_path`); requests to any other host than the console's are blocked and
counted (the page needs no network).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Iterator
from typing import Any
from urllib.parse import urlparse

import numpy as np

#: Page script: record when each of the texts appears on the page from now on (``performance.now()``, ms), watched
#: by one MutationObserver; ``window.__seen[text]`` holds the time (a text already shown counts at once).
JS_WATCH = """(texts) => {
  window.__seen = window.__seen || {};
  window.__texts = texts;
  for (const t of texts) delete window.__seen[t];
  window.__check = () => { const body = document.body.innerText;
    for (const t of window.__texts) {
      if (!(t in window.__seen) && body.includes(t)) window.__seen[t] = performance.now(); } };
  window.__check();
  if (!window.__observer) {
    window.__observer = new MutationObserver(() => window.__check());
    window.__observer.observe(document.body, {subtree: true, childList: true, characterData: true});
  }
}"""
#: Page script: the value of the preview slider's thumb each time it changes after the watch starts, with its time.
JS_SLIDER = """() => {
  window.__slider = [];
  const el = () => document.querySelector('[role="slider"]');
  const check = () => { const s = el(); if (!s) return; const v = s.getAttribute('aria-valuenow');
    const last = window.__slider.length ? window.__slider[window.__slider.length - 1][1] : null;
    if (v !== last) window.__slider.push([performance.now(), v]); };
  check();
  new MutationObserver(check).observe(document.body, {subtree: true, attributes: true, childList: true});
}"""


class Operator:
    """The page of a running :class:`~climb_ompl.console.page.ConsolePage` in Chromium.

    Attributes:
        page: the Playwright page; console: the console page (server side); blocked: requests blocked (other
        hosts).
    """

    def __init__(self, page: Any, console: Any):
        self.page, self.console = page, console
        self.blocked: list[str] = []

    def client(self) -> Any:
        """The viser client of this page (the one connected)."""
        clients = self.console.server.get_clients()
        if not clients:
            raise RuntimeError("no client connected")
        return clients[max(clients)]

    def screen_point(self, p: Any) -> tuple[float, float]:
        """Page pixel of world point ``p`` through the client's camera (pinhole, vertical field of view ``fov``;
        the camera frame is OpenCV's: x right, y down, z forward)."""
        import viser.transforms as tf

        cam = self.client().camera
        R = tf.SO3(np.asarray(cam.wxyz, dtype=float)).as_matrix()
        pc = R.T @ (np.asarray(p, dtype=float) - np.asarray(cam.position, dtype=float))
        box = self.page.locator("canvas").first.bounding_box()
        w, h = box["width"], box["height"]
        f = 0.5 * h / np.tan(0.5 * float(cam.fov))
        return box["x"] + w / 2 + f * pc[0] / pc[2], box["y"] + h / 2 + f * pc[1] / pc[2]

    def click_hold(self, hid: str) -> float:
        """Click hold ``hid`` in the 3-D view; the page time of the click, ms (``performance.now()``)."""
        x, y = self.screen_point(self.console.hold_pos[hid])
        t = float(self.page.evaluate("() => performance.now()"))
        self.page.mouse.click(x, y)
        return t

    def clock_offset(self) -> float:
        """Milliseconds to add to a page time (``performance.now()``) to get this process's
        ``time.perf_counter()`` in milliseconds (measured across one round trip, to within half of it)."""
        a = time.perf_counter()
        page = float(self.page.evaluate("() => performance.now()"))
        b = time.perf_counter()
        return 500.0 * (a + b) - page

    def click_latency(self, hid: str, timeout_s: float = 5.0) -> tuple[float, float] | None:
        """Click hold ``hid``: milliseconds from the click until the page shows it selected, and of those until
        the server's click callback ran (the rest is the way back and the page's drawing); ``None`` when the click
        did not select it (it missed the hold)."""
        text = f"Selected hold: {hid};"
        self.watch(text)
        off = self.clock_offset()
        t = self.click_hold(hid)
        try:
            seen = self.seen(text, timeout_s)
        except TimeoutError:
            return None
        return seen - t, 1000.0 * self.console.stamps["select"] - off - t

    def press(self, label: str) -> None:
        """Click the panel's button ``label``."""
        self.page.get_by_role("button", name=label, exact=True).click()

    def watch(self, *texts: str) -> None:
        """Start recording when each of ``texts`` first appears on the page (:meth:`seen`)."""
        self.page.evaluate(JS_WATCH, list(texts))

    def seen(self, text: str, timeout_s: float = 60.0) -> float:
        """Page time (ms) at which ``text`` appeared (waits for it).

        Raises:
            TimeoutError: it did not appear within ``timeout_s``.
        """
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout_s:
            v = self.page.evaluate("(t) => (window.__seen || {})[t]", text)
            if v is not None:
                return float(v)
            self.page.wait_for_timeout(20)
        raise TimeoutError(f"{text!r} did not appear within {timeout_s} s")

    def wait_text(self, text: str, timeout_s: float = 60.0) -> None:
        """Wait until ``text`` is on the page."""
        self.page.get_by_text(text).first.wait_for(timeout=timeout_s * 1000)

    def wait_idle(self, timeout_s: float = 120.0) -> None:
        """Wait until the console plans nothing."""
        t0 = time.monotonic()
        while self.console.state.busy is not None and time.monotonic() - t0 < timeout_s:
            time.sleep(0.02)
        self.page.wait_for_timeout(150)


@contextlib.contextmanager
def browse(console: Any, *, size: tuple[int, int] = (1280, 800), timeout_s: float = 60.0) -> Iterator[Operator]:
    """Open ``console``'s page in headless Chromium; yields an :class:`Operator` once the page shows the panel and
    its client is connected.

    Raises:
        VizError: Playwright or Chromium is missing.
    """
    from climb_ompl.errors import VizError
    from climb_ompl.viz._browser import CHROMIUM_ARGS, chromium_path

    exe = chromium_path()
    if exe is None:
        raise VizError("chromium not found (apt-get install chromium, or set CLIMB_OMPL_CHROMIUM)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        raise VizError("playwright is not installed") from None
    host = urlparse(console.url).netloc
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=exe, args=list(CHROMIUM_ARGS), headless=True)
        try:
            page = browser.new_page(viewport={"width": size[0], "height": size[1]})
            op = Operator(page, console)

            def route(r: Any) -> None:
                u = urlparse(r.request.url)
                if u.scheme in ("data", "blob") or u.netloc == host:
                    r.continue_()
                else:
                    op.blocked.append(r.request.url)
                    r.abort()

            page.route("**/*", route)
            n0 = len(console.server.get_clients())
            page.goto(console.url, timeout=timeout_s * 1000)
            page.get_by_role("button", name="Accept", exact=True).wait_for(timeout=timeout_s * 1000)
            t0 = time.monotonic()
            while len(console.server.get_clients()) <= n0 and time.monotonic() - t0 < timeout_s:
                time.sleep(0.05)
            page.wait_for_timeout(1500)  # the scene and the camera
            yield op
        finally:
            browser.close()


__all__ = ["JS_SLIDER", "JS_WATCH", "Operator", "browse"]
