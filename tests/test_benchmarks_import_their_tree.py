"""Every benchmark imports the packages of the tree it lives in: ``python benchmarks/x.py`` puts
benchmarks/ (not the tree's root) on the import path, and an editable install of the project
points at one checkout, so a script that does not put its own tree first measures that checkout
whatever tree it is run from. Checked statically for every script, and by
one real run of a script from a ``git archive`` copy whose code is marked."""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCHMARKS = sorted((ROOT / "benchmarks").glob("*.py"))
PROJECT = {"elements", "femcore", "solvers", "materials", "validation", "fibreshell", "cases"}
# the scripts import one another (benchmarks/ is on the path): one imported before the tree is
# put first would import the project from wherever the path finds it
PROJECT |= {path.stem for path in BENCHMARKS}
# the tree's root, as the scripts spell it: the folder above benchmarks/
ROOT_SPELLINGS = {
    "str(Path(__file__).resolve().parents[1])",
    "os.path.dirname(os.path.dirname(os.path.abspath(__file__)))",
}


def _bound_names(module: ast.Module) -> dict[str, str]:
    """Module-level ``NAME = expression`` as source text, names bound earlier substituted."""
    names: dict[str, str] = {}
    for statement in module.body:
        if (
            isinstance(statement, ast.Assign)
            and len(statement.targets) == 1
            and isinstance(statement.targets[0], ast.Name)
        ):
            names[statement.targets[0].id] = _spelled(statement.value, names)
    return names


def _spelled(node: ast.expr, names: dict[str, str]) -> str:
    """``node`` as source text with module-level names replaced by what they were bound to."""

    class Substitute(ast.NodeTransformer):
        def visit_Name(self, name: ast.Name) -> ast.AST:
            if name.id in names:
                return ast.parse(names[name.id], mode="eval").body
            return name

    return ast.unparse(Substitute().visit(ast.parse(ast.unparse(node), mode="eval")))


def tree_first_line(module: ast.Module) -> int | None:
    """The line of the module-level ``sys.path.insert(0, <the tree's root>)`` (under a
    module-level ``if`` too), None where the script has none."""
    names = _bound_names(module)
    statements = list(module.body)
    while statements:
        statement = statements.pop(0)
        if isinstance(statement, ast.If):
            statements[:0] = statement.body + statement.orelse
            continue
        if not isinstance(statement, ast.Expr) or not isinstance(statement.value, ast.Call):
            continue
        call = statement.value
        if ast.unparse(call.func) != "sys.path.insert" or len(call.args) != 2:
            continue
        where, folder = call.args
        spelled = _spelled(folder, names)
        if spelled.startswith("str(") is False and not spelled.startswith("os.path"):
            spelled = f"str({spelled})"
        if ast.unparse(where) == "0" and spelled in ROOT_SPELLINGS:
            return statement.lineno
    return None


def project_imports(module: ast.Module) -> list[tuple[int, str]]:
    """(line, module) of every import of the project's packages or of another script, at
    module level or in a function, and of every ``importlib.import_module`` of a name (or
    f-string) that starts with one."""
    found = []
    for node in ast.walk(module):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.append((node.lineno, node.module))
        elif (
            isinstance(node, ast.Call)
            and ast.unparse(node.func) in {"importlib.import_module", "import_module"}
            and node.args
        ):
            first = node.args[0]
            if isinstance(first, ast.JoinedStr) and first.values:
                first = first.values[0]
            if isinstance(first, ast.Constant) and isinstance(first.value, str):
                found.append((node.lineno, first.value))
    return [(line, name) for line, name in found if name.split(".")[0] in PROJECT]


@pytest.mark.parametrize("script", BENCHMARKS, ids=lambda path: path.name)
def test_each_script_puts_its_tree_first_before_importing_the_project(script: Path) -> None:
    module = ast.parse(script.read_text())
    imports = project_imports(module)
    line = tree_first_line(module)
    if not imports:
        return  # nothing of the project imported in the script's own process
    assert line is not None, f"{script.name} imports {imports[0][1]} without its tree first"
    early = [(at, name) for at, name in imports if at < line]
    assert not early, f"{script.name} imports {early} before line {line} puts its tree first"


def test_the_static_check_catches_a_script_without_its_tree() -> None:
    """The check itself: a script importing the project with benchmarks/ alone on the path, or
    before its tree is put first, is caught; the canonical spelling is taken."""
    without = ast.parse("import sys\nfrom pathlib import Path\n"
                        "sys.path.insert(0, str(Path(__file__).resolve().parent))\n"
                        "def f():\n    from femcore import Mesh\n")  # fmt: skip
    assert project_imports(without) == [(5, "femcore")] and tree_first_line(without) is None
    late = ast.parse("from solvers import Static\nimport sys\nfrom pathlib import Path\n"
                     "ROOT = Path(__file__).resolve().parents[1]\n"
                     "sys.path.insert(0, str(ROOT))\n")  # fmt: skip
    assert tree_first_line(late) == 5 and project_imports(late)[0][0] < 5


@pytest.mark.skipif(shutil.which("git") is None, reason="git is needed for the archive")
def test_a_script_run_from_an_archived_copy_runs_the_copys_code(tmp_path: Path) -> None:
    """``python benchmarks/cluster_idle.py --help`` run from a ``git archive`` of HEAD whose
    fibreshell/cluster.py is marked (a line printing a mark appended in the copy) prints the
    mark: the copy's module ran, not the one of the checkout the environment has installed."""
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", "HEAD"], capture_output=True, check=False
    )
    if archive.returncode != 0:
        pytest.skip("not a git checkout")
    subprocess.run(["tar", "-x", "-C", str(tmp_path)], input=archive.stdout, check=True)
    mark = "the archived copy's fibreshell.cluster ran"
    cluster = tmp_path / "fibreshell" / "cluster.py"
    cluster.write_text(cluster.read_text() + f"\nprint({mark!r})\n")
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    done = subprocess.run(
        [sys.executable, "benchmarks/cluster_idle.py", "--help"],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert mark in done.stdout
