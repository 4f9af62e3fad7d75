"""The package follows the library convention: a NullHandler on its logger, so a script calling
profilegen.design gets the warnings in the result, not log records on its stderr through
logging's last-resort handler; the CLI (or the script) configures the output."""

import subprocess
import sys

DESIGN = """
import logging, profilegen as pg
gs = pg.load_gearset("default").with_values({"wave_generator.deflection_coefficient": 1.001})
d = pg.design(gs, scene="sketch", contact=False, stress=False)
logging.getLogger("profilegen.pipeline.design").warning("a record from the package")
print(len(d.warnings))
"""


def run(script: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)


def test_a_script_sees_the_warnings_in_the_result_and_nothing_on_stderr():
    res = run(DESIGN)
    assert res.returncode == 0, res.stderr
    assert int(res.stdout.strip()) >= 1 and res.stderr == ""


def test_a_handler_the_script_adds_receives_the_records():
    res = run("import logging, profilegen\nlogging.basicConfig(level=logging.WARNING)\n"
              "logging.getLogger('profilegen.pipeline.design').warning('a record from the package')")
    assert res.returncode == 0 and "WARNING:profilegen.pipeline.design:a record from the package" in res.stderr
