"""Files and figures of an optimisation run (:mod:`profilegen.studies.optimize`): a gear set as TOML,
the Pareto-front figure and the report page comparing the front with the starting design.

Everything takes plain data (rows as dicts, names, numbers): this module does not import
the optimiser.
"""

from __future__ import annotations

import html
import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

from .export import atomic_write

__all__ = ["front_figure", "front_in_words", "gearset_toml", "optimize_report_html", "write_gearset_toml"]


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)  # shortest round-trip form, valid TOML (1e-05, 0.9, 209000.0)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a TOML basic string: JSON's escapes are TOML's
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write a {type(value).__name__} as a TOML value")


def comment_text(text) -> str:
    """A text for one TOML comment line: control characters shown as '?'."""
    return re.sub(r"[\x00-\x1f\x7f\x85\u2028\u2029]", "?", str(text))


def gearset_toml(data: Mapping, *, header: Sequence[str] = ()) -> str:
    """A gear set's dict (:meth:`GearSet.to_dict`: top-level keys, then one table per section)
    as TOML text; values None are left out (their defaults apply). ``header``: comment lines,
    each kept on its line (a control character — a line break would end the comment and start
    TOML — is written as ``?``)."""
    lines = [f"# {comment_text(h)}" for h in header]
    scalars = {k: v for k, v in data.items() if not isinstance(v, Mapping)}
    tables = {k: v for k, v in data.items() if isinstance(v, Mapping)}
    for key, value in scalars.items():
        if value is not None:
            lines.append(f"{key} = {_toml_value(value)}")
    for name, table in tables.items():
        lines.append("")
        lines.append(f"[{name}]")
        for key, value in table.items():
            if isinstance(value, Mapping):
                raise TypeError(f"{name}.{key}: nested tables are not part of the gear-set schema")
            if value is not None:
                lines.append(f"{key} = {_toml_value(value)}")
    return "\n".join(lines) + "\n"


def write_gearset_toml(data: Mapping, path: str | os.PathLike, *, header: Sequence[str] = ()) -> Path:
    """Write :func:`gearset_toml` atomically; returns the path."""
    path = Path(path)
    with atomic_write(path) as f:
        f.write(gearset_toml(data, header=header))
    return path


