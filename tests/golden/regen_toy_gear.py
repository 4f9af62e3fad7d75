"""Regenerate the golden toy-gear DXF, only if the new file is the analytic toy gear.

    python tests/golden/regen_toy_gear.py            # dry run: write to a temp file, check, report
    python tests/golden/regen_toy_gear.py --write    # ... and replace tests/golden/toy_gear.dxf

The toy gear is the one of ``tests/unit/test_cad.py`` (``toy_gear_layers``, ``TOY_TEXTS``),
written by :func:`profilegen.output.cad.write_contours_dxf`. Before anything is replaced the new
file must pass :func:`tests.golden.toy_gear_checks.check_toy_gear_dxf` (closure, turning,
G1 joins, area, radii, symmetry against the analytic gear); a file that fails is not
written, and the exit status is 1. The golden file is replaced atomically (temp file in the
same folder + rename). The tests never write it; commit a regenerated file together with the
change that made it necessary.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from profilegen.output.cad import write_contours_dxf  # noqa: E402
from tests.golden.toy_gear_checks import ToyGearCheckError, check_toy_gear_dxf  # noqa: E402

GOLDEN = ROOT / "tests" / "golden" / "toy_gear.dxf"


def toy_gear_layers():
    from tests.unit.test_cad import toy_gear_layers as layers

    return layers()


def toy_gear_texts():
    from tests.unit.test_cad import TOY_TEXTS

    return TOY_TEXTS


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="replace the golden file (default: check only)")
    ap.add_argument("--output", type=Path, default=GOLDEN, help=f"golden file to replace (default {GOLDEN})")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="toy_gear_") as tmp:
        fresh = Path(tmp) / "toy_gear.dxf"
        write_contours_dxf(fresh, toy_gear_layers(), texts=toy_gear_texts())
        try:
            measured = check_toy_gear_dxf(fresh)
        except ToyGearCheckError as exc:
            print(f"not written: the new toy gear fails the geometric check: {exc}", file=sys.stderr)
            return 1
        print(f"checked: {measured['entities']} entities, z = {measured['teeth']}, area {measured['area_mm2']:.9f} mm² "
              f"(analytic {measured['analytic_area_mm2']:.9f}), radii {measured['root_mm']:.9f} … {measured['tip_mm']:.9f} mm")
        if not args.write:
            print("dry run: nothing written (give --write to replace the golden file)")
            return 0
        args.output.parent.mkdir(parents=True, exist_ok=True)
        fd, part = tempfile.mkstemp(prefix=".toy_gear.", suffix=".part", dir=args.output.parent)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(fresh.read_bytes())
                f.flush()
                os.fsync(f.fileno())
            os.replace(part, args.output)
        except BaseException:
            Path(part).unlink(missing_ok=True)
            raise
    print(f"written: {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
