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
