"""`python -m validation` (the README's main job) and the README itself."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from validation.__main__ import main
from validation.cases import CASES

ROOT = Path(__file__).resolve().parents[1]


def test_list_names_every_case(capsys):
    assert main(["--list"]) == 0
    listed = capsys.readouterr().out.split()
    assert all(name in listed for name in CASES)


def test_a_coarse_run_writes_the_report_and_passes_its_checks(tmp_path, capsys):
    assert main(["--resolution", "coarse", "--out", str(tmp_path)]) == 0
    report = json.loads((tmp_path / "results.json").read_text())
    assert set(report["cases"]) == set(CASES)
    for case in report["cases"].values():
        assert case["converged"] and case["checks"]
        assert all(check["passed"] for check in case["checks"])
        for figure in case["figures"]:
            assert (tmp_path / figure).stat().st_size > 1000
    page = (tmp_path / "index.html").read_text()
    assert "Verification" in page and "FAIL" not in page
    assert "checks passed" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--cases", "no-such-case"], "unknown case name"),
        (["--resolution", "huge"], "unknown resolution"),
    ],
)
def test_bad_arguments_give_a_clear_error(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def readme_commands():
    return re.findall(r"```\n(apt-get update .*?)\n```", (ROOT / "README.md").read_text())


def test_the_readme_starts_with_the_two_setup_commands_and_ci_runs_the_second():
    commands = readme_commands()
    assert len(commands) == 2
    assert commands[0].endswith("python -m validation")
    assert commands[1].endswith("python -m pytest")
    assert commands[1] in (ROOT / ".ci" / "run").read_text()


@pytest.mark.parametrize("index, output", [(0, "cable.pvd"), (1, "laminate.vtu")])
def test_the_readme_examples_run(tmp_path, index, output):
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.DOTALL)
    assert len(blocks) == 2
    env = {**os.environ, "PYTHONPATH": str(ROOT)}  # also when the project is not installed
    completed = subprocess.run(
        [sys.executable, "-c", blocks[index]],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    assert completed.returncode == 0, completed.stderr
    assert (tmp_path / output).exists()
