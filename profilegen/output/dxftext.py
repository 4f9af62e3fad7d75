"""DXF R2010 text without ezdxf: the document around the entities, from a stored template.

:func:`profilegen.output.cad.write_contours_dxf` makes its entities' text itself; the rest of
the file — header, classes, tables, blocks, objects — is the same for every drawing on the
standard layers but for the extents, the view and the handles that come after the entities.
ezdxf builds that document in ~0.1 s a file and its import takes ~0.4 s, longer than the
design's geometry stages; this module fills the document ezdxf writes for one line (stored in
``dxf_r2010.template``, made by :func:`build_template`) with the drawing's entities, extents
and handles instead, byte for byte what ezdxf writes (tests/unit/test_dxf_template.py compares
both writers on varied drawings, and the stored template with a fresh one where the installed
ezdxf is the version that made it).

The fast path takes the standard layers spelled as :data:`~profilegen.output.export.
DXF_LAYER_COLORS` spells them, a drawing with extents (at least one element), and notes of
plain ASCII; :func:`covers` says whether a drawing qualifies, and the writer falls back to
ezdxf otherwise.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

__all__ = ["FIRST_HANDLE", "OWNER", "build_template", "covers", "document", "stored_version", "text_entity",
           "write_template"]

TEMPLATE_PATH = Path(__file__).with_name("dxf_r2010.template")
#: The first handle after the document's own objects (standard layers, no extras): the entities start here.
FIRST_HANDLE = 0x34
#: The modelspace block record's handle: every entity's owner (group code 330).
OWNER = "17"

# markers in the stored template (the document ezdxf writes has no "@@")
_EXTENTS_HEADER = "@@EXTENTS_HEADER@@"
_HANDSEED = "@@HANDSEED@@"
_VPORT = "@@VPORT@@"
_VIEW = "@@VIEW@@"
_APPID_1 = "@@APPID_1@@"
_APPID_2 = "@@APPID_2@@"
_ENTITIES = "@@ENTITIES@@"
_LAYOUT_EXTENTS = "@@LAYOUT_EXTENTS@@"
_DICTVAR = "@@DICTVAR@@"
_PLAIN = re.compile(r"[ -~]*")  # printable ASCII
_SPECIAL = re.compile(r"[\\^%{}]")  # DXF text codes (\P, ^J, %%d, {…}): left to ezdxf


def covers(names, standard, texts) -> bool:
    """True if the template writes this drawing: layer ``names`` all standard and spelled as
    ``standard`` spells them, notes of printable ASCII without DXF text codes."""
    if any(n not in standard for n in names):
        return False
    return all(_PLAIN.fullmatch(s) and not _SPECIAL.search(s) and _PLAIN.fullmatch(layer)
               for layer, _xy, _h, s in texts)


def _hex(n: int) -> str:
    return f"{n:X}"


def text_entity(layer: str, xy, height: float, string: str, handle: str) -> str:
    """A TEXT entity as ezdxf writes it (left-aligned, baseline at ``xy``)."""
    x, y = float(xy[0]), float(xy[1])
    return (f"  0\nTEXT\n  5\n{handle}\n330\n{OWNER}\n100\nAcDbEntity\n  8\n{layer}\n100\nAcDbText\n"
            f" 10\n{x!r}\n 20\n{y!r}\n 30\n0.0\n 40\n{float(height)!r}\n  1\n{string}\n100\nAcDbText\n")


def _vec(codes: tuple[int, int, int], v) -> str:
    return "".join(f"{c:3d}\n{float(x)!r}\n" for c, x in zip(codes, v))


@functools.cache
def _stored() -> tuple[str, str]:
    """(ezdxf version that made it, template text) of the stored template."""
    first, text = TEMPLATE_PATH.read_text(encoding="utf-8").split("\n", 1)
    return first.removeprefix("ezdxf "), text


def _template() -> str:
    return _stored()[1]


def stored_version() -> str:
    """The ezdxf version that made the stored template (its first line)."""
    return _stored()[0]


def write_template() -> Path:
    """Store :func:`build_template` with the installed ezdxf's version (run after an ezdxf upgrade
    changes what it writes: ``python -c "from profilegen.output import dxftext; dxftext.write_template()"``)."""
    import ezdxf

    TEMPLATE_PATH.write_text(f"ezdxf {ezdxf.__version__}\n" + build_template(), encoding="utf-8")
    return TEMPLATE_PATH


def document(entities: str, count: int, extents) -> str:
    """The whole DXF file: ``entities`` (the text of ``count`` entities with the handles
    FIRST_HANDLE, FIRST_HANDLE + 1, …), the extents ``(lo, hi)`` (mm, (2,) each) in the header
    and the modelspace layout, the view fitted to them, the handles after the entities."""
    lo, hi = extents
    lo3, hi3 = (float(lo[0]), float(lo[1]), 0.0), (float(hi[0]), float(hi[1]), 0.0)
    size = (float(hi[0]) - float(lo[0]), float(hi[1]) - float(lo[1]))
    height = float(max(size[1], size[0] * 0.75, 1e-3) * 1.1)
    centre = (float(lo[0] + hi[0]) / 2, float(lo[1] + hi[1]) / 2)
    nxt = FIRST_HANDLE + count
    # ezdxf copies the layout's extents into the header only where neither is the zero vector
    if any(lo3) and any(hi3):
        header = "  9\n$EXTMIN\n" + _vec((10, 20, 30), lo3) + "  9\n$EXTMAX\n" + _vec((10, 20, 30), hi3)
    else:
        header = "  9\n$EXTMIN\n" + _vec((10, 20, 30), (1e20,) * 3) + "  9\n$EXTMAX\n" + _vec((10, 20, 30), (-1e20,) * 3)
    view = f" 12\n{centre[0]!r}\n 22\n{centre[1]!r}\n"
    parts = {
        _EXTENTS_HEADER: header,
        _HANDSEED: _hex(nxt + 4),
        _VPORT: _hex(nxt),
        _VIEW: view,
        _APPID_1: _hex(nxt + 1),
        _APPID_2: _hex(nxt + 2),
        _DICTVAR: _hex(nxt + 3),
        _LAYOUT_EXTENTS: _vec((14, 24, 34), lo3) + _vec((15, 25, 35), hi3),
        "@@HEIGHT@@": f"{height!r}",
        _ENTITIES: entities,
    }
    pieces = re.split("(@@[A-Z_0-9]+@@)", _template())
    return "".join(parts.get(p, p) for p in pieces)


def build_template() -> str:
    """The template, from the document ezdxf writes for one LINE on the standard layers with
    extents (−5, −5)…(5, 5) (ezdxf imported here; tests/unit/test_dxf_template.py keeps the
    stored file equal to it for the ezdxf version named in its first line)."""
    import ezdxf

    from .export import DXF_LAYER_COLORS, dxf_document, save_dxf

    import tempfile

    import numpy as np

    lo, hi = (-5.0, -5.0), (5.0, 5.0)
    with dxf_document([], rename={n.lower(): n for n in DXF_LAYER_COLORS}) as doc, \
            tempfile.TemporaryDirectory() as tmp:
        msp = doc.modelspace()
        handle = doc.entitydb.handles.next()
        if handle != _hex(FIRST_HANDLE) or msp.block_record_handle != OWNER:
            raise RuntimeError(f"DXF template: ezdxf {ezdxf.__version__} gives the first entity handle {handle} "
                               f"and the modelspace owner {msp.block_record_handle}, not {_hex(FIRST_HANDLE)}, {OWNER}")
        entity = (f"  0\nLINE\n  5\n{handle}\n330\n{OWNER}\n100\nAcDbEntity\n  8\nCS\n100\nAcDbLine\n"
                  " 10\n0.0\n 20\n0.0\n 30\n0.0\n 11\n1.0\n 21\n1.0\n 31\n0.0\n")
        path = Path(tmp) / "template.dxf"
        save_dxf(doc, path, (np.array(lo), np.array(hi)), entities=entity)
        text = path.read_text(encoding="utf-8")
    if "@@" in text:
        raise RuntimeError(f"DXF template: ezdxf {ezdxf.__version__} wrote '@@', the template's marker")
    n = FIRST_HANDLE + 1

    def swap(old: str, new: str, count: int = 1) -> None:
        nonlocal text
        found = text.count(old)
        if found != count:
            raise RuntimeError(f"DXF template: {old!r} found {found} times, expected {count} (ezdxf {ezdxf.__version__})")
        text = text.replace(old, new)

    swap("  9\n$EXTMIN\n 10\n-5.0\n 20\n-5.0\n 30\n0.0\n  9\n$EXTMAX\n 10\n5.0\n 20\n5.0\n 30\n0.0\n", _EXTENTS_HEADER)
    swap(f"  9\n$HANDSEED\n  5\n{_hex(n + 4)}\n", f"  9\n$HANDSEED\n  5\n{_HANDSEED}\n")
    swap(f"  0\nVPORT\n  5\n{_hex(n)}\n", f"  0\nVPORT\n  5\n{_VPORT}\n")
    # the view centre and height: the first (12, 22) and 40 of the *Active VPORT entry
    at = text.index(f"  5\n{_VPORT}\n")
    for old, new in ((" 12\n0.0\n 22\n0.0\n", _VIEW), (" 40\n11.0\n", " 40\n@@HEIGHT@@\n")):
        k = text.find(old, at)
        if k < 0 or k > text.find("  0\n", at):
            raise RuntimeError(f"DXF template: {old!r} not in the VPORT entry (ezdxf {ezdxf.__version__})")
        text = text[:k] + new + text[k + len(old):]
    swap(f"  0\nAPPID\n  5\n{_hex(n + 1)}\n", f"  0\nAPPID\n  5\n{_APPID_1}\n")
    swap(f"  0\nAPPID\n  5\n{_hex(n + 2)}\n", f"  0\nAPPID\n  5\n{_APPID_2}\n")
    swap(" 14\n-5.0\n 24\n-5.0\n 34\n0.0\n 15\n5.0\n 25\n5.0\n 35\n0.0\n", _LAYOUT_EXTENTS)
    swap(f"350\n{_hex(n + 3)}\n", f"350\n{_DICTVAR}\n")
    swap(f"  0\nDICTIONARYVAR\n  5\n{_hex(n + 3)}\n", f"  0\nDICTIONARYVAR\n  5\n{_DICTVAR}\n")
    swap(entity, _ENTITIES)
    return text
