"""tests/example_project, a user's project, installed with schemalog in a fresh virtual
environment: its own tests pass, the plugin proves every shipped task, and a hand-edited
unsound compressed task fails with the counterexample in pytest's output (issue 34).

The environment sees the site-packages of the interpreter running this suite (a .pth file
naming them): it takes pytest, hypothesis and schemalog's dependencies (numpy, sympy, lark,
...) from there, so the test needs no download of them and takes seconds, not minutes. Not
--system-site-packages: when the suite itself runs in a venv, as the README's commands do,
that venv's packages are not the "system site" of a venv made from it (issue 45). schemalog itself and
the example project are installed into it from this checkout by pip, as wheels (no
--editable), so what runs there is the package as a user gets it, entry point included; the
test checks that `import schemalog` there is the installed copy, not the checkout's or an
older install the system site holds.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import site
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "tests" / "example_project"
KB_TASKS = ROOT / "kb" / "tasks"

pytestmark = pytest.mark.skipif(not (ROOT / "pyproject.toml").is_file(), reason="needs a source checkout")


def run(argv: list, cwd: Path, timeout: int = 300) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return subprocess.run([str(a) for a in argv], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(python, project): a fresh venv with schemalog and the example project installed, and a
    copy of the project to run its tests in."""
    base = tmp_path_factory.mktemp("example")
    project = base / "example_project"
    shutil.copytree(EXAMPLE, project, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "build"))
    venv = base / "venv"
    made = run([sys.executable, "-m", "venv", venv], base)
    assert made.returncode == 0, made.stderr
    python = venv / "bin" / "python"
    ours = run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], base).stdout.strip()
    outer = [p for p in dict.fromkeys([*site.getsitepackages(), site.getusersitepackages(),
                                       sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]])
             if Path(p).is_dir()]
    (Path(ours) / "_suite_site.pth").write_text("".join(f"{p}\n" for p in outer))   # after the venv's own
    # with hatchling at hand, build without fetching it (offline); else pip fetches it
    isolation = [] if importlib.util.find_spec("hatchling") is None else ["--no-build-isolation"]
    pip = run([python, "-m", "pip", "install", "--no-deps", *isolation, ROOT, project], base, timeout=600)
    assert pip.returncode == 0, pip.stdout[-3000:] + pip.stderr[-3000:]
    where = run([python, "-c", "import schemalog, schemalog.testing.plugin; print(schemalog.__file__)"], base)
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.strip()).is_relative_to(venv), where.stdout
    return python, project


def test_the_example_project_passes_and_the_plugin_proves_every_shipped_task(installed):
    python, project = installed
    out = run([python, "-m", "pytest", "-p", "no:cacheprovider", "-v",
               "--schemalog-tasks", "tasks", "--schemalog-tasks", KB_TASKS], project)
    assert out.returncode == 0, out.stdout[-5000:] + out.stderr[-3000:]
    lines = out.stdout.splitlines()
    shipped = sorted(p.name for p in KB_TASKS.glob("*.pl"))
    assert len(shipped) == 3
    for name in shipped:
        assert any(f"{name}::" in line and line.split()[1] == "PASSED" for line in lines if "::" in line), name
    assert any(line.startswith("tasks/serve_water.pl::serve(water) PASSED") for line in lines)
    for test in ("test_serve_water_compresses_soundly", "test_the_hand_edited_compressed_file_is_refuted",
                 "test_every_generated_task_compresses_soundly"):
        assert f"tests/test_kitchen.py::{test} PASSED" in out.stdout, test
    assert "failed" not in lines[-1] and "9 passed" in lines[-1]


def test_a_broken_compressed_task_fails_with_its_counterexample(installed):
    python, project = installed
    out = run([python, "-m", "pytest", "-p", "no:cacheprovider", "--schemalog-tasks", "broken", "-k", "serve"],
              project)
    assert out.returncode == 1, out.stdout[-5000:] + out.stderr[-3000:]
    text = out.stdout
    assert "_ serve(water) in broken/serve_water_compressed.pl _" in text
    assert "soundness (no perceptual aliasing): FAILS" in text
    assert "counterexample, from the initial state hand.free:" in text
    assert "then the compressed tree takes a3_a4_a5(bottle): a3(bottle)" in text
    assert "the original would not take a3(bottle) there (state: hand.free):" in text
    assert "result: the compressed tree is not sound (exit 1)" in text
    assert "FAILED broken/serve_water_compressed.pl::serve(water)" in text
    assert "Traceback" not in text and "site-packages" not in text
