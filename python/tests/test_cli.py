"""The ``tensorglyph`` console command the wheel installs is the Rust binary's command line."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO, run_cli


def console_script():
    exe = shutil.which("tensorglyph") or str(Path(sys.executable).with_name("tensorglyph"))
    if not Path(exe).exists():
        if os.environ.get("CI"):
            pytest.fail("the tensorglyph console script is not installed (CI installs it)")
        pytest.skip("the tensorglyph console script is not installed")
    return exe


def run(*args):
    return subprocess.run([console_script(), *map(str, args)], capture_output=True, text=True, timeout=600)


def test_the_console_script_is_the_command_line(tmp_path):
    v = run("--version")
    assert v.returncode == 0 and v.stdout.startswith("tensorglyph ")
    h = run("render", "--help")
    assert h.returncode == 0 and "--reference-check" in h.stdout
    ours = run("info", "--demo", "grid:4", "--json", "--sample", "3")
    assert ours.returncode == 0
    assert json.loads(ours.stdout) == json.loads(run_cli("info", "--demo", "grid:4", "--json", "--sample", "3").stdout)
    out = tmp_path / "g.png"
    r = run("render", "--demo", "grid:4", "-o", out, "--size", "64x48", "-q")
    assert r.returncode == 0 and out.stat().st_size > 0


def test_errors_are_one_line_and_status_two(tmp_path):
    for args in (["render", "--demo", "grid:4", "-o", tmp_path / "x.png", "--view", "up"],
                 ["info", tmp_path / "missing.nii.gz"],
                 ["frobnicate"]):
        r = run(*args)
        assert r.returncode == 2, r
        assert r.stderr.count("\n") == 1 and r.stderr.startswith("error:"), r.stderr
        assert r.stderr == run_cli(*args, check=False).stderr


def test_a_closed_pipe_is_not_an_error():
    p = subprocess.run(f"'{console_script()}' info --demo grid:8 | head -c 10", shell=True,
                       capture_output=True, text=True, cwd=REPO)
    assert p.returncode == 0 and p.stderr == ""
