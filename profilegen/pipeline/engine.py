"""The incremental engine: :func:`profilegen.design` with every stage's result kept and reused.

An :class:`Engine` runs the same pipeline as :func:`profilegen.design` (the same code: each
stage of :func:`profilegen.pipeline.design._design` is one lookup in the engine's stage cache), but a
stage whose inputs have not changed since an earlier design is taken from the cache instead of
run again. Each stage is keyed by what it reads (:data:`STAGE_INPUTS`): the gear-set sections,
the scene keys, its own arguments and its upstream stage's key — so

* a torque change re-solves the contact and the stresses only (the torques are read by no
  stage before them), and inside the contact stage it builds neither flank's points nor their
  compliance (:func:`reuse`: they read no torque);
* a tooth change starts at the tooth (the rim of the sketch and design scenes does not read it;
  the face stage, the envelope and everything after it do);
* a requirements change re-runs the stresses only (the checks carry their required values);
* a scene change re-runs the stages whose scene keys differ and those downstream of them.

Results are identical to an uncached :func:`profilegen.design`: a hit returns the objects the
stage made before (frozen results, read-only arrays), the warnings and stage reports it added,
in the same order (``tests/unit/test_engine.py``; the big randomized run is
``tests/benchmarks/engine_identity.py``). The stage times in a design's reports are those of
the run that computed the stage.

Memory is bounded: a least-recently-used cache with a byte budget (``memory_bytes``, default
:data:`DEFAULT_MEMORY_BYTES` or the environment's ``PROFILEGEN_ENGINE_MEMORY``, e.g. ``512M``),
each entry sized once when stored (its arrays and containers, walked).

Cancellation: :meth:`Engine.cancel` — or a newer :meth:`Engine.design` call from another thread,
which supersedes the running one — makes the running design raise :class:`Cancelled` at its next
checkpoint: before every stage, at every progress line and inside the pipeline's longer loops
(each fit method and each of its SLP steps, before the clearance maps, each flank's points and
its FS and CS compliance, each torque of the contact solves and of the torsional curve's
continuation; :func:`checkpoint` is the hook a stage's own loop may call). A stage without one
inside (the face stage, the rim FEM, a clearance map) runs to its end first:
``tests/benchmarks/engine.py --cancel`` measures the delay. One design runs at a time per engine
(``supersede=True``, the default); a superseding call waits for the running one to stop, then
runs. On an engine shared by threads (``supersede=False``) a design's own ``stop`` callable
(:meth:`Engine.design`) is its cancellation: the app's tabs pass "a newer request came".

In an interactive application, one engine per user (or browser tab), each change designed in a
worker thread; a change that arrives while one is designed supersedes it::

    engine = pg.Engine()
    def on_change(gearset):                       # called in a worker thread for each change
        try:
            design = engine.design(gearset, scene="sketch", progress=show_stage)
        except pg.Cancelled:
            return                                # a newer change took over
        show(design)                              # design.verdict, design.profile, ...

>>> import profilegen as pg
>>> engine = pg.Engine()
>>> gs = pg.load_gearset(pg.default_gearset_path())
>>> d1 = engine.design(gs, scene="sketch")
>>> d2 = engine.design(gs.with_values({"torque.rated_nm": 200.0}), scene="sketch")
>>> engine.last_run  # the stages the torque change ran (the sketch scene has no contact)
('stress',)
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import sys
import threading
import types
from collections import Counter, OrderedDict
from typing import TYPE_CHECKING, Any, Callable, cast

import numpy as np

from ..gearset import GearSet
from ..stagecache import STAGE_CACHE, checkpoint, reuse

if TYPE_CHECKING:  # pragma: no cover
    from .design import Design
    from .scenes import Scene

__all__ = ["Engine", "Cancelled", "checkpoint", "reuse", "STAGE_INPUTS", "DEFAULT_MEMORY_BYTES", "default_engine",
           "cached_design"]

log = logging.getLogger(__name__)

#: the cache's default byte budget (a design-scene design of the default set keeps ~71 MB of stage
#: results, 61 MB of them the sliced torsional curve's stacked flanks, kept for a torque change
#: (contact.face_curve.FaceSlices.apply); a sketch one ~6 MB: tests/benchmarks/engine.py prints them)
DEFAULT_MEMORY_BYTES = 1 << 30
MEMORY_ENV = "PROFILEGEN_ENGINE_MEMORY"

#: the gear-set sections (of ``GearSet.to_dict()``) no stage reads: the set's name and texts
_NOT_READ = ("name", "description", "source", "scene")
_ALL = ("gear", "tooth", "wave_generator", "material", "torque", "circular_spline", "cup", "face", "requirements")
_GEOMETRY = tuple(s for s in _ALL if s not in ("torque", "requirements"))

#: stage → (gear-set sections it reads, scene keys it reads). Its key is these, its arguments
#: (the rim tier, the envelope's chord, the fit method, whether the contact was asked for) and its
#: upstream stages' keys: tooth and rim → face (cup tiers) → envelope → gearform → arcfit →
#: contact → stress. The rim reads ``tooth`` too on the toothed tiers (:func:`_rim_sections`).
#: A section too many here costs a cache miss; one too few would be a wrong result, which the
#: randomized identity test (every float field edited) is there to catch.
STAGE_INPUTS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "tooth": (("gear", "tooth"), ()),
    "rim": (("gear", "wave_generator", "material", "cup", "face"), ()),  # and its tier (an argument)
    "face": (_GEOMETRY, ()),
    "envelope": (("gear", "tooth", "wave_generator"), ("n_t", "n_phi")),
    "gearform": (("gear", "tooth", "wave_generator", "circular_spline"),
                 ("chord_tol_mm", "n_t", "n_phi", "clearance_samples", "brute_force_check")),
    "arcfit": (("gear", "tooth", "wave_generator", "circular_spline"), ("fit_check_positions", "fit_starts")),
    "contact": (_GEOMETRY + ("torque",), ("contact", "ratcheting", "transmission_error", "face_slices")),
    "stress": (_ALL, ()),
}


class Cancelled(Exception):
    """The design was cancelled (:meth:`Engine.cancel`) or superseded by a newer
    :meth:`Engine.design` call. Deliberately not a ProfilegenError: no stage may take it for a
    failure of the design (the contact stage turns those into warnings)."""


# checkpoint() and reuse() live below the stages (profilegen.stagecache); the engine's API re-exports them


def _rim_sections(tier) -> tuple[str, ...]:
    sections = STAGE_INPUTS["rim"][0]
    model = getattr(tier, "model", None)
    if model is None:  # a tier name: the bundled tiers
        from ..rim.stage import RIM_TIERS

        model = getattr(RIM_TIERS.get(tier), "model", "toothed")
    if model == "ring theory":  # ω*, the waves and the module only: a material or cup change keeps it
        return ("gear", "wave_generator")
    return sections if model == "cup" else sections + ("tooth",)


def _digest(*parts) -> str:
    h = hashlib.blake2b(digest_size=16)
    for p in parts:
        h.update(p.encode() if isinstance(p, str) else repr(p).encode())
        h.update(b"\x1f")
    return h.hexdigest()


def _parse_size(text: str) -> int:
    text = text.strip().upper()
    scale = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30}.get(text[-1:], 1)
    try:
        value = float(text[:-1] if scale > 1 else text) * scale
    except ValueError:
        raise ValueError(f"{MEMORY_ENV} = {text!r}: must be a size in bytes, or with K, M or G (e.g. 512M)") from None
    if not value > 0:
        raise ValueError(f"{MEMORY_ENV} = {text!r}: must be > 0")
    return int(value)


_ATOMS = (str, bytes, int, float, complex, bool, type(None), np.generic)
_SKIP = (type, types.ModuleType, types.FunctionType, types.BuiltinFunctionType, types.MethodType)


#: a list or tuple longer than this, of objects of a few classes (not numbers or strings), is measured
#: by a sample of this many of them, scaled (a CS outline's ~2 800 arcs and lines: 7 ms walked one by
#: one, ~3 % of a sketch-scene design)
_SAMPLED = 64


def _objects(items) -> bool:
    """True when ``items`` are objects of at most four classes, none a number, string or array."""
    kinds = set(map(type, items))
    return len(kinds) <= 4 and not any(issubclass(k, _ATOMS + (np.ndarray,)) for k in kinds)


def nbytes(value) -> int:
    """An estimate of the memory ``value`` holds: its numpy arrays' buffers and every container,
    dataclass (slots or dict) and object reached from it, each counted once; a long list or tuple
    of objects of a few classes by :data:`_SAMPLED` of them, scaled (the buffers behind their
    array views once when a few are shared by all of them)."""
    return _walk([value], set())


def _walk(stack: list, seen: set[int], bases: list | None = None) -> int:
    """The sizes of what ``stack`` reaches (not in ``seen``); with ``bases``, the buffers behind
    array views are put there instead of counted."""
    total = 0
    while stack:
        o = stack.pop()
        if id(o) in seen or isinstance(o, _SKIP):
            continue
        seen.add(id(o))
        if isinstance(o, np.ndarray):
            if o.base is None:
                total += o.nbytes
            else:
                (stack if bases is None else bases).append(o.base)
            total += 112
            continue
        try:
            total += sys.getsizeof(o)
        except TypeError:
            total += 64
        if isinstance(o, _ATOMS):
            continue
        if isinstance(o, dict):
            stack.extend(o.keys())
            stack.extend(o.values())
        elif isinstance(o, (list, tuple)) and len(o) > _SAMPLED and _objects(o):
            pick = o[:: len(o) // _SAMPLED][:_SAMPLED]
            scale = len(o) / len(pick)
            behind: list = []
            total += int(_walk(list(pick), seen, behind) * scale)
            # the buffers behind the sample's array views: a few shared by all the items (a CS
            # outline's rows of one array per element of its space) count once, else each item's own
            buffers = list({id(b): b for b in behind}.values())
            shared = 4 * len(buffers) <= len(pick)
            total += int(_walk(buffers, seen) * (1.0 if shared else scale))  # (the walk empties the list)
        elif isinstance(o, (list, tuple, set, frozenset)):
            stack.extend(o)
        else:
            d = getattr(o, "__dict__", None)
            if d is not None:
                stack.append(d)
            for cls in type(o).__mro__:
                for slot in getattr(cls, "__slots__", ()):
                    if slot not in ("__dict__", "__weakref__"):
                        try:
                            stack.append(getattr(o, slot))
                        except AttributeError:
                            pass
    return total


class _Run:
    """One :meth:`Engine.design` call: the stage lookups of :func:`profilegen.pipeline.design._stage`
    (this object is :data:`profilegen.stagecache.STAGE_CACHE` while it runs) and its checkpoint."""

    def __init__(self, engine: "Engine", generation: int, stop: Callable[[], bool] | None = None):
        self.engine, self.generation, self.stop = engine, generation, stop
        self.ran: list[str] = []
        self._sections: tuple[GearSet, dict] | None = None

    def checkpoint(self) -> None:
        if self.engine._generation != self.generation:
            raise Cancelled("the design was cancelled (Engine.cancel, or a newer Engine.design call)")
        if self.stop is not None and self.stop():
            raise Cancelled("the design was cancelled (its stop() said so)")

    def _section_digests(self, gearset: GearSet) -> dict:
        if self._sections is None or self._sections[0] is not gearset:
            data = gearset.to_dict()
            self._sections = (gearset, {k: _digest(json.dumps(v, sort_keys=True)) for k, v in data.items()
                                        if k not in _NOT_READ})
        return self._sections[1]

    def key(self, name: str, parent, gearset: GearSet, scene, extra: tuple) -> str:
        sections, scene_keys = STAGE_INPUTS[name]
        if name == "rim":
            sections = _rim_sections(extra[0])
        digests = self._section_digests(gearset)
        return _digest(name, [(s, digests[s]) for s in sections], [(k, getattr(scene, k)) for k in scene_keys],
                       extra, parent)

    def reuse(self, name: str, compute: Callable, gearset: GearSet, sections: tuple[str, ...], key: tuple,
              owners: tuple):
        """:func:`reuse` inside this run (see there)."""
        self.checkpoint()
        digests = self._section_digests(gearset)
        k = _digest("reuse", name, [(s, digests[s]) for s in sections], key, [id(o) for o in owners])
        found, entry = self.engine._get(k)
        held = cast("tuple[tuple, Any] | None", entry)  # a "reuse" key holds (owners, value): the _put below
        if found and held is not None and all(a is b for a, b in zip(held[0], owners)):
            with self.engine._lock:
                self.engine.hits[name] += 1
            return held[1]
        value = compute()
        with self.engine._lock:
            self.engine.runs[name] += 1
        self.engine._put(k, (tuple(owners), value), size=nbytes(value))
        return value

    def stage(self, name: str, parent, compute: Callable, gearset: GearSet, scene, extra: tuple,
              on_hit: Callable[[], None] | None):
        self.checkpoint()
        key = self.key(name, parent, gearset, scene, extra)
        found, value = self.engine._get(key)
        if found:
            with self.engine._lock:
                self.engine.hits[name] += 1
            if on_hit is not None:
                on_hit()
            return value, key
        value = compute()
        with self.engine._lock:
            self.engine.runs[name] += 1
        self.ran.append(name)
        self.engine._put(key, value)
        return value, key


class Engine:
    """:func:`profilegen.design` with a stage cache (see the module docstring).

    ``memory_bytes``: the cache's budget (default :data:`DEFAULT_MEMORY_BYTES`, or
    ``PROFILEGEN_ENGINE_MEMORY``); 0 keeps nothing (every stage runs, as :func:`profilegen.design`).
    ``supersede``: a :meth:`design` call cancels the one running (the interactive use: one engine
    per user or browser tab; designs run one at a time); False: calls from several threads run
    side by side and share the cache (a thread-pool sweep; :meth:`cancel` stops them all).

    Attributes: ``runs`` and ``hits`` (Counters, stage name → stage executions / cache hits since
    the engine was made), ``last_run`` (the stages the last design to finish ran, in order), ``stats()``.
    Thread-safe: :meth:`design` may be called from any thread (one runs at a time; a newer call
    supersedes the running one), :meth:`cancel` from any thread.
    """

    def __init__(self, *, memory_bytes: int | None = None, supersede: bool = True):
        if memory_bytes is None:
            env = os.environ.get(MEMORY_ENV)
            memory_bytes = _parse_size(env) if env else DEFAULT_MEMORY_BYTES
        if isinstance(memory_bytes, bool) or not isinstance(memory_bytes, (int, np.integer)) or memory_bytes < 0:
            raise ValueError(f"memory_bytes must be an integer >= 0, got {memory_bytes!r}")
        self.memory_bytes = int(memory_bytes)
        self.supersede = bool(supersede)
        self._cache: OrderedDict[str, tuple[object, int]] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()  # the cache and the generation
        self._running = threading.Lock()  # one design at a time
        self._generation = 0
        self.runs: Counter = Counter()
        self.hits: Counter = Counter()
        self.last_run: tuple[str, ...] = ()

    # ------------------------------------------------------------------ the public API
    def design(self, gearset: GearSet, *, scene: str | os.PathLike | Scene | None = None, fit_method: str | None = None,
               progress: Callable[[str], None] | None = None, contact: bool | None = None, stress: bool = True,
               on_profile: Callable[[Design], None] | None = None, on_stage: Callable[[Design], None] | None = None,
               stop: Callable[[], bool] | None = None) -> Design:
        """:func:`profilegen.design` with the same arguments and the same result, reusing every
        stage whose inputs an earlier design of this engine had. Raises :class:`Cancelled` when
        :meth:`cancel` is called, or a newer :meth:`design` starts, before it finishes — or when
        ``stop()`` returns True at a checkpoint: this one design's own cancellation, for callers
        that share an engine (``supersede=False``: the app's tabs, each superseding only its own
        designs; ``stop`` is called at every checkpoint, so it must be quick)."""
        from . import design as pipeline

        with self._lock:
            if self.supersede:
                self._generation += 1  # supersedes a running design: it stops at its next checkpoint
            generation = self._generation
        with self._running if self.supersede else contextlib.nullcontext():
            run = _Run(self, generation, stop)
            run.checkpoint()  # superseded while it waited
            say = progress

            def checked(name: str) -> None:
                run.checkpoint()
                if say is not None:
                    say(name)

            token = STAGE_CACHE.set(run)
            try:
                return pipeline.design(gearset, scene=scene, fit_method=fit_method, progress=checked,
                                       contact=contact, stress=stress, on_profile=on_profile, on_stage=on_stage)
            finally:
                STAGE_CACHE.reset(token)
                self.last_run = tuple(run.ran)

    def cancel(self) -> None:
        """Stop the running design (if any) at its next checkpoint: it raises :class:`Cancelled`.
        A design started after this call runs normally."""
        with self._lock:
            self._generation += 1

    def clear(self) -> None:
        """Forget every cached stage result."""
        with self._lock:
            self._cache.clear()
            self._bytes = 0

    def stats(self) -> dict:
        """{'entries', 'bytes', 'memory_bytes', 'runs', 'hits'}: the cache as it stands."""
        with self._lock:
            return {"entries": len(self._cache), "bytes": self._bytes, "memory_bytes": self.memory_bytes,
                    "runs": dict(self.runs), "hits": dict(self.hits)}

    # ------------------------------------------------------------------ the LRU
    def _get(self, key: str) -> tuple[bool, object]:
        with self._lock:
            hit = self._cache.get(key)
            if hit is None:
                return False, None
            self._cache.move_to_end(key)
            return True, hit[0]

    def _put(self, key: str, value, size: int | None = None) -> None:
        if self.memory_bytes <= 0:
            return
        size = nbytes(value) if size is None else size
        if size > self.memory_bytes:
            log.info("engine: a stage result of %d bytes is over the budget of %d: not kept", size, self.memory_bytes)
            return
        with self._lock:
            old = self._cache.pop(key, None)
            if old is not None:
                self._bytes -= old[1]
            self._cache[key] = (value, size)
            self._bytes += size
            while self._bytes > self.memory_bytes:
                _, (_, dropped) = self._cache.popitem(last=False)
                self._bytes -= dropped


_DEFAULT: Engine | None = None
_DEFAULT_LOCK = threading.Lock()


def default_engine() -> Engine:
    """This process's shared engine, ``Engine(supersede=False)``: designs from several threads run
    side by side (made on first use; a forked child starts with a new one)."""
    global _DEFAULT
    with _DEFAULT_LOCK:
        if _DEFAULT is None:
            _DEFAULT = Engine(supersede=False)
        return _DEFAULT


def _forget_default() -> None:
    global _DEFAULT, _DEFAULT_LOCK
    _DEFAULT, _DEFAULT_LOCK = None, threading.Lock()


os.register_at_fork(after_in_child=_forget_default)


def cached_design(gearset: GearSet, **options):
    """``default_engine().design(gearset, **options)``: a module-level function (it pickles), the
    designer of sweeps and the optimiser."""
    return default_engine().design(gearset, **options)
