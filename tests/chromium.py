"""Debian's Chromium and its driver for the browser tests (tests/app/test_app_browser.py,
tests/validation/test_browser.py): where they are, and why a test must skip without them."""

from __future__ import annotations

import os

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


def missing() -> str | None:
    """Why the browser tests cannot run here (a skip reason), or None when they can."""
    for path in (CHROMIUM, CHROMEDRIVER):
        if not (os.path.exists(path) and os.access(path, os.X_OK)):
            return f"{path} is missing (apt-get install chromium chromium-driver)"
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install -e '.[test]')"
    import resource

    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY and soft < 64 << 30:
        return f"chromium reserves more address space than this process's RLIMIT_AS ({soft >> 20} MiB) allows"
    return None
