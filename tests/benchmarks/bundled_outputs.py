"""The bundled gear sets' output files, before and after a change (issue 26: "outputs of the
bundled sets unchanged, files compared before/after").

    python tests/benchmarks/bundled_outputs.py run OUT [--sets NAME ...]
    python tests/benchmarks/bundled_outputs.py compare A B [--rel 1e-12] [--show 5]
    python tests/benchmarks/bundled_outputs.py at COMMIT OUT [--sets NAME ...]
    python tests/benchmarks/bundled_outputs.py against COMMIT [--keep DIR]   # HEAD's tree vs COMMIT's

``run`` designs every bundled gear set (``profiles/*.toml``) in its own default scene with
``profilegen design NAME --out OUT/NAME -q``, in a subprocess whose PYTHONPATH is the source
tree's root (so the tree's own package runs, not the editable install), under a 4 GB
address-space cap. ``at`` does the same in the tree of another commit: ``git archive COMMIT``
unpacked into a temporary folder (the files of a ``git worktree`` at that commit, without touching
the repository's worktree list), run from there, then removed. ``against COMMIT`` runs HEAD's
committed tree and COMMIT's tree and compares them.

``compare`` walks both folders and compares every file of the same relative path by what it
means, not byte for byte:

* JSON: the same keys and list lengths; numbers equal to ``--rel`` (1e-12) relative (and
  1e-300 absolute: exact zeros); texts equal. Keys that are run times or environment
  (``*time_s``, ``*_s`` of a timing table, ``seconds``, ``version``, ``python``, ``host``,
  ``created``, ``started``, ``timestamp``, paths) are skipped, and a time quoted in a text
  ("FEM solve 1.294 s") is masked.
* CSV: the same rows and columns; cells that are both numbers to ``--rel``, others equal.
* DXF: read with ezdxf; the modelspace entities and each block's, in order: the same types,
  layers and every numeric DXF attribute to ``--rel`` (points component by component), text
  contents equal.
* TOML, TXT, MD, CSV-like text, STEP: the lines, with their numbers to ``--rel`` (the STEP
  header's ``FILE_NAME`` line, which holds the time, skipped).
* PNG, SVG, HTML, PDF: present in both (their bytes hold figures and times).

Prints one line per file (same / differs / only in A / only in B) with the first ``--show``
differences of each, then the counts. Exits 1 if anything differs.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PRESENCE_ONLY = {".png", ".svg", ".html", ".pdf", ".jpg"}
SKIP_KEY = re.compile(r"(^|_)(time|times|seconds|elapsed|version|versions|python|host|hostname|created|started|"
                      r"finished|timestamp|date|path|cwd|pid|wall)(_s)?$|_s$", re.I)
SECONDS = re.compile(r"\b\d+(?:\.\d+)? s\b")
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


# --------------------------------------------------------------------------- running the designs


def bundled_sets(tree: Path) -> list[str]:
    return sorted(p.stem for p in (tree / "profiles").glob("*.toml"))


def _cap():
    cap = 4 * 1024**3
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def run(tree: Path, out: Path, sets: list[str] | None = None) -> dict:
    """Design each bundled set of ``tree`` into ``out``/NAME with ``tree``'s own package."""
    out.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "PYTHONPATH": str(tree), "PYTHONDONTWRITEBYTECODE": "1", "MPLBACKEND": "Agg"}
    where = subprocess.run([sys.executable, "-c", "import profilegen; print(profilegen.__file__)"], cwd=tree, env=env,
                           capture_output=True, text=True, check=True).stdout.strip()
    if not Path(where).resolve().is_relative_to(tree.resolve()):
        raise SystemExit(f"the tree {tree} imports profilegen from {where}: its own package would not run")
    results = {}
    for name in sets or bundled_sets(tree):
        t0 = time.perf_counter()
        p = subprocess.run([sys.executable, "-m", "profilegen", "design", str(tree / "profiles" / f"{name}.toml"),
                            "--out", str(out / name), "-q"], cwd=tree, env=env, capture_output=True, text=True,
                           preexec_fn=_cap, timeout=1800)
        dt = time.perf_counter() - t0
        last = (p.stderr.strip().splitlines() or [""])[-1]
        results[name] = {"exit": p.returncode, "seconds": round(dt, 1), "stderr": last[:300]}
        print(f"  {name:24s} exit {p.returncode} in {dt:5.1f} s  {last[:120]}", flush=True)
    (out / "bundled_outputs_run.json").write_text(json.dumps({"tree": str(tree), "sets": results}, indent=1))
    return results


def at_commit(commit: str, out: Path, sets: list[str] | None = None) -> dict:
    """``run`` in the tree of ``commit`` (git archive into a temporary folder)."""
    sha = subprocess.run(["git", "rev-parse", "--short", commit], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout.strip()
    with tempfile.TemporaryDirectory(prefix=f"profilegen-{sha}-") as tmp:
        tree = Path(tmp)
        archive = subprocess.run(["git", "archive", sha], cwd=ROOT, capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(tree)], input=archive, check=True)
        print(f"{sha}: the bundled sets into {out}", flush=True)
        return run(tree, out, sets)


