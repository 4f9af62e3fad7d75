"""One browser tab's state: the gear set and its undo/redo history, the designs computed off the
web server's request threads (the newest request supersedes the older ones), the pinned design
of an A/B compare, and the workspace folder the tab may read and write.

Nothing here knows about the web framework: the tests drive it directly.
"""

from __future__ import annotations

import logging
import os
import re
import threading
import time
import uuid
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any, Callable

from ..pipeline.engine import Cancelled
from ..errors import ProfilegenError
from ..gearset import GearSet, load_gearset
from . import schema
from .compute import redesign

__all__ = ["Computer", "History", "Session", "Sessions", "Snapshot", "Workspace", "WorkspaceError"]

log = logging.getLogger(__name__)


class WorkspaceError(ProfilegenError):
    """A file name the workspace refuses (outside it, not a gear-set file, unreadable)."""


# ------------------------------------------------------------------------------------------ workspace

BUNDLED = "bundled:"  # a bundled gear set's name in the load list (not a file of the workspace)
_NAME_PART = re.compile(r"[A-Za-z0-9_.+-]+")
MAX_LISTED = 500


class Workspace:
    """The one folder the app reads and writes (given at start). A file is named relative to
    it (``sets/a.toml``): no absolute path, no ``..``, no hidden part, nothing that resolves
    (through a link) outside the folder; gear-set files end in ``.toml``."""

    def __init__(self, root: str | os.PathLike):
        path = Path(root).expanduser()
        if not path.is_dir():
            raise WorkspaceError(f"workspace {str(root)!r}: not a folder")
        self.root = path.resolve()

    def path(self, name: str, *, suffix: str = ".toml") -> Path:
        """The file ``name`` inside the workspace, or :class:`WorkspaceError` saying why not."""
        if not isinstance(name, str) or not name.strip():
            raise WorkspaceError("file name: give a name such as my_set.toml")
        text = name.strip()
        shown = repr(text if len(text) <= 80 else text[:77] + "...")
        if "\\" in text or "\x00" in text or text.startswith(("/", "~")) or re.match(r"^[A-Za-z]:", text):
            raise WorkspaceError(f"file name {shown}: must be a name inside the workspace, not a path elsewhere")
        parts = PurePosixPath(text).parts
        if not parts or any(p in ("..", ".") or p.startswith(".") or not _NAME_PART.fullmatch(p) for p in parts):
            raise WorkspaceError(f"file name {shown}: only letters, digits, _ . + - and / between folders "
                                 "(no '..', no hidden names)")
        if suffix and not text.endswith(suffix):
            raise WorkspaceError(f"file name {shown}: must end in {suffix}")
        path = (self.root / Path(*parts)).resolve()
        if not path.is_relative_to(self.root):
            raise WorkspaceError(f"file name {shown}: resolves outside the workspace {self.root}")
        return path

    def gearset_files(self) -> list[str]:
        """The ``.toml`` files in the workspace (and its folders, not hidden ones), relative names."""
        out = []
        for dirpath, dirnames, filenames in os.walk(self.root):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith(".") and d != "export")
            for f in sorted(filenames):
                if f.endswith(".toml") and not f.startswith("."):
                    rel = (Path(dirpath) / f).relative_to(self.root).as_posix()
                    try:
                        self.path(rel)
                    except WorkspaceError:
                        continue
                    out.append(rel)
                    if len(out) >= MAX_LISTED:
                        return out
        return out

    def load(self, name: str) -> GearSet:
        path = self.path(name)
        if not path.is_file():
            raise WorkspaceError(f"{name}: no such file in the workspace")
        return load_gearset(path)

    def save(self, gearset: GearSet, name: str) -> Path:
        """The gear set's explicit fields as TOML (atomically), at ``name`` in the workspace."""
        from ..output.optimize import write_gearset_toml

        path = self.path(name)
        if not path.parent.is_dir():
            raise WorkspaceError(f"{name}: its folder is not in the workspace")
        return write_gearset_toml(gearset.to_dict(include_defaults=False), path,
                                  header=[f"saved by profilegen app on {time.strftime('%Y-%m-%d %H:%M')}"])

    def export(self, design) -> Path:
        """Every output file of ``design`` into ``export/<name>/`` in the workspace (the output
        layer's atomic folder), and the gear set beside it as ``export/<name>.toml``."""
        from ..output.files import write_design

        name = design.gearset.name  # [a-z0-9_-]+ (the reader's pattern): one plain folder name
        out = self.root / "export" / name
        out.parent.mkdir(exist_ok=True)
        write_design(design, out)
        self.save(design.gearset, f"export/{name}.toml")
        return out


