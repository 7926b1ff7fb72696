"""dem2d stays a pure engine (STYLE.md Part B): no rerun, no plotting, no studies,
no printing, no file I/O."""

import ast
from pathlib import Path

import dem2d

SRC = Path(dem2d.__file__).parent
FORBIDDEN_MODULES = ("rerun", "matplotlib", "viz", "studies", "cli", "rich")
FORBIDDEN_CALLS = ("print", "open")


def test_engine_imports_and_calls():
    for path in sorted(SRC.glob("*.py")):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""] if node.level == 0 else []
            else:
                names = []
            for n in names:
                assert n.split(".")[0] not in FORBIDDEN_MODULES, f"{path.name} imports {n}"
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                assert node.func.id not in FORBIDDEN_CALLS, f"{path.name} calls {node.func.id}()"
            if isinstance(node, ast.Attribute) and node.attr in ("write_text", "write_bytes", "read_text",
                                                                 "read_bytes"):
                raise AssertionError(f"{path.name} does file I/O ({node.attr})")
