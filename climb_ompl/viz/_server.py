"""The meshcat server: a visualizer for the length of a ``with`` block, static HTML export, live serving.

meshcat keeps the scene tree in its server process, and ``Visualizer.static_html()`` asks that server for
a self-contained page (viewer JavaScript plus every command, the animation included).  So a static export
also starts a server (a local subprocess on free ports, about half a second) and stops it afterwards.
"""

from __future__ import annotations

import contextlib
import io
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TextIO

import meshcat

from climb_ompl._io import atomic_write


@contextlib.contextmanager
def open_visualizer(*, quiet: bool = True) -> Iterator[meshcat.Visualizer]:
    """A meshcat ``Visualizer`` on a fresh local server, stopped when the block ends.

    Args:
        quiet: hide meshcat's "You can open the visualizer..." banner.

    Raises:
        VizError: the server could not be started.
    """
    from climb_ompl.errors import VizError

    sink = io.StringIO()
    with _stopped_by_signals():
        try:
            with contextlib.redirect_stdout(sink) if quiet else contextlib.nullcontext():
                vis = meshcat.Visualizer()
        except (RuntimeError, OSError) as exc:
            raise VizError(f"cannot start the meshcat server: {exc}") from None
        try:
            yield vis
        finally:
            close_visualizer(vis)


@contextlib.contextmanager
def _stopped_by_signals() -> Iterator[None]:
    """Within the block, SIGTERM and SIGHUP (``timeout``, ``kill``, a closed terminal) exit through Python
    (``SystemExit``), so that ``finally`` clauses run: without it the process died at once and left the meshcat
    server it had started running, holding its port.  Only in the main thread (where Python handles signals), and
    only for signals the process does not ignore (``nohup`` keeps meaning what it says)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, _frame: object) -> None:
        raise SystemExit(128 + signum)

    names = [n for n in ("SIGTERM", "SIGHUP")
             if hasattr(signal, n) and signal.getsignal(getattr(signal, n)) is not signal.SIG_IGN]
    old = {n: signal.signal(getattr(signal, n), stop) for n in names}
    try:
        yield
    finally:
        for n, handler in old.items():
            signal.signal(getattr(signal, n), handler)


def close_visualizer(vis: meshcat.Visualizer) -> None:
    """Close the connection and stop the server process this visualizer started (if any)."""
    window = vis.window
    sock = getattr(window, "zmq_socket", None)
    if sock is not None:
        sock.close(linger=0)
    proc = getattr(window, "server_proc", None)
    if proc is not None and proc.poll() is None:
        proc.kill()
        proc.wait(timeout=10)


def render_html(build: Callable[[meshcat.Visualizer], object]) -> str:
    """Run ``build(vis)`` on a fresh visualizer and return the static, self-contained HTML of the result."""
    with open_visualizer() as vis:
        build(vis)
        return vis.static_html()


def write_html(path: str | Path, build: Callable[[meshcat.Visualizer], object]) -> Path:
    """Like :func:`render_html`, written atomically to ``path`` (no partial file on error).

    Raises:
        InputError: the output folder does not exist or is not writable (checked before building).
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        from climb_ompl.errors import InputError

        raise InputError(path, "output", f"folder {str(folder)!r} does not exist")
    return atomic_write(path, render_html(build))


def serve(build: Callable[[meshcat.Visualizer], object], *, wait: bool | None = None,
          out: TextIO | None = None) -> str:
    """Live playback: start a meshcat server, build the scene, print its URL.

    Args:
        build: draws into the visualizer.
        wait: keep the server up until Enter (or Ctrl-C); default: only when stdin is a terminal, so a
            non-interactive run (CI, a pipe) returns at once instead of hanging.
        out: where to print the URL (default stdout).

    Returns:
        The viewer URL (the server stops when this returns, or at process exit when not waiting).
    """
    out = out or sys.stdout
    if wait is None:
        wait = sys.stdin is not None and sys.stdin.isatty()
    with open_visualizer() as vis:
        build(vis)
        url = vis.url()
        print(f"meshcat viewer: {url}", file=out, flush=True)
        if wait:
            print("press Enter (or Ctrl-C) to stop the server", file=out, flush=True)
            with contextlib.suppress(EOFError, KeyboardInterrupt):
                _wait_for_enter()
        else:
            print("stdin is not a terminal: not waiting (the server stops now)", file=out, flush=True)
    return url


def _wait_for_enter(slice_s: float = 0.25) -> None:
    """Wait for a line (Enter) or the end of standard input.

    Python runs a signal's handler between bytecodes, in the main thread; a signal another thread took, or one that
    arrived after the last check and before a blocking read began, is handled only when the read returns: ``kill``
    sent at such a moment left the viewer waiting for Enter.  On POSIX, when standard input is the process's own and
    ``input`` Python's, the wait is in slices of ``slice_s`` seconds (``select`` on the file descriptor, then a read of
    what is there), after each of which pending handlers run; elsewhere (Windows, a notebook's input prompt, a replaced
    ``sys.stdin``) it is ``input()``.  Input Python already buffered in ``sys.stdin`` is not seen (nothing reads it
    before)."""
    import builtins
    import os
    import select

    fd = -1
    if os.name == "posix" and sys.stdin is not None and sys.stdin is sys.__stdin__ \
            and getattr(builtins.input, "__module__", None) == "builtins":
        try:
            fd = sys.stdin.fileno()
        except (AttributeError, OSError, ValueError):
            fd = -1
    if fd < 0:
        input()
        return
    try:
        while True:
            if not select.select([fd], [], [], slice_s)[0]:
                continue
            chunk = os.read(fd, 4096)
            if not chunk or b"\n" in chunk:
                return
    except (ValueError, OSError):  # a descriptor select cannot watch (>= FD_SETSIZE): Python's own wait
        input()
