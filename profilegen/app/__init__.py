"""``profilegen app``: a local web workbench — change a field, see the conjugate profile, its fit
and its verdict.

* :mod:`.schema` — the gear set as a form (every field the reader checks, with unit and range);
* :mod:`.compute` — :func:`redesign`, the one function the app computes a design through;
* :mod:`.session` — one tab's state: undo/redo, the computation off the request threads (the
  newest request supersedes), the pinned design, the workspace folder;
* :mod:`.views` — the figures and numbers drawn from a design;
* :mod:`.server` — the Dash page, its callbacks and the local server.

In a notebook: ``profilegen.app.show()`` runs the same app inside the cell.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["make_app", "serve", "show", "start"]


def make_app(gearset=None, *, workspace: str | Path = ".", scene: str | None = None):
    """The Dash app (see :func:`profilegen.app.server.make_app`)."""
    from .server import make_app as _make

    return _make(gearset, workspace=workspace, scene=scene)


def serve(gearset=None, *, workspace: str | Path = ".", scene: str | None = None, host: str = "127.0.0.1",
          port: int = 8050) -> int:
    """Serve until Ctrl-C, printing the URL (what ``profilegen app`` runs)."""
    from .server import serve as _serve

    return _serve(gearset, workspace=workspace, scene=scene, host=host, port=port)


def start(gearset=None, *, workspace: str | Path = ".", scene: str | None = None, host: str = "127.0.0.1",
          port: int = 0):
    """Serve on a background thread; returns a handle with ``url`` and ``stop()``."""
    from .server import start as _start

    return _start(gearset, workspace=workspace, scene=scene, host=host, port=port)


def show(gearset=None, *, workspace: str | Path = ".", scene: str | None = None, port: int = 8050,
         height: int = 950):
    """The workbench inside a Jupyter cell (Dash's inline mode), served from this kernel."""
    app = make_app(gearset, workspace=workspace, scene=scene)
    app.run(jupyter_mode="inline", host="127.0.0.1", port=port, jupyter_height=height)
    return app
