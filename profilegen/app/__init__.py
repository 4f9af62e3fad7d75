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

__all__ = ["Notebook", "make_app", "serve", "show", "start"]


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


def show(gearset=None, *, workspace: str | Path = ".", scene: str | None = None, host: str = "127.0.0.1",
         port: int = 0, height: int = 950) -> "Notebook":
    """The workbench inside a Jupyter cell: the app served from this kernel on a background thread
    (:func:`start`; ``port=0``: a free port), shown by the returned :class:`Notebook`'s HTML — an
    ``<iframe>`` of ``height`` pixels — when it is the cell's last expression. The cell does not
    block; ``.stop()`` ends the server (a new ``show()`` starts another). Outside a notebook it
    serves all the same (``.url`` is the page's address)."""
    return Notebook(start(gearset, workspace=workspace, scene=scene, host=host, port=port), height=height)


class Notebook:
    """A workbench served for a notebook (:func:`show`): ``url``, ``app`` (the Dash app),
    :meth:`stop`, and the ``<iframe>`` Jupyter draws (``_repr_html_``)."""

    def __init__(self, running, *, height: int = 950):
        self.running, self.height = running, int(height)
        self.url, self.app = running.url, running.app

    def _repr_html_(self) -> str:
        from html import escape

        return (f'<iframe src="{escape(self.url)}" width="100%" height="{self.height}" '
                'style="border:1px solid #ddd" title="profilegen workbench"></iframe>')

    def __repr__(self) -> str:
        return f"profilegen workbench at {self.url}"

    def stop(self) -> None:
        self.running.stop()