# ------------------------------------------------------------------------------------------ history

class History:
    """Undo/redo over whole states (gear set, scene): a new state drops what could be redone."""

    def __init__(self, first, *, limit: int = 200):
        self._items, self._i, self._limit = [first], 0, limit

    @property
    def current(self):
        return self._items[self._i]

    @property
    def can_undo(self) -> bool:
        return self._i > 0

    @property
    def can_redo(self) -> bool:
        return self._i < len(self._items) - 1

    def push(self, item) -> None:
        if item == self.current:
            return
        del self._items[self._i + 1:]
        self._items.append(item)
        if len(self._items) > self._limit:
            del self._items[0]
        self._i = len(self._items) - 1

    def undo(self):
        if self.can_undo:
            self._i -= 1
        return self.current

    def redo(self):
        if self.can_redo:
            self._i += 1
        return self.current


# ------------------------------------------------------------------------------------------ computing

class Superseded(Exception):
    """Raised inside a running design when a newer request came (not an error)."""


@dataclass(frozen=True)
class Snapshot:
    """What one request has produced so far: ``design`` (partial until ``done``), the stages
    started, an ``error`` line instead of a design, and a ``version`` that grows with every
    snapshot of the session."""

    job: int
    version: int
    gearset: GearSet
    scene: str
    design: Any = None
    stages: tuple[str, ...] = ()
    planned: tuple[str, ...] = ()
    done: bool = False
    error: str | None = None
    has_profile: bool = False
    started: float = field(default_factory=time.perf_counter)