def front_figure(objectives: Sequence[tuple[str, str]], evaluated: Sequence[Mapping], front: Sequence[Mapping],
                 start: Mapping | None, *, confirm_label: str | None = None, title: str = "",
                 path: str | os.PathLike | None = None, ax=None):
    """The search in objective space, one panel per pair of objectives (one panel for two):
    every feasible candidate (grey), the infeasible ones (red crosses), the front (blue), the
    front confirmed in the fine scene (open squares, keys ``confirm_<output>``; red: infeasible
    there, ``confirm_feasible``) and the
    starting design (star; its confirmed value a open star). ``objectives``: (output, sense).
    Returns the first Axes, or ``path`` when given (PNG, atomically)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    names = [o for o, _ in objectives]
    pairs: list[tuple[str, str | None]] = [(names[i], names[j]) for i in range(len(names))
                                           for j in range(i + 1, len(names))] or [(names[0], None)]
    if ax is None:
        fig = Figure(figsize=(4.6 * len(pairs), 4.0), layout="constrained")
        FigureCanvasAgg(fig)
        axes = [fig.add_subplot(1, len(pairs), k + 1) for k in range(len(pairs))]
    else:
        fig, axes = ax.figure, [ax]

    def xy(rows, a, b, prefix=""):
        pts = [(r.get(prefix + a), r.get(prefix + b) if b else 0.0) for r in rows]
        return [(x, y) for x, y in pts if x is not None and y is not None]

    for axis, (a, b) in zip(axes, pairs):
        feas = xy([r for r in evaluated if r.get("feasible")], a, b)
        infeas = xy([r for r in evaluated if not r.get("feasible") and r.get("status") == "ok"], a, b)
        if feas:
            axis.plot(*zip(*feas), ".", color="#9a9a9a", markersize=4, label=f"feasible ({len(feas)})")
        if infeas:
            axis.plot(*zip(*infeas), "x", color="#d62728", markersize=4, label=f"infeasible ({len(infeas)})")
        pf = sorted(xy(front, a, b))
        if pf:
            axis.plot(*zip(*pf), "o", color="#1f5fbf", markersize=6, label=f"front ({len(pf)})")
        if confirm_label:
            cf = xy([r for r in front if r.get("confirm_feasible")], a, b, prefix="confirm_")
            if cf:
                axis.plot(*zip(*cf), "s", mfc="none", color="#1f5fbf", markersize=7,
                          label=f"front, {confirm_label} scene ({len(cf)})")
            cf = xy([r for r in front if not r.get("confirm_feasible")], a, b, prefix="confirm_")
            if cf:
                axis.plot(*zip(*cf), "s", mfc="none", color="#d62728", markersize=9,
                          label=f"front, infeasible in the {confirm_label} scene ({len(cf)})")
        if start is not None:
            s = xy([start], a, b)
            if s:
                axis.plot(*zip(*s), "*", color="#e08a00", markersize=14, label="starting design")
            s = xy([start], a, b, prefix="confirm_")
            if confirm_label and s:
                axis.plot(*zip(*s), "*", mfc="none", color="#e08a00", markersize=14,
                          label=f"starting design, {confirm_label}")
        sense = dict(objectives)
        axis.set_xlabel(f"{a} ({sense[a]})")
        axis.set_ylabel(f"{b} ({sense[b]})" if b else "")
        axis.grid(True, linewidth=0.4, alpha=0.5)
        axis.legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=9)
    if path is None:
        return axes[0]
    path = Path(path)
    with atomic_write(path, "wb") as handle:
        fig.savefig(handle, format="png", dpi=120)
    return path


def _fmt(v) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, Mapping):
        return html.escape(", ".join(f"{k}: {x}" for k, x in v.items()))
    if isinstance(v, (list, tuple)):
        return html.escape("; ".join(str(x) for x in v))
    return html.escape(str(v))


def _verdict_text(r: Mapping) -> str | None:
    verdict = r.get("confirm_verdict", r.get("verdict"))
    failed = r.get("confirm_failed_checks", r.get("failed_checks"))
    return None if verdict is None else (f"{verdict}: {failed}" if failed else str(verdict))


def _num(v) -> str:
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def front_in_words(front: Sequence[Mapping], start: Mapping | None, *, variables: Sequence[str],
                   objectives: Sequence[tuple[str, str]]) -> list[str]:
    """One sentence per front design: which variables it changes from the starting design (from →
    to), what it gains and gives up in each objective (confirmed values where there are, in
    %), and its verdict — infeasible ones said so first."""
    lines = []
    for k, r in enumerate(front):
        changes = [f"{v} {_num(start.get(v))} → {_num(r.get(v))}" for v in variables
                   if start is not None and r.get(v) is not None and r.get(v) != start.get(v)]
        gains: list[str] = []
        costs: list[str] = []
        for o, sense in objectives:
            s = None if start is None else start.get(f"confirm_{o}", start.get(o))
            v = r.get(f"confirm_{o}", r.get(o))
            if s is None or v is None:
                continue
            rel = (v - s) / abs(s) * 100 if s else None
            better = (v > s) if sense == "max" else (v < s)
            text = f"{o} {_num(s)} → {_num(v)}" + (f" ({rel:+.1f} %)" if rel is not None else "")
            (gains if better else costs if v != s else []).append(text)
        feasible = r.get("confirm_feasible", r.get("feasible"))
        head = f"#{k + 1}: " + ("INFEASIBLE — " + str(r.get("confirm_reason") or r.get("reason") or "")
                                + "; " if feasible is False else "")
        body = ("changes " + ", ".join(changes) if changes else "changes nothing from the starting design")
        body += ("; buys " + ", ".join(gains)) if gains else "; buys nothing over the starting design"
        if costs:
            body += "; gives up " + ", ".join(costs)
        verdict = _verdict_text(r)
        if verdict:
            body += f"; verdict {verdict}"
        lines.append(head + body + ".")
    return lines


def optimize_report_html(summary: Mapping, front: Sequence[Mapping], start: Mapping | None, *,
                         variables: Sequence[str], objectives: Sequence[tuple[str, str]],
                         constraints: Sequence[str], figure: str | None, path: str | os.PathLike) -> Path:
    """The report page: the run's settings and counts (``summary``), the figure, and a table
    of the starting design and each front design — variables, objectives in the search and
    the confirm scene with the change against the starting design (+ = better), the
    constraints, whether it dominates the starting design. Written atomically."""
    title = f"profilegen optimize: {summary.get('name', '')}"
    rows = []
    head = ["design", *variables]
    for o, sense in objectives:
        head += [f"{o} ({sense})", f"{o} confirmed", "change vs start"]
    head += [*constraints, "verdict (confirmed)", "feasible (confirmed)", "dominates start", "gear set"]

    def change(o, sense, r):
        s = None if start is None else start.get(f"confirm_{o}", start.get(o))
        v = r.get(f"confirm_{o}", r.get(o))
        if s is None or v is None or s == 0:
            return "—"
        gain = (v - s) / abs(s) * (1 if sense == "max" else -1)
        return f"{100 * gain:+.2f} %"

    for label, r in ([("start", start)] if start is not None else []) + [(f"#{k + 1}", r) for k, r in enumerate(front)]:
        cells = [label, *(_fmt(r.get(v)) for v in variables)]
        for o, sense in objectives:
            cells += [_fmt(r.get(o)), _fmt(r.get(f"confirm_{o}")), change(o, sense, r) if label != "start" else ""]
        cells += [_fmt(r.get(f"confirm_{c}", r.get(c))) for c in constraints]
        cells += [_fmt(_verdict_text(r)), _fmt(r.get("confirm_feasible", r.get("feasible"))),
                  _fmt(r.get("dominates_start", "")), _fmt(r.get("toml", ""))]
        feasible = r.get("confirm_feasible", r.get("feasible"))
        mark = ' class="infeasible" title="infeasible"' if feasible is False else ""
        rows.append(f"<tr{mark}>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    words = "".join(f"<li>{html.escape(line)}</li>" for line in
                    front_in_words(front, start, variables=variables, objectives=objectives))
    facts = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{_fmt(v)}</td></tr>" for k, v in summary.items())
    img = f'<p><img src="{html.escape(figure)}" alt="Pareto front" style="max-width:100%"></p>' if figure else ""
    page = f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<style>body{{font-family:sans-serif;margin:1.5em}} table{{border-collapse:collapse;font-size:12px}}
td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}} th{{background:#f3f3f3}}
tr.infeasible td{{background:#fde8e8;color:#8a1f1f}}</style></head>
<body><h1>{html.escape(title)}</h1>
<table>{facts}</table>
{img}
<h2>The front against the starting design</h2>
<p>Values in the search scene, then confirmed in the confirm scene; the change is the confirmed value's
improvement over the starting design's confirmed value (+ is better).</p>
<table><tr>{''.join(f'<th>{html.escape(h)}</th>' for h in head)}</tr>
{''.join(rows)}
</table>
<p>Rows in red are infeasible: a constraint is violated or the design's verdict is FAIL (in the confirm
scene when there is one).</p>
<h2>What each front design changes and buys</h2>
<ul>{words}</ul>
</body></html>
"""
    path = Path(path)
    with atomic_write(path) as f:
        f.write(page)
    return path
