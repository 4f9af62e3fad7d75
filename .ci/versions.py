"""Print the versions pip resolved for the scientific stack and the BLAS kernels in use.

Run by .ci/run before the tests, so a red run says what it ran on: the suite's tolerances are
stated against what each algorithm guarantees, but its numbers still come from numpy/scipy and
from the OpenBLAS kernel chosen for the CPU (OPENBLAS_CORETYPE overrides that choice)."""

import platform
from importlib import metadata

PACKAGES = ("numpy", "scipy", "shapely", "matplotlib", "ezdxf", "scikit-fem", "contourpy", "plotly", "pymoo",
            "cadquery-ocp-novtk", "threadpoolctl", "pytest", "pytest-xdist", "hypothesis")


def version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "absent"


print(f"python {platform.python_version()} on {platform.machine()} ({platform.platform()})")
print("resolved: " + ", ".join(f"{p} {version(p)}" for p in PACKAGES))

import scipy.linalg  # noqa: E402,F401  (loads scipy's own OpenBLAS beside numpy's)
import threadpoolctl  # noqa: E402

for lib in threadpoolctl.threadpool_info():
    where = lib.get("filepath", "").rsplit("/", 2)[-2]
    print(f"blas: {lib.get('internal_api')} {lib.get('version')}, kernel {lib.get('architecture')} ({where})")
