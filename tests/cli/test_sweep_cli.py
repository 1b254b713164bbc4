"""End to end: `schemalog sweep` and `schemalog verify --each` as a user runs them."""

from __future__ import annotations

import os
import subprocess
import sys

from conftest import COFFEE, GRIPPER, MIX, ROOT

GRID = """\
name: tiny
shapes: [3x2, 4x2]
reductions: [0, 0.5]
seeds: [1]
measures: [prove, time]
runs: 2
ticks: 1
"""


# Dask missing: the modules' names are None in sys.modules, so importing them fails.
WITHOUT_DASK = """
import sys
for name in ("dask", "distributed", "pyarrow", "pyarrow.parquet"):
    sys.modules[name] = None
from schemalog.cli.main import main
code = main(sys.argv[1:])
print("loaded:", sorted(m for m in ("dask", "distributed") if sys.modules.get(m) is not None), file=sys.stderr)
sys.exit(code)
"""


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=300)


def python(code, *args, cwd=None):
    return subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True,
                          cwd=cwd or ROOT, timeout=300)


def ours(stderr: str) -> str:
    """stderr without dd's own shutdown notes (a BDD manager collected with nodes alive)."""
    skip = ("Exception ignored in: 'dd.cudd", "Traceback (most recent call last):", "  File ", "    ",
            "AssertionError: Still")
    return "\n".join(line for line in stderr.splitlines() if not line.startswith(skip))


def test_sweep_serial_writes_the_results_and_a_rerun_skips_them(tmp_path):
    grid = tmp_path / "tiny.yaml"
    grid.write_text(GRID)
    out = tmp_path / "out"
    r = run("sweep", grid, "--out", out, "--serial")
    assert r.returncode == 0, r.stderr
    assert "sweep tiny: 4 of 4 cells done, 0 failed; 4 computed" in r.stdout
    assert "in this process (--serial)" in r.stdout
    for name in ("results.parquet", "sweep.md", "results.csv", "results.md", "figure4.png"):
        assert (out / name).is_file(), name
    assert not [p for p in os.listdir(out) if p.startswith(".")]     # no temporary file left
    assert "| generated/4x2/rd0.5/seed1/full | 15 |" in (out / "sweep.md").read_text()
    lines = [line for line in r.stderr.splitlines() if line.startswith("sweep tiny [")]
    assert len(lines) == 4 and lines[-1].startswith("sweep tiny [4/4, ")
    again = run("sweep", grid, "--out", out, "--serial")
    assert again.returncode == 0 and "0 computed" in again.stdout and "4 already stored" in again.stdout


def test_a_bad_grid_is_told_with_file_line_and_column(tmp_path):
    grid = tmp_path / "bad.yaml"
    grid.write_text("shapes: [4x2]\nreductions: [0, 2]\n")
    r = run("sweep", grid, "--out", tmp_path / "out", "--serial")
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert f"{grid}:2:17: error: grid: a reduction degree must be between 0 and 1, not 2" in r.stderr
    assert run("sweep", tmp_path / "missing.yaml", "--serial").returncode == 1
    nope = run("sweep", "nosuchgrid", "--serial")
    assert nope.returncode == 2 and "shipped: paper, quick, runtimes" in nope.stderr
    assert run("sweep", grid, "--serial", "--workers", "2").returncode == 2


def test_without_dask_sweep_says_how_to_install_it_and_serial_still_runs(tmp_path):
    grid = tmp_path / "tiny.yaml"
    grid.write_text(GRID)
    r = python(WITHOUT_DASK, "sweep", grid, "--out", tmp_path / "out")
    assert r.returncode == 2 and "pip install 'schemalog[distributed]'" in r.stderr and "--serial" in r.stderr
    serial = python(WITHOUT_DASK, "sweep", grid, "--out", tmp_path / "out", "--serial")
    assert serial.returncode == 0, serial.stderr
    assert "loaded: []" in serial.stderr and (tmp_path / "out" / "results.jsonl").is_file()


def test_without_dask_verify_each_runs_in_this_process_and_says_so():
    """It stopped with "this needs Dask"; its results do not depend on where it runs."""
    for extra in ([], ["--workers", "2"]):
        r = python(WITHOUT_DASK, "verify", "--each", MIX, *extra)
        assert r.returncode == 0, r.stderr
        assert r.stderr.startswith("note: Dask is not installed (pip install 'schemalog[distributed]'"
                                   + ("; --workers 2 needs it" if extra else "")
                                   + "): running in this process, one task after another\n")
        assert "loaded: []" in r.stderr and r.stdout.startswith("PROVED ")
        assert r.stdout.endswith("1 proved, 0 refuted, 0 vacuous, 0 no proof, 0 error "
                                 "(in this process (Dask is not installed))\n")
    # a cluster named cannot be reached without Dask: refused, as sweep refuses
    named = python(WITHOUT_DASK, "verify", "--each", MIX, "--scheduler", "tcp://localhost:8786")
    assert named.returncode == 2 and "this needs Dask: pip install 'schemalog[distributed]'" in named.stderr


def test_verify_each_proves_every_task_of_a_folder(tmp_path):
    r = run("verify", "--each", "kb/tasks", "--serial")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert [line.split()[0] for line in lines[:-1]] == ["PROVED"] * 3
    assert "kb/tasks/mix_with_spoon.pl: use(spoon): sound and complete; 12 -> 6 behaviours" in r.stdout
    assert lines[-1].startswith("verify --each: 3 tasks in 3 files: 3 proved, 0 refuted, 0 vacuous, 0 no proof")


