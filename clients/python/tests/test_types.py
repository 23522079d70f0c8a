"""The package's annotations hold (mypy over the package and the examples, which use it as users do)."""
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1]


def test_mypy_passes():
    p = subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(PACKAGE / "pyproject.toml"),
                        "--cache-dir", "/dev/null", "depath", "examples"], cwd=PACKAGE, capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