# --------------------------------------------------------------------------- comparing


def _close(a: float, b: float, rel: float) -> bool:
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b or math.isclose(a, b, rel_tol=rel, abs_tol=1e-300)


def _num(text: str):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def compare_json(a, b, rel: float, where: str = "") -> list[str]:
    out = []
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            if SKIP_KEY.search(str(k)):
                continue
            if k not in a or k not in b:
                out.append(f"{where}/{k}: only in {'B' if k not in a else 'A'}")
                continue
            out += compare_json(a[k], b[k], rel, f"{where}/{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: {len(a)} items against {len(b)}"]
        for i, (x, y) in enumerate(zip(a, b)):
            out += compare_json(x, y, rel, f"{where}[{i}]")
            if len(out) > 50:
                break
        return out
    num = (int, float)
    if isinstance(a, num) and isinstance(b, num) and not isinstance(a, bool) and not isinstance(b, bool):
        return [] if _close(float(a), float(b), rel) else [f"{where}: {a!r} against {b!r}"]
    if isinstance(a, str) and isinstance(b, str) and SECONDS.sub("# s", a) == SECONDS.sub("# s", b):
        return []  # a text that differs only in a time it quotes ("FEM solve 1.294 s (9 Newton iterations)")
    return [] if a == b else [f"{where}: {str(a)[:80]!r} against {str(b)[:80]!r}"]


def compare_csv(pa: Path, pb: Path, rel: float) -> list[str]:
    ra = list(csv.reader(pa.open(newline="", encoding="utf-8")))
    rb = list(csv.reader(pb.open(newline="", encoding="utf-8")))
    if len(ra) != len(rb):
        return [f"{len(ra)} rows against {len(rb)}"]
    head = ra[0] if ra else []
    out = []
    for i, (x, y) in enumerate(zip(ra, rb)):
        if len(x) != len(y):
            out.append(f"row {i}: {len(x)} cells against {len(y)}")
            continue
        for j, (u, v) in enumerate(zip(x, y)):
            if j < len(head) and i > 0 and SKIP_KEY.search(head[j]):
                continue
            nu, nv = _num(u), _num(v)
            same = _close(nu, nv, rel) if nu is not None and nv is not None else u == v
            if not same:
                out.append(f"row {i} {head[j] if j < len(head) else j}: {u[:40]!r} against {v[:40]!r}")
        if len(out) > 50:
            break
    return out


def compare_text(pa: Path, pb: Path, rel: float) -> list[str]:
    la = pa.read_text(encoding="utf-8", errors="replace").splitlines()
    lb = pb.read_text(encoding="utf-8", errors="replace").splitlines()
    if len(la) != len(lb):
        return [f"{len(la)} lines against {len(lb)}"]
    out = []
    for i, (x, y) in enumerate(zip(la, lb)):
        if x == y or (x.startswith("FILE_NAME") and y.startswith("FILE_NAME")):
            continue
        if NUMBER.sub("#", x) == NUMBER.sub("#", y) and all(
                _close(float(u), float(v), rel) for u, v in zip(NUMBER.findall(x), NUMBER.findall(y))):
            continue
        out.append(f"line {i + 1}: {x[:70]!r} against {y[:70]!r}")
        if len(out) > 50:
            break
    return out


def _entities(doc):
    yield "modelspace", list(doc.modelspace())
    for block in doc.blocks:
        if not block.name.startswith("*"):
            yield f"block {block.name}", list(block)


def _attribs(e) -> dict:
    out = {}
    for key, value in e.dxfattribs().items():
        if key in ("handle", "owner"):
            continue
        out[key] = tuple(value) if hasattr(value, "__iter__") and not isinstance(value, str) else value
    if e.dxftype() in ("LWPOLYLINE",):
        out["points"] = tuple(tuple(p) for p in e.get_points())
    elif e.dxftype() in ("POLYLINE",):
        out["points"] = tuple(tuple(v.dxf.location) for v in e.vertices)
    elif e.dxftype() in ("SPLINE",):
        out["points"] = tuple(tuple(p) for p in e.control_points) + tuple(tuple(p) for p in e.fit_points)
    elif e.dxftype() in ("MTEXT",):
        out["text"] = e.text
    return out


def _same_value(x, y, rel: float) -> bool:
    if isinstance(x, tuple) and isinstance(y, tuple):
        return len(x) == len(y) and all(_same_value(u, v, rel) for u, v in zip(x, y))
    if isinstance(x, (int, float)) and isinstance(y, (int, float)):
        return _close(float(x), float(y), rel)
    return x == y