def test_verify_each_on_two_workers_refutes_flags_vacuous_and_unreadable(tmp_path):
    (tmp_path / "vacuous.pl").write_text(GRIPPER)
    (tmp_path / "broken.pl").write_text("task(t).\nschema(t, [(a, true)] a.done).\n")
    r = run("verify", "--each", MIX, COFFEE, tmp_path, "--propagate", "pre", "--workers", "2")
    assert r.returncode == 1, r.stderr
    verdicts = {line.split()[1].split(":")[0]: line.split()[0] for line in r.stdout.splitlines()[:-1]}
    assert verdicts[str(COFFEE)] == "REFUTED"
    assert verdicts[str(tmp_path / "vacuous.pl")] == "VACUOUS"
    assert verdicts[str(tmp_path / "broken.pl")] == "ERROR"
    assert f"ERROR     {tmp_path / 'broken.pl'}:2:23: error: syntax error" in r.stdout   # the error's place
    assert "on 2 Dask worker processes" in r.stdout and "internal error" not in r.stderr


def test_a_busy_dashboard_port_is_no_warning():
    """With port 8787 taken (a second sweep, a notebook's cluster), distributed printed its own
    warning, "Port 8787 is already in use", with a site-packages path."""
    import socket

    busy = socket.socket()
    try:
        busy.bind(("0.0.0.0", 8787))
        busy.listen()
    except OSError:
        pass                                    # taken already: as busy as the test wants it
    try:
        r = run("verify", "--each", MIX, "--workers", "2")
    finally:
        busy.close()
    assert r.returncode == 0, r.stderr
    assert "8787" not in r.stderr and "site-packages" not in r.stderr and "Warning" not in r.stderr, r.stderr
    assert "on 2 Dask worker processes" in r.stdout


def test_verify_each_without_a_proof_is_inconclusive_and_refuses_single_task_options():
    r = run("verify", "--each", COFFEE, "--method", "explicit", "--max-states", "3", "--serial")
    assert r.returncode == 3 and r.stdout.startswith("NO PROOF") and "limit" in r.stdout
    assert "1 no proof" in r.stdout and "proved" not in r.stdout.split("\n")[0]
    assert run("verify", "--each", COFFEE, "--task", "prepareboth", "--serial").returncode == 2
    assert run("verify", "--each", "nowhere", "--serial").returncode == 2


SLOW_GRID = """\
shapes: [6x4, 7x3]
reductions: [0.3, 0.5, 0.7]
seeds: [1, 2, 3, 4, 5, 6]
measures: [compress, prove]
"""


def start_sweep(tmp_path, *extra, grid=SLOW_GRID):
    """`sweep --workers 2` as a terminal starts it: its own process group, SIGINT at its default,
    Dask's and the sweep's temporary files in tmp_path/tmp."""
    import signal

    (tmp_path / "g.yaml").write_text(grid)
    (tmp_path / "tmp").mkdir(exist_ok=True)
    env = {**os.environ, "TMPDIR": str(tmp_path / "tmp")}
    return subprocess.Popen([sys.executable, "-m", "schemalog", "sweep", "g.yaml", "--workers", "2", "--out", "o",
                             *extra], cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def in_session(sid: int) -> list[int]:
    """The processes of session `sid`."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                if os.getsid(int(entry)) == sid:
                    found.append(int(entry))
            except OSError:
                pass
    return found


def test_ctrl_c_while_the_workers_start_ends_quietly(tmp_path):
    """Ctrl-C reaches the whole process group; in the first seconds the workers were still
    starting and died with tracebacks (issue 46: 4 of 5 tries). Whenever it comes: exit 130,
    "interrupted", no traceback, no leaked-semaphore warning, no scratch folder left."""
    import signal
    import time

    for delay in (0.4, 0.8, 1.2, 2.0):
        p = start_sweep(tmp_path)
        time.sleep(delay)
        os.killpg(p.pid, signal.SIGINT)
        _, err = p.communicate(timeout=120)
        err = err.decode()
        assert p.returncode == 130, (delay, err[-2000:])
        assert "interrupted" in err and "Traceback" not in err and "resource_tracker" not in err, (delay, err[-2000:])
        assert list((tmp_path / "tmp").iterdir()) == [], delay


def test_a_killed_sweeps_workers_leave_quietly_and_the_next_sweep_cleans_up(tmp_path):
    import signal
    import time

    p = start_sweep(tmp_path)
    time.sleep(3)
    os.kill(p.pid, signal.SIGKILL)
    _, err = p.communicate(timeout=120)          # until the orphaned workers have gone too
    err = err.decode()
    assert "resource_tracker" not in err and "Traceback" not in err, err[-2000:]
    left = [f.name for f in (tmp_path / "tmp").iterdir()]
    assert left and all(name.startswith(f"schemalog-dask-{p.pid}-") for name in left)   # a SIGKILL leaves it
    for _ in range(100):                                              # the killed sweep's workers end
        if not in_session(p.pid):
            break
        time.sleep(0.1)
    again = start_sweep(tmp_path, "--fresh", grid="shapes: [3x2]\nreductions: [0.5]\nmeasures: [compress]\n")
    _, err = again.communicate(timeout=300)
    assert again.returncode == 0, err.decode()[-2000:]
    assert list((tmp_path / "tmp").iterdir()) == []                   # the orphan removed, its own too
