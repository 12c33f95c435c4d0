"""The house's checks (issue 42, item 5): ruff and mypy on the package, run by CI.

The checks themselves run in ``.ci/run`` (the ``lint`` extra installs them); these tests
only hold the wiring in place, without the tools: CI's lines, the extra, and the settings
in ``pyproject.toml`` that the lines rely on.
"""
from __future__ import annotations

import shlex
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _ci_lines():
    """``.ci/run``'s command lines, split into words (comments and blanks left out)."""
    out = []
    for raw in (ROOT / ".ci" / "run").read_text().splitlines():
        words = shlex.split(raw, comments=True)
        if words:
            out.append(words)
    return out


def _pyproject():
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_ci_runs_ruff_and_mypy_on_the_package_before_the_tests():
    """Hypothesis: ``.ci/run`` installs the ``lint`` extra and runs ``ruff check
    vibimpact`` and ``mypy vibimpact``, each on a line of its own, before the fast test
    command (a failing check stops CI early: ``set -e``)."""
    lines = _ci_lines()
    assert ["set", "-euo", "pipefail"] in lines
    install = lines.index(["install", "-e", ".[lint]"])
    ruff = lines.index(["python", "-m", "ruff", "check", "vibimpact"])
    mypy = lines.index(["python", "-m", "mypy", "vibimpact"])
    tests = lines.index(["python", "-m", "pytest", "-q", "-n", "2"])
    assert install < ruff < tests and install < mypy < tests


def test_the_lint_extra_installs_both_tools():
    """Hypothesis: the ``lint`` extra names ruff and mypy, each with a floor."""
    extra = _pyproject()["project"]["optional-dependencies"]["lint"]
    names = {d.split(">=")[0].strip(): d for d in extra}
    assert set(names) == {"ruff", "mypy"}
    assert all(">=" in d for d in extra)


def test_ruff_settings_select_rules_and_sort_or_format_nothing():
    """Hypothesis: ``[tool.ruff.lint]`` selects its rules explicitly (pyflakes and
    bugbear among them), the line length is the code's 100 columns, and no selected rule
    rewrites a file wholesale (no import sorting ``I``, no ``ALL``)."""
    ruff = _pyproject()["tool"]["ruff"]
    select = ruff["lint"]["select"]
    assert ruff["line-length"] == 100
    assert {"F", "B", "E9"} <= set(select)
    assert not {"I", "ALL"} & set(select)


def test_mypy_settings_cover_the_package_on_python_311():
    """Hypothesis: ``[tool.mypy]`` checks ``vibimpact`` as Python 3.11 (the floor of
    requires-python), with unused or code-less ``type: ignore`` comments as errors."""
    mypy = _pyproject()["tool"]["mypy"]
    assert mypy["python_version"] == "3.11"
    assert mypy["files"] == ["vibimpact"]
    assert mypy["warn_unused_ignores"] is True
    assert "ignore-without-code" in mypy["enable_error_code"]