class Computer:
    """One computation at a time for one tab, on its own thread. :meth:`submit` returns at
    once; a newer request supersedes the running one (abandoned at its next stage) and any
    queued one, and a superseded request's results are never published."""

    def __init__(self, compute: Callable = redesign, *, on_profile: Callable[[int, Any], None] | None = None):
        self._compute = compute
        self._on_profile = on_profile
        self._cv = threading.Condition()
        self._next = 0
        self._pending: tuple | None = None
        self._snap: Snapshot | None = None
        self._final: Snapshot | None = None
        self._version = 0
        self._profile_version = 0  # the version that first had the running job's profile
        self._profile = None  # that profile (the design's, once fitted)
        self._thread: threading.Thread | None = None
        self._closed = False
        self.ran: list[int] = []  # the jobs the thread started (for the tests)

    # -- the request side
    def submit(self, gearset: GearSet, scene: str) -> int:
        from ..pipeline.design import planned_stages

        try:
            planned = planned_stages(gearset, scene=scene)
        except ProfilegenError:
            planned = ()
        with self._cv:
            self._next += 1
            job = self._next
            self._pending = (job, gearset, scene, planned)
            self._publish(Snapshot(job, 0, gearset, scene, planned=planned))
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="profilegen-app-compute", daemon=True)
                self._thread.start()
            self._cv.notify_all()
        return job

    @property
    def latest_job(self) -> int:
        return self._next

    def latest(self) -> Snapshot | None:
        with self._cv:
            return self._snap

    def newer(self, version, *, timeout: float) -> Snapshot | None:
        """The newest snapshot when its version differs from ``version`` (the one the page shows),
        waiting up to ``timeout`` s: at once for a finished design (or error) or a profile the page
        has not had, else at the timeout (the progress lines of a running design coalesce: each
        drawn one takes the interpreter from the computation); None if nothing new came."""
        end = time.monotonic() + timeout
        seen = version if isinstance(version, int) else 0
        with self._cv:
            while True:
                snap = self._snap
                fresh = snap if snap is not None and snap.version != version else None
                if fresh is not None and (fresh.done or self._profile_version > seen):
                    return fresh
                left = end - time.monotonic()
                if left <= 0 or self._closed:
                    return fresh
                self._cv.wait(left)

    @property
    def final(self) -> Snapshot | None:
        """The newest finished request's snapshot (a complete design or an error)."""
        with self._cv:
            return self._final

    def wait(self, job: int, *, profile: bool = True, timeout: float = 300.0) -> Snapshot | None:
        """The snapshot of ``job`` once it has its profile (``profile``) or is done; None when a
        newer request superseded it (or the wait timed out)."""
        end = time.monotonic() + timeout
        with self._cv:
            while True:
                if job != self._next:
                    return None
                snap = self._snap
                if snap is not None and snap.job == job and (snap.done or (profile and snap.has_profile)):
                    return snap
                left = end - time.monotonic()
                if left <= 0 or self._closed:
                    return None
                self._cv.wait(left)

    def close(self) -> None:
        with self._cv:
            self._closed = True
            self._pending = None
            self._next += 1  # whatever runs is superseded
            self._cv.notify_all()

    # -- the thread
    def _publish(self, snap: Snapshot) -> None:  # with the lock held
        if snap.job != self._next:
            return  # stale: a newer request came meanwhile
        self._version += 1
        snap = Snapshot(**{**snap.__dict__, "version": self._version})
        before = self._snap
        if snap.has_profile and not (before is not None and before.job == snap.job and before.has_profile):
            # a profile the page has not had: the engine's very object of the last one (a torque
            # change) is not new, and the request's wait goes on to the finished design
            profile = getattr(snap.design, "profile", None)
            if profile is None or profile is not self._profile:
                self._profile_version = self._version
            self._profile = profile
        self._snap = snap
        if snap.done:
            self._final = snap
        self._cv.notify_all()

    def _run(self) -> None:
        while True:
            with self._cv:
                while self._pending is None and not self._closed:
                    self._cv.wait()
                if self._closed:
                    return
                pending = self._pending
                if pending is None:  # not closed, so the wait above ended on a pending job
                    raise RuntimeError("Computer._run: woke with no job pending and not closed")
                job, gearset, scene, planned = pending
                self._pending = None
            self.ran.append(job)
            self._one(job, gearset, scene, planned)

    def _one(self, job, gearset, scene, planned) -> None:
        started, stages = time.perf_counter(), []
        base = dict(job=job, version=0, gearset=gearset, scene=scene, planned=planned, started=started)

        def progress(name: str) -> None:
            with self._cv:
                if job != self._next:
                    raise Superseded()
                stages.append(name)
                snap = self._snap
                keep = dict(design=snap.design, has_profile=snap.has_profile) if snap and snap.job == job else {}
                self._publish(Snapshot(**base, stages=tuple(stages), **keep))

        def partial(design) -> None:
            if self._on_profile is not None and design.profile is not None and job == self._next:
                snap = self._snap
                if not (snap is not None and snap.job == job and snap.has_profile):
                    try:  # before it is published: see Session(on_profile=...)
                        self._on_profile(job, design)
                    except Exception:  # noqa: BLE001 — a figure's failure must not fail the design
                        log.exception("profilegen app: the profile hook failed")
            with self._cv:
                self._publish(Snapshot(**base, design=design, stages=tuple(stages),
                                       has_profile=design.profile is not None))

        def stop() -> bool:  # read without the lock: an int compared at every checkpoint of the engine
            return job != self._next

        try:
            design = self._compute(gearset, scene, progress=progress, on_profile=partial, on_stage=partial, stop=stop)
        except (Superseded, Cancelled):
            return
        except ProfilegenError as exc:
            with self._cv:
                self._publish(Snapshot(**base, stages=tuple(stages), done=True, error=_one_line(exc)))
            return
        except Exception as exc:  # noqa: BLE001 — a bug of ours: the tab says so in one line, the log has it all
            log.exception("profilegen app: the design of %s failed", gearset.name)
            with self._cv:
                self._publish(Snapshot(**base, stages=tuple(stages), done=True,
                                       error=f"internal error ({type(exc).__name__}): {_one_line(exc)}"))
            return
        with self._cv:
            self._publish(Snapshot(**base, design=design, stages=tuple(stages), done=True, has_profile=True))


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= 600 else text[:597] + "..."


