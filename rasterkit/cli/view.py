"""``rasterkit view MODEL [render flags]``: the interactive viewer as a local web page
(:mod:`rasterkit.viewer.server`), ended with Ctrl-C, after which it prints the ``rasterkit
render`` command that draws the last view."""

from __future__ import annotations

import argparse
import shlex
import sys

from rasterkit.batch.report import UsageError
from rasterkit.cli.args import add_limits, add_view_arguments, positive_int, task_from_args
from rasterkit.cli.look import add_look_arguments
from rasterkit.options import MODES

__all__ = ["add_view_command", "run"]

#: The viewer's image size unless ``--size`` says otherwise.
VIEW_SIZE = (960, 720)
# Left out of the render command the viewer prints (the number of arguments each takes): the
# view command's own flags, and those of the view that the command's last flags replace.
_DROPPED = {"--port": 1, "--no-browser": 0, "--size": 1, "--eye": 1, "--target": 1, "--up": 1, "--fov": 1,
            "--azimuth": 1, "--elevation": 1, "--distance": 1, "--mode": 1, "--shading": 1, "--camera": 1,
            "--camera-opencv": 1}


def _port(text: str) -> int:
    value = positive_int(text)
    if value > 65535:
        raise argparse.ArgumentTypeError(f"a port is 1 to 65535, got {value}")
    return value


def add_view_command(commands) -> None:
    v = commands.add_parser("view", help="look at a model interactively in the browser (a local page)")
    v.add_argument("model", nargs="?", metavar="MODEL", help="a model file (none: --demo)")
    v.add_argument("--demo", action="store_true", help="view the built-in demo model")
    v.add_argument("--mode", choices=MODES, default="solid", help="default solid")
    v.add_argument("--port", type=_port, default=0, help="the page's port on 127.0.0.1 (default: a free one)")
    v.add_argument("--no-browser", action="store_true", help="only print the page's address")
    v.add_argument("--threads", type=positive_int, metavar="N", help="threads for the kernels (default: all cores)")
    add_view_arguments(v)
    add_look_arguments(v)
    add_limits(v)
    v.set_defaults(size=VIEW_SIZE, turntable=None, turn_lights=False, depth=None, normals=None, ids=None)


def render_arguments(argv: list[str]) -> list[str]:
    """``view``'s arguments (after the word ``view``) without its own flags and those of the
    view (:meth:`rasterkit.viewer.session.ViewerSession.flags` gives them): the rest of a
    ``rasterkit render`` command."""
    kept, skip = [], 0
    for word in argv:
        if skip:
            skip -= 1
            continue
        name = word.split("=", 1)[0]
        if name in _DROPPED:
            skip = _DROPPED[name] if "=" not in word else 0
            continue
        kept.append(word)
    return kept


def run(args, argv: list[str]) -> int:
    """Serve the viewer until Ctrl-C; then print the render command of the last view."""
    import webbrowser
    from pathlib import Path

    if (args.model is None) == (not args.demo):
        raise UsageError("view takes one model file, or --demo")
    task = task_from_args(args)
    from rasterkit.batch import report as _report
    from rasterkit.batch.render_one import load_drawn
    from rasterkit.runtime import threads as _threads
    from rasterkit.runtime.notice import compile_notice
    from rasterkit.viewer.loop import FrameLoop
    from rasterkit.viewer.server import ViewerServer
    from rasterkit.viewer.session import ViewerSession, choices

    try:
        _threads.set_threads(args.threads)
    except ValueError as e:
        raise UsageError(str(e)) from None
    source = None if args.model is None else Path(args.model)
    with compile_notice():
        with _report.model(source):
            drawn = load_drawn(source, task.frame_options(), task.options.textures,
                               lambda line: print(line, file=sys.stderr))
            session = ViewerSession(drawn, task.view)
        session.command = render_arguments(argv[1:])  # argv[0] is "view"
        loop = FrameLoop(session)
        try:
            server = ViewerServer(loop, {"model": "the demo" if source is None else source.name,
                                         "size": list(task.view.size), "choices": choices(),
                                         "current": session.current()}, args.port)
        except OSError as e:
            loop.close()
            raise UsageError(f"port {args.port}: {e.strerror or e}") from None
        print(f"rasterkit view: {server.url} (Ctrl-C to stop)", flush=True)
        if not args.no_browser:
            webbrowser.open(server.url)
        try:
            server.serve_forever(poll_interval=0.2)
        except KeyboardInterrupt:
            pass
        finally:
            server.server_close()
            loop.close()
    print("rasterkit render " + shlex.join([*session.command, *session.flags(), "-o", "view.png"]), flush=True)
    return 0
