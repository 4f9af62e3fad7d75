"""Unit tests of profilegen.output.plot: lazy matplotlib, the envelope figure, clearance."""

from __future__ import annotations

import dataclasses
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import pytest

from profilegen.output import plot
from profilegen.errors import ExportError

ROOT = Path(__file__).resolve().parents[2]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _classes(env):
    return {p.cls for p in env.pieces}


def test_import_does_not_import_matplotlib():
    code = "import sys, profilegen.output.plot, profilegen.output.export; print(sorted(m for m in sys.modules if m.startswith(('matplotlib', 'ezdxf'))))"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout


def test_envelope_figure_writes_png(tmp_path, default_set):
    tooth, motion, env = default_set
    path = tmp_path / "fig" / "envelope.png"
    fig = plot.envelope_figure(env, tooth, motion, title="default set", path=path)
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC
    assert sorted(p.name for p in path.parent.iterdir()) == ["envelope.png"]  # no temp file left
    assert len(fig.axes) == 2 and fig.get_suptitle() == "default set"
    # 150 dpi: the PNG's IHDR width is figure width (in) × 150
    width = int.from_bytes(data[16:20], "big")
    assert width == round(fig.get_figwidth() * 150)
    (legend,) = fig.legends
    labels = [t.get_text() for t in legend.get_texts()]
    assert set(labels) - {"ridge (kink)", "fold"} == _classes(env)
    assert ("fold" in labels) == bool(env.folds)


def test_envelope_figure_zoom_shows_the_right_flank(default_set):
    tooth, motion, env = default_set
    fig = plot.envelope_figure(env, tooth, motion)
    whole, zoom = fig.axes
    right = np.asarray(env.flank["right"])
    (x0, x1), (y0, y1) = zoom.get_xlim(), zoom.get_ylim()
    assert x0 < right[:, 0].min() and right[:, 0].max() < x1
    assert y0 < right[:, 1].min() and right[:, 1].max() < y1
    boundary = np.asarray(env.flank["boundary"])
    (X0, X1), (Y0, Y1) = whole.get_xlim(), whole.get_ylim()
    assert X0 < boundary[:, 0].min() and boundary[:, 0].max() < X1 and Y0 < boundary[:, 1].min() and boundary[:, 1].max() < Y1
    assert (x1 - x0) < (X1 - X0)


def test_envelope_figure_unwritable_path(tmp_path, default_set):
    tooth, motion, env = default_set
    (tmp_path / "f").write_text("x")
    with pytest.raises(ExportError, match="envelope.png"):
        plot.envelope_figure(env, tooth, motion, path=tmp_path / "f" / "envelope.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f"]


def test_envelope_legend_lists_the_classes_present(default_set):
    tooth, motion, env = default_set
    ax = plot.envelope(env, tooth=tooth, motion=motion, family=5)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sorted(labels) == sorted(_classes(env))
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)"
    assert ax.get_aspect() == 1.0
    # only interfering pieces: the legend has exactly that class
    only = dataclasses.replace(env, pieces=tuple(p for p in env.pieces if p.cls == "interfering"))
    ax = plot.envelope(only)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["interfering"]


def test_envelope_family_spans_the_pass(default_set):
    tooth, motion, env = default_set
    phi = np.linspace(*env.phi_range, 3)
    lines = plot.family_outlines(tooth, motion, phi)
    assert len(lines) == 3
    # the tooth at φ = 0 is centred on the CS space axis (x → −x symmetry of the default set)
    mid = lines[1]
    assert abs(mid[:, 0].min() + mid[:, 0].max()) < 1e-9
    # the drawn edge stays on or outside the FS root circle (no rim-sector cut lines)
    edge = plot.tooth_line(tooth)
    r = np.hypot(edge[:, 0], edge[:, 1] + tooth.neutral_radius_mm)
    assert r.min() >= tooth.neutral_radius_mm + tooth.dedendum_y_mm - 1e-9


def test_envelope_zoom_and_markers(default_set):
    from profilegen.profile.envelope import Ridge

    tooth, motion, env = default_set
    ridge = Ridge((0.5749, 50.0853), ("right", "right_tip"), (0.1, 0.2), 12.34)
    env2 = dataclasses.replace(env, ridges=(ridge,))
    ax = plot.envelope(env2, zoom=(0.0, 1.0, 49.9, 50.9))
    assert ax.get_xlim() == (0.0, 1.0) and ax.get_ylim() == (49.9, 50.9)
    assert any(t.get_text() == "12.3°" for t in ax.texts)
    assert sorted(t.get_text() for t in ax.get_legend().get_texts()) == sorted(_classes(env))


def test_envelope_bad_input_names_the_parameter(default_set):
    tooth, motion, env = default_set
    with pytest.raises(ValueError, match="zoom"):
        plot.envelope(env, zoom=(1.0, 0.0, 49.0, 51.0))
    with pytest.raises(ValueError, match="zoom"):
        plot.envelope(env, zoom=(0.0, 1.0))
    with pytest.raises(ValueError, match="motion"):
        plot.envelope(env, tooth=tooth)
    with pytest.raises(ValueError, match="family"):
        plot.envelope(env, tooth=tooth, motion=motion, family=0)