# ------------------------------------------------------------------------------------------ the tab

@dataclass(frozen=True)
class State:
    """What undo/redo moves between: the gear set and the scene."""

    gearset: GearSet
    scene: str

    def __eq__(self, other) -> bool:
        return (isinstance(other, State) and self.scene == other.scene
                and self.gearset.to_dict(include_defaults=False) == other.gearset.to_dict(include_defaults=False))

    __hash__ = None  # type: ignore[assignment]  # the usual way to say "unhashable" (object types it as a method)


class Session:
    """One browser tab: its history, its computer, its pinned design and its workspace."""

    def __init__(self, gearset: GearSet, scene: str, workspace: Workspace, *, compute: Callable = redesign,
                 on_profile: Callable[[Session, int, Any], None] | None = None):
        self.id = uuid.uuid4().hex
        self.workspace = workspace
        self.history = History(State(gearset, scene))
        self.computer = Computer(compute, on_profile=None if on_profile is None else
                                 lambda job, design: on_profile(self, job, design))
        self.lock = threading.RLock()
        self.fields = schema.form_fields(gearset)
        self.pinned: Snapshot | None = None  # the Snapshot pinned for A/B
        self.shown: Snapshot | None = None  # the last final snapshot drawn (the changes are against it)
        self.before: Snapshot | None = None  # the final one drawn before that
        self.errors: dict[str, str] = {}
        self.used = time.monotonic()
        self._profiles: OrderedDict[int, tuple[Any, int]] = OrderedDict()  # id(profile) -> (profile, token)
        self.profile_snap: Snapshot | None = None  # the newest snapshot with a profile (the figures' design)
        # the space figure the page shows: (its key, the whole figure, the view it opens with, the view
        # shown); the page gets its points thinned for the view (views.lighter), again at each zoom
        self.space: tuple | None = None
        self.figure_wait: int | None = None  # the request whose profile the figures' callback waits for
        self.prebuilt: tuple | None = None  # (design, figures) built as its profile came (on_profile)
        self.error_figure: tuple | None = None  # (key, the fit-error figure) of the CS space last sent
        self._clicks: dict[str, Any] = {}

    @property
    def gearset(self) -> GearSet:
        return self.history.current.gearset

    @property
    def scene(self) -> str:
        return self.history.current.scene

    def values(self) -> dict[str, Any]:
        return schema.current_values(self.gearset, self.fields)

    def edit(self, texts: dict[str, Any]) -> dict[str, str]:
        """Apply the form's texts: a new state (and a design request) when they make a valid
        gear set that differs; returns the reader's errors by field path (empty when fine)."""
        from ..errors import GearSetError

        with self.lock:
            try:
                gs, changes = schema.apply_form(self.gearset, self.fields, texts)
            except GearSetError as exc:
                self.errors = schema.errors_by_field(exc, [f.path for f in self.fields])
                return self.errors
            self.errors = {}
            if changes:
                self._set(State(gs, self.scene))
            return {}

    def set_scene(self, scene: str) -> None:
        with self.lock:
            self._set(State(self.gearset, scene))

    def load(self, name: str) -> GearSet:
        """A gear set from the workspace (``sets/a.toml``) or a bundled one (``bundled:default``)."""
        with self.lock:
            if name.startswith(BUNDLED):
                from ..gearset import list_profiles

                stem = name[len(BUNDLED):]
                if stem not in {p.stem for p in list_profiles()}:
                    raise WorkspaceError(f"{name}: no bundled gear set of that name")
                gs = load_gearset(stem)
            else:
                gs = self.workspace.load(name)
            self._set(State(gs, self.scene))
            return gs

    def undo(self) -> State:
        with self.lock:
            self.errors = {}
            state = self.history.undo()
            self.fields = schema.form_fields(state.gearset)
            return state

    def redo(self) -> State:
        with self.lock:
            self.errors = {}
            state = self.history.redo()
            self.fields = schema.form_fields(state.gearset)
            return state

    def _set(self, state: State) -> None:
        self.history.push(state)
        self.fields = schema.form_fields(state.gearset)

    def submit(self) -> int:
        with self.lock:
            return self.computer.submit(self.gearset, self.scene)

    def pin(self) -> Snapshot | None:
        """Pin the newest complete design (A); the next ones are drawn over it (B)."""
        with self.lock:
            final = self.computer.final
            self.pinned = final if final is not None and final.design is not None else None
            return self.pinned

    def unpin(self) -> None:
        with self.lock:
            self.pinned = None

    def clicked(self, button: str, n_clicks) -> None:
        """Pin or unpin for the page's click ``n_clicks`` of ``button`` ("pin", "unpin"), once: the
        page's callbacks that a click triggers each call this, whichever runs first acts."""
        with self.lock:
            if self._clicks.get(button) == n_clicks:
                return
            self._clicks[button] = n_clicks
            self.pin() if button == "pin" else self.unpin()

    def drawn(self, snap: Snapshot) -> None:
        """Note that ``snap`` was drawn: a new complete design moves the previous one to 'before'."""
        with self.lock:
            if snap.done and snap.design is not None and (self.shown is None or snap.job != self.shown.job):
                self.before, self.shown = self.shown, snap

    def profile_token(self, profile, job: int) -> int:
        """The job that first drew ``profile`` (this very object) among the tab's last few
        profiles, else ``job``: the figures are sent again only when the token changes — a torque
        change keeps the profile (the engine's cached object), so only the numbers and the verdict
        travel. The profiles are held here, so an id cannot be reused while it counts."""
        with self.lock:
            hit = self._profiles.get(id(profile))
            if hit is not None and hit[0] is profile:
                self._profiles.move_to_end(id(profile))
                return hit[1]
            self._profiles[id(profile)] = (profile, job)
            while len(self._profiles) > 8:
                self._profiles.popitem(last=False)
            return job

    def close(self) -> None:
        self.computer.close()


class Sessions:
    """The open tabs (the newest ``limit``; the least recently used is closed beyond that)."""

    def __init__(self, make: Callable[[], Session], *, limit: int = 16):
        self._make, self._limit = make, limit
        self._items: OrderedDict[str, Session] = OrderedDict()
        self._lock = threading.Lock()

    def new(self) -> Session:
        s = self._make()
        with self._lock:
            self._items[s.id] = s
            while len(self._items) > self._limit:
                _, old = self._items.popitem(last=False)
                old.close()
        return s

    def get(self, sid) -> Session | None:
        with self._lock:
            s = self._items.get(sid) if isinstance(sid, str) else None
            if s is not None:
                self._items.move_to_end(sid)
                s.used = time.monotonic()
            return s

    def close(self) -> None:
        with self._lock:
            for s in self._items.values():
                s.close()
            self._items.clear()