def compare_dxf(pa: Path, pb: Path, rel: float) -> list[str]:
    import ezdxf

    da, db = ezdxf.readfile(pa), ezdxf.readfile(pb)
    out = []
    groups_b = dict(_entities(db))
    for name, ents_a in _entities(da):
        ents_b = groups_b.pop(name, None)
        if ents_b is None:
            out.append(f"{name}: only in A")
            continue
        if len(ents_a) != len(ents_b):
            out.append(f"{name}: {len(ents_a)} entities against {len(ents_b)}")
            continue
        for k, (ea, eb) in enumerate(zip(ents_a, ents_b)):
            if ea.dxftype() != eb.dxftype():
                out.append(f"{name} #{k}: {ea.dxftype()} against {eb.dxftype()}")
                continue
            aa, ab = _attribs(ea), _attribs(eb)
            for key in sorted(set(aa) | set(ab)):
                if not _same_value(aa.get(key), ab.get(key), rel):
                    out.append(f"{name} #{k} {ea.dxftype()}.{key}: {str(aa.get(key))[:60]} against "
                               f"{str(ab.get(key))[:60]}")
                    break
            if len(out) > 50:
                return out
    out += [f"{name}: only in B" for name in groups_b]
    return out


def compare_file(pa: Path, pb: Path, rel: float) -> tuple[str, list[str]]:
    ext = pa.suffix.lower()
    try:
        if ext in PRESENCE_ONLY:
            return "present", []
        if ext == ".json":
            return "json", compare_json(json.loads(pa.read_text()), json.loads(pb.read_text()), rel)
        if ext == ".csv":
            return "csv", compare_csv(pa, pb, rel)
        if ext == ".dxf":
            return "dxf", compare_dxf(pa, pb, rel)
        return "text", compare_text(pa, pb, rel)
    except Exception as exc:  # noqa: BLE001 — a file that cannot be read is a difference, said so
        return "error", [f"cannot compare: {type(exc).__name__}: {exc}"[:200]]


def compare(a: Path, b: Path, rel: float = 1e-12, show: int = 5) -> int:
    files_a = {p.relative_to(a) for p in a.rglob("*") if p.is_file() and p.name != "bundled_outputs_run.json"}
    files_b = {p.relative_to(b) for p in b.rglob("*") if p.is_file() and p.name != "bundled_outputs_run.json"}
    counts = {"same": 0, "differs": 0, "only in A": 0, "only in B": 0}
    for rel_path in sorted(files_a | files_b):
        if rel_path not in files_b or rel_path not in files_a:
            which = "only in A" if rel_path not in files_b else "only in B"
            counts[which] += 1
            print(f"{which:10s} {rel_path}")
            continue
        kind, diffs = compare_file(a / rel_path, b / rel_path, rel)
        if diffs:
            counts["differs"] += 1
            print(f"{'differs':10s} {rel_path} ({kind}, {len(diffs)}{'+' if len(diffs) > 50 else ''} differences)")
            for d in diffs[:show]:
                print(f"{'':12s}{d}")
        else:
            counts["same"] += 1
            print(f"{'same':10s} {rel_path} ({kind})")
    print("\n" + ", ".join(f"{k}: {v}" for k, v in counts.items()) + f" (numbers to rel {rel:g}; PNG/SVG/HTML/PDF by "
          "presence)")
    return 0 if counts["differs"] == counts["only in A"] == counts["only in B"] == 0 else 1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="design every bundled set in its default scene into OUT (this tree)")
    r.add_argument("out", type=Path)
    r.add_argument("--sets", nargs="+")
    c = sub.add_parser("compare", help="compare two such folders file by file")
    c.add_argument("a", type=Path)
    c.add_argument("b", type=Path)
    c.add_argument("--rel", type=float, default=1e-12)
    c.add_argument("--show", type=int, default=5)
    t = sub.add_parser("at", help="run in the tree of COMMIT (git archive into a temporary folder)")
    t.add_argument("commit")
    t.add_argument("out", type=Path)
    t.add_argument("--sets", nargs="+")
    g = sub.add_parser("against", help="HEAD's committed tree against COMMIT's: run both, compare")
    g.add_argument("commit")
    g.add_argument("--keep", type=Path, help="keep the two folders here (default: a temporary folder)")
    g.add_argument("--sets", nargs="+")
    g.add_argument("--rel", type=float, default=1e-12)
    args = ap.parse_args(argv)
    if args.cmd == "run":
        res = run(ROOT, args.out, args.sets)
        return 0 if all(v["exit"] == 0 for v in res.values()) else 1
    if args.cmd == "compare":
        return compare(args.a, args.b, args.rel, args.show)
    if args.cmd == "at":
        res = at_commit(args.commit, args.out, args.sets)
        return 0 if all(v["exit"] == 0 for v in res.values()) else 1
    base = args.keep or Path(tempfile.mkdtemp(prefix="bundled-outputs-"))
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                          check=True).stdout.strip()
    at_commit(args.commit, base / "before", args.sets)
    at_commit(head, base / "after", args.sets)
    print(f"\n{args.commit} (A) against {head} (B):")
    code = compare(base / "before", base / "after", args.rel)
    if args.keep is None:
        shutil.rmtree(base, ignore_errors=True)
    return code


if __name__ == "__main__":
    raise SystemExit(main())
