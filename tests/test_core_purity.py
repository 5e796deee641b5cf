"""The physics core stays pure: no pandas, pyarrow, matplotlib or CLI/API code in it."""

import pkgutil
import shutil
import subprocess
import sys
from pathlib import Path

import mcbat.core

ROOT = Path(__file__).resolve().parents[1]
FORBIDDEN = ("pandas", "pyarrow", "matplotlib", "tqdm", "dask", "mcbat.api", "mcbat.cli")


def test_importing_every_core_module_loads_no_forbidden_package():
    modules = [m.name for m in pkgutil.walk_packages(mcbat.core.__path__, "mcbat.core.")]
    assert "mcbat.core.cabo2012.contact" in modules
    code = (
        "import importlib, sys\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module(name)\n"
        f"bad = sorted(m for m in sys.modules if m.split('.')[0] in {FORBIDDEN!r} or m in {FORBIDDEN!r})\n"
        "print(','.join(bad))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert proc.stdout.strip() == ""


def test_import_linter_contract_holds():
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent))
    assert exe, "import-linter is part of the test extra"
    proc = subprocess.run([exe], capture_output=True, text=True, cwd=ROOT, check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "1 kept, 0 broken" in proc.stdout
