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


def driver(profile_dir, screen: tuple[int, int], logs: dict):
    """Headless Chromium driven by ChromeDriver, its viewport (not the window, which includes the
    browser's own bars) ``screen`` pixels, a fresh profile in ``profile_dir``, ``logs`` its
    ``goog:loggingPrefs``. The caller quits it."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--hide-scrollbars", f"--window-size={screen[0]},{screen[1]}", f"--user-data-dir={profile_dir}"):
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", logs)
    chrome = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=opts)
    chrome.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                           {"width": screen[0], "height": screen[1], "deviceScaleFactor": 1, "mobile": False})
    return chrome
