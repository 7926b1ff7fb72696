"""The design's boundaries, checked on the source: only viz/ imports rerun; engines and
theories do no file I/O and never print; analytic/ imports no engine."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ["analytic", "dem2d", "dem3d", "viz", "studies"]


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module.split(".")[0])
    return out


def _sources(pkg):
    return sorted((ROOT / pkg).rglob("*.py"))


def test_only_viz_imports_rerun():
    offenders = [str(p.relative_to(ROOT)) for pkg in PACKAGES if pkg != "viz"
                 for p in _sources(pkg) if "rerun" in _imports(p)]
    offenders += ["cli.py"] if "rerun" in _imports(ROOT / "cli.py") else []
    assert offenders == []


def test_engines_and_theories_are_pure():
    """No print(), open() or rerun/matplotlib in analytic/, dem2d/, dem3d/."""
    bad = []
    for pkg in ("analytic", "dem2d", "dem3d"):
        for p in _sources(pkg):
            tree = ast.parse(p.read_text())
            for node in ast.walk(tree):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("print", "open"):
                    bad.append(f"{p.relative_to(ROOT)}:{node.lineno} {node.func.id}()")
            if _imports(p) & {"rerun", "matplotlib", "rich"}:
                bad.append(f"{p.relative_to(ROOT)} imports output libraries")
    assert bad == []


def test_analytic_depends_on_no_engine():
    for p in _sources("analytic"):
        assert not (_imports(p) & {"dem2d", "dem3d", "viz", "studies", "pymunk", "numba"}), p


def _modules_imported(path: Path) -> set[str]:
    """Full dotted names of every absolute import in a file."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
    return out


def test_engines_import_no_study():
    for pkg in ("analytic", "dem2d", "dem3d"):
        for p in _sources(pkg):
            assert "studies" not in _imports(p), p


def test_cli_names_no_study():
    """cli.py builds the study commands from the registry: adding a study adds no code there."""
    from studies import NAMES
    named = {m for m in _modules_imported(ROOT / "cli.py")
             if m.startswith("studies.") and m.split(".")[1] in NAMES}
    assert named == set()


def test_every_validation_report_is_indexed():
    """docs/validation/README.md names every file and folder at the top of docs/validation."""
    folder = ROOT / "docs" / "validation"
    index = (folder / "README.md").read_text()
    missing = [p.name for p in folder.iterdir() if p.name != "README.md" and p.name not in index]
    assert missing == []


def test_study_functions_are_short():
    """No function of the study layer is longer than 60 lines (a study reads as stages)."""
    long = []
    for p in _sources("studies"):
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.end_lineno - node.lineno >= 60:
                long.append(f"{p.relative_to(ROOT)}:{node.lineno} {node.name}")
    assert long == []
