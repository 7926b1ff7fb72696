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


def _module_names() -> dict[str, Path]:
    """Dotted module name -> file, for every module of the package (and cli, reproducibility)."""
    mods = {}
    for pkg in PACKAGES:
        for p in _sources(pkg):
            parts = list(p.relative_to(ROOT).with_suffix("").parts)
            mods[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = p
    return mods | {"cli": ROOT / "cli.py", "reproducibility": ROOT / "reproducibility.py"}


def _import_graph() -> dict[str, dict[str, set[str]]]:
    """module -> {module it imports (anywhere in the file, lazy imports too): names taken}."""
    mods = _module_names()

    def owner(name: str) -> str | None:
        while name and name not in mods:
            name = name.rpartition(".")[0]
        return name or None

    graph = {}
    for mod, path in mods.items():
        base = mod.split(".") if path.name == "__init__.py" else mod.split(".")[:-1]
        deps: dict[str, set[str]] = {}
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                for a in node.names:
                    if owner(a.name):
                        deps.setdefault(owner(a.name), set()).add(a.name)
            elif isinstance(node, ast.ImportFrom):
                src = ".".join(base[:len(base) - node.level + 1] + [node.module or ""]).strip(".") if node.level \
                    else node.module
                for a in node.names:
                    target = owner(f"{src}.{a.name}") if f"{src}.{a.name}" in mods else owner(src)
                    if target:
                        deps.setdefault(target, set()).add(a.name)
        deps.pop(mod, None)
        graph[mod] = deps
    return graph


def _cycles(graph: dict[str, set]) -> list[list[str]]:
    """The strongly connected components of more than one node (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def _study_of(module: str) -> str | None:
    from studies import NAMES
    parts = module.split(".")
    return parts[1] if parts[0] == "studies" and len(parts) > 1 and parts[1] in NAMES else None


def test_no_import_circle():
    """No two modules import each other, directly or round a circle (lazy imports
    included: a circle hidden in a function is still one design), and no two studies do."""
    graph = _import_graph()
    assert _cycles(graph) == []
    studies = {}
    for mod, deps in graph.items():
        if _study_of(mod):
            studies.setdefault(_study_of(mod), set()).update(
                s for s in map(_study_of, deps) if s and s != _study_of(mod))
    assert _cycles(studies) == []


def test_no_study_takes_another_studys_private_names():
    """A study uses another study only through its public names (what it chose to offer)."""
    taken = [f"{mod} <- {dep}: {sorted(n for n in names if n.startswith('_'))}"
             for mod, deps in _import_graph().items() for dep, names in deps.items()
             if _study_of(mod) and _study_of(dep) and _study_of(mod) != _study_of(dep)
             and any(n.startswith("_") for n in names)]
    assert taken == []


def test_viz_names_no_study():
    """viz/ is generic: it imports no study, and none of its functions, classes or names
    is a study's (each study draws its own figures and lays out its own recording from
    viz's generic pieces)."""
    from studies import NAMES
    # "wall" names a study and the thing every study draws: viz may say wall, not import it
    words = (set(NAMES) - {"wall"}) | {"drystone", "sizkow", "oetomo"}
    named = []
    for p in _sources("viz"):
        tree = ast.parse(p.read_text())
        if any(m.split(".")[0] == "studies" for m in _modules_imported(p)):
            named.append(f"{p.relative_to(ROOT)} imports studies")
        for node in ast.walk(tree):
            name = getattr(node, "name", None) if isinstance(node, (ast.FunctionDef, ast.ClassDef)) else \
                node.id if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store) else None
            if name and any(w in name.lower() for w in words):
                named.append(f"{p.relative_to(ROOT)}:{node.lineno} {name}")
    assert named == []


def test_every_reference_file_has_one_schema():
    """Each study's reference.json: ``source`` (the paper, as text) and ``targets`` (the
    tolerances and readings of the paper's words the checks use, with their own
    ``source``: they are wallsim's, not the paper's), whatever else the paper gives."""
    import json

    from studies import all_studies
    files = [s.reference_file for s in all_studies() if getattr(s, "reference_file", None)]
    assert len(files) >= 5
    for path in files:
        ref = json.loads(Path(path).read_text())
        assert isinstance(ref.get("source"), str) and ref["source"], path
        targets = ref.get("targets")
        assert isinstance(targets, dict) and isinstance(targets.get("source"), str), path
        for key, value in targets.items():
            if not (key == "source" or key.endswith("_note")):
                assert isinstance(value, (int, float, list)), f"{path}: targets.{key}"