def test_envelope_legend_names_every_class(default_set):
    _, _, env = default_set
    ax = plot.envelope(env)
    assert sorted(t.get_text() for t in ax.get_legend().get_texts()) == sorted(_classes(env))


def test_clearance_units_and_minimum():
    phi = np.linspace(-np.pi / 2, np.pi / 2, 181)
    c_mm = 0.010 + 0.005 * np.cos(2 * (phi - 0.3))  # min 5 µm at φ = 0.3 − π/2
    ax = plot.clearance(phi, c_mm)
    x, y = ax.lines[-2].get_data()  # the curve (then the min marker)
    assert np.allclose(x, np.degrees(phi)) and np.allclose(y, c_mm * 1e3)
    mx, my = ax.lines[-1].get_data()
    k = int(np.argmin(c_mm))
    assert np.isclose(mx[0], np.degrees(phi[k])) and np.isclose(my[0], 5.0, atol=0.01)
    assert any(np.allclose(line.get_ydata(), 0.0) for line in ax.lines)  # the zero line
    assert ax.get_xlabel() == "φ (°)" and "µm" in ax.get_ylabel()


def test_clearance_bad_input_names_the_parameter():
    with pytest.raises(ValueError, match="clearance_mm"):
        plot.clearance(np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="phi_rad"):
        plot.clearance([0.0, np.nan], [0.0, 0.0])


@pytest.fixture(scope="module")
def sketch_stress(default_sketch):
    """The stresses of a sketch design of the default set (force estimate, no contact)."""
    return default_sketch.stress  # conftest.py: the sketch design, computed once per worker


def _inside(fig, artist) -> bool:
    box = artist.get_window_extent(fig.canvas.get_renderer())
    return 0 <= box.x0 and box.x1 <= fig.bbox.width and 0 <= box.y0 and box.y1 <= fig.bbox.height


def test_stress_figure_every_text_inside_the_figure(sketch_stress):
    """Fixed margins (no layout engine): titles, axis labels, tick labels and the safety-factor
    labels all lie inside the figure; each safety-factor label starts at its bar's end."""
    fig = plot.stress_figure(sketch_stress, title="default: flexspline stresses")
    fig.canvas.draw()
    sf = fig.axes[3]
    for ax in fig.axes:
        (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
        ticks = [t for t in ax.get_xticklabels() if x0 <= t.get_position()[0] <= x1]  # the ones drawn
        ticks += [t for t in ax.get_yticklabels() if y0 <= t.get_position()[1] <= y1]
        for t in [ax.title, ax.xaxis.label, ax.yaxis.label, *ticks, *ax.texts]:
            if t.get_text() and t.get_visible():
                assert _inside(fig, t), (ax.get_title(), t.get_text())
    labels = [t for t in sf.texts if "at" in t.get_text()]
    assert len(labels) == len(sketch_stress.checks)
    for t, c in zip(labels, sketch_stress.checks):
        assert t.get_position()[0] == pytest.approx(c.value)


def test_stress_figure_safety_axis_labels_do_not_run_together(sketch_stress):
    """The safety factors' log axis is labelled with plain 1-2-5 numbers and its minor ticks not
    at all (matplotlib labelled every minor tick of a short range: "2×10⁰3×10⁰4×10⁰" overlapped);
    the drawn labels' boxes are disjoint."""
    fig = plot.stress_figure(sketch_stress)
    fig.canvas.draw()
    sf = fig.axes[3]
    lo, hi = sorted(sf.get_xlim())
    drawn = [t for t in sf.get_xticklabels() if lo <= t.get_position()[0] <= hi and t.get_text()]
    assert len(drawn) >= 2
    for t in drawn:
        value = float(t.get_text())
        mantissa = value / 10 ** math.floor(math.log10(value))
        assert round(mantissa, 9) in (1.0, 2.0, 5.0) and value == pytest.approx(t.get_position()[0])
    assert not any(t.get_text() for t in sf.get_xticklabels(minor=True))
    boxes = sorted((t.get_window_extent() for t in drawn), key=lambda b: b.x0)
    assert all(a.x1 < b.x0 for a, b in zip(boxes, boxes[1:]))


def test_stress_figure_all_checks_skipped(sketch_stress):
    """A material without limits skips every check: the "skipped" labels sit inside the panel
    (a log axis has no 0 to put them at) and every check keeps its row."""
    skipped = tuple(dataclasses.replace(c, value=None) for c in sketch_stress.checks)
    fig = plot.stress_figure(dataclasses.replace(sketch_stress, checks=skipped))
    fig.canvas.draw()
    sf = fig.axes[3]
    texts = [t for t in sf.texts if t.get_text().startswith("skipped")]
    assert len(texts) == len(skipped)
    panel = sf.get_window_extent()
    r = fig.canvas.get_renderer()
    required_px = sf.transData.transform((skipped[0].required, 0.0))[0]
    for t in texts:
        box = t.get_window_extent(r)
        assert panel.x0 <= box.x0 and box.x1 <= panel.x1
        assert not box.x0 <= required_px <= box.x1  # clear of the dashed required-safety line
    lo, hi = sorted(sf.get_ylim())
    assert lo < 0 and hi > len(skipped) - 1 and sf.yaxis_inverted()
