"""dem3d stays pure: no file I/O, printing, rerun, viz or studies imports (STYLE.md Part B)."""

import ast
from pathlib import Path

import dem3d

ALLOWED = {"numpy", "numba", "scipy", "math", "typing", "dataclasses", "__future__", "analytic"}
FORBIDDEN_CALLS = {"print", "open"}


def test_dem3d_imports_only_numerics_and_does_no_io():
    root = Path(dem3d.__file__).parent
    for path in sorted(root.glob("*.py")):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [] if node.level else [node.module]
            else:
                names = []
            for name in names:
                assert name.split(".")[0] in ALLOWED, f"{path.name} imports {name}"
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                assert node.func.id not in FORBIDDEN_CALLS, f"{path.name} calls {node.func.id}()"
