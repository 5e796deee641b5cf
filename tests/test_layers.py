"""The house rules of the package: the layers, a pure core, no private names across
modules, and a package list that ships every package."""

import ast
import pkgutil
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import mcbat
import mcbat.core
from tests.conftest import ROOT

# scipy is not in this list: numba itself imports parts of it when present. That the core
# never imports scipy is checked statically by the import-linter contract.
FORBIDDEN = ("pandas", "pyarrow", "matplotlib", "tqdm", "dask", "mcbat.api", "mcbat.cli")


def test_importing_every_core_module_loads_no_forbidden_package():
    modules = [m.name for m in pkgutil.walk_packages(mcbat.core.__path__, "mcbat.core.")]
    assert "mcbat.core.cabo2012.contact" in modules
    code = (
        "import importlib, sys\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module(name)\n"
        f"bad = sorted(m for m in sys.modules if m.split('.')[0] in {FORBIDDEN!r} "
        f"or m in {FORBIDDEN!r})\n"
        "print(','.join(bad))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert proc.stdout.strip() == ""


def test_import_linter_contracts_hold():
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent))
    assert exe, "import-linter is part of the test extra"
    proc = subprocess.run([exe], capture_output=True, text=True, cwd=ROOT, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    kept = len(contracts["contracts"])
    assert kept >= 5 and f"{kept} kept, 0 broken" in proc.stdout


def _python_files():
    return sorted((ROOT / "mcbat").rglob("*.py"))


def test_no_private_name_is_imported_across_modules():
    offenders = []
    for path in _python_files():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("mcbat"):
                offenders += [f"{path.relative_to(ROOT)}: {node.module}.{alias.name}"
                              for alias in node.names if alias.name.startswith("_")
                              and not alias.name.startswith("__")]
    assert offenders == []


def test_import_mcbat_is_light():
    code = ("import sys, mcbat\n"
            "heavy = ('numba', 'numpy', 'pandas', 'pyarrow', 'scipy', 'matplotlib')\n"
            "print(','.join(m for m in heavy if m in sys.modules))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert proc.stdout.strip() == ""
    assert callable(mcbat.solve) and callable(mcbat.run) and callable(mcbat.solve_frame)


def test_the_package_list_names_every_package():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
                 ["packages"])
    found = {".".join(p.relative_to(ROOT).parent.parts) for p in
             (ROOT / "mcbat").rglob("__init__.py")}
    assert found <= listed
    assert {"mcbat.data", "mcbat.studies"} <= listed


def test_every_public_module_declares_all():
    missing = []
    for path in _python_files():
        if path.name.startswith("_") and path.name != "__init__.py" or path.name == "__main__.py":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        names = {t.id for node in tree.body if isinstance(node, ast.Assign)
                 for t in node.targets if isinstance(t, ast.Name)}
        if "__all__" not in names:
            missing.append(str(path.relative_to(ROOT)))
    assert missing == []


def _top_level_imports(folder):
    """``{file: {top-level package}}`` of every import in a top-level folder's modules."""
    found = {}
    for path in sorted((ROOT / folder).rglob("*.py")):
        names = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names.add(node.module.split(".")[0])
        found[str(path.relative_to(ROOT))] = names
    return found


def test_benchmarks_and_validation_share_only_the_harness():
    # Speed (benchmarks/) and correctness (validation/) both run on harness/ and never
    # import each other; the harness imports neither.
    offenders = []
    for folder, other in (("benchmarks", {"validation"}), ("validation", {"benchmarks"}),
                          ("harness", {"benchmarks", "validation"})):
        imports = _top_level_imports(folder)
        assert imports, folder
        offenders += [f"{path} imports {sorted(names & other)}"
                      for path, names in imports.items() if names & other]
    assert offenders == []
    assert any("harness" in names for names in _top_level_imports("benchmarks").values())
    assert any("harness" in names for names in _top_level_imports("validation").values())


def test_no_validation_run_shares_a_name_with_a_module_of_mcbat_testing():
    # One name, one module: `validation.x` and `mcbat.testing.x` would be two different
    # things behind the same name in commands, imports and docs.
    testing = {p.stem for p in (ROOT / "mcbat" / "testing").glob("*.py")} - {"__init__"}
    runs = {p.stem for p in (ROOT / "validation").glob("*.py")} - {"__init__", "__main__"}
    assert testing and runs
    assert testing & runs == set()


def test_tests_import_the_top_level_folders_as_packages():
    # No test loads a module by its path or edits sys.path: validation, benchmarks and the
    # harness are imported as packages from the repository's root (pytest's pythonpath).
    offenders = []
    for path in sorted((ROOT / "tests").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            called = ast.unparse(node.func)
            if called.endswith("spec_from_file_location") or called.startswith("sys.path."):
                offenders.append(f"{path.relative_to(ROOT)}:{node.lineno}: {called}")
    assert offenders == []
