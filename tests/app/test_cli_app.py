"""`profilegen app` at the command line: it prints its URL on 127.0.0.1, serves the page, and
Ctrl-C (SIGINT) ends it cleanly (exit 0, one line, no traceback); a workspace that is not a folder
is one line naming it (exit 2)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _env():
    return dict(os.environ, PYTHONPATH=str(ROOT))


def test_app_prints_its_url_serves_and_stops_on_ctrl_c(tmp_path):
    # SIGINT as a terminal delivers it: under pytest-xdist the worker ignores SIGINT and a child
    # inherits that, so Python would install no KeyboardInterrupt handler and Ctrl-C would do nothing
    proc = subprocess.Popen([sys.executable, "-m", "profilegen", "app", "--port", "0", "--workspace", str(tmp_path)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=_env(), cwd=tmp_path,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        line = proc.stdout.readline()
        m = re.match(r"profilegen app: (http://127\.0\.0\.1:(\d+)/) ", line)
        assert m, line
        with urllib.request.urlopen(m.group(1), timeout=30) as page:
            assert page.status == 200 and b"profilegen" in page.read()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert "Traceback" not in err and err.strip().endswith("profilegen app: stopped")


def test_a_workspace_that_is_not_a_folder_is_one_line(tmp_path):
    res = subprocess.run([sys.executable, "-m", "profilegen", "app", "--workspace", str(tmp_path / "nope")],
                         capture_output=True, text=True, env=_env(), timeout=60)
    assert res.returncode == 2
    assert res.stderr.strip().splitlines() == [f"profilegen: error: workspace {str(tmp_path / 'nope')!r}: not a folder"]
