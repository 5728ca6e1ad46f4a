"""Documentation checks: examples in every public docstring, runnable guides and README commands.

* Every public function, class and method (walking ``collisionkit`` and all
  its submodules, skipping names with a leading underscore) has a numpydoc
  docstring with an ``Examples`` section. Properties are attributes, not
  methods, and are not required to have one. The doctests themselves run in
  the main test suite (``--doctest-modules``).
* The guides' ``>>>`` examples (``docs/*.rst``, ``docs/guide/*.rst``) run as doctests.
* The README's quick-start commands run: the demo, exactly as written, with
  this interpreter's ``collisionkit`` script; the test-suite command is not
  run recursively: it must be the command that ``.ci/run`` runs.
"""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import collisionkit

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES_SECTION = re.compile(r"^\s*Examples\n\s*-{8,}\s*$", re.MULTILINE)

# Public objects that had no Examples section when this test was written, in
# modules the documentation work could not edit. The test fails for any
# offender NOT listed here, and for any entry listed here that has since been
# fixed (so the list only shrinks). Please add an Examples section and delete
# the entry rather than adding entries.
KNOWN_MISSING: set[str] = set()


def public_modules():
    """collisionkit and every submodule with no leading underscore anywhere in its dotted name."""
    names = ["collisionkit"]
    for info in pkgutil.walk_packages(collisionkit.__path__, "collisionkit."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return names


def public_objects():
    """(dotted name, object) of every public function, class and method defined in a public module."""
    for module_name in public_modules():
        module = importlib.import_module(module_name)
        for name, obj in vars(module).items():
            if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if getattr(obj, "__module__", None) != module_name:
                continue  # imported from elsewhere: checked where it is defined
            dotted = f"{module_name}.{name}"
            yield dotted, obj
            if inspect.isclass(obj):
                for member_name, member in vars(obj).items():
                    if member_name.startswith("_"):
                        continue
                    function = member.__func__ if isinstance(member, (staticmethod, classmethod)) else member
                    if inspect.isfunction(function):
                        yield f"{dotted}.{member_name}", function


def lacks_examples(obj) -> bool:
    return not EXAMPLES_SECTION.search(obj.__doc__ or "")


def test_the_walk_finds_the_main_modules():
    names = public_modules()
    for expected in ("collisionkit.collisions", "collisionkit.edmd", "collisionkit.encounters", "collisionkit.plotting"):
        assert expected in names
    assert not any("._" in name for name in names)


def test_every_public_function_class_and_method_has_an_examples_section():
    offenders = sorted(name for name, obj in public_objects() if lacks_examples(obj) and name not in KNOWN_MISSING)
    assert not offenders, (
        "these public objects need a numpydoc docstring with an 'Examples' section:\n  " + "\n  ".join(offenders)
    )


def test_known_missing_lists_only_current_offenders():
    offenders = {name for name, obj in public_objects() if lacks_examples(obj)}
    fixed = sorted(KNOWN_MISSING - offenders)
    assert not fixed, (
        "these now have an Examples section (or no longer exist): delete them from KNOWN_MISSING in "
        "tests/test_docs.py:\n  " + "\n  ".join(fixed)
    )


GUIDES = sorted([*(ROOT / "docs").glob("*.rst"), *(ROOT / "docs" / "guide").glob("*.rst")])


@pytest.mark.parametrize("path", GUIDES, ids=lambda path: path.relative_to(ROOT / "docs").as_posix())
def test_guide_examples_run(path):
    result = doctest.testfile(
        str(path), module_relative=False, verbose=False,
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
    )  # fmt: skip
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in {path.name} failed (see output)"


def test_the_guides_exist_for_each_capability():
    names = {path.stem for path in (ROOT / "docs" / "guide").glob("*.rst")}
    assert {"collisions", "edmd", "encounters", "transport", "sweeps"} <= names


# ---------------------------------------------------------------- README quick start


def quick_start_commands():
    """The commands of the two bash blocks after '## Quick start' in the README."""
    text = (ROOT / "README.md").read_text()
    section = text.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```bash\n(.*?)```", section, re.DOTALL)
    assert len(blocks) == 2, "the README's quick start must hold two bash blocks (demo, test suite)"
    return [block.strip() for block in blocks]


def split_steps(command):
    return [shlex.split(step) for step in command.split("&&")]


def test_readme_demo_setup_uses_an_existing_extra():
    demo, _ = quick_start_commands()
    steps = split_steps(demo)
    assert steps[0][:3] == ["python3", "-m", "venv"]
    install = steps[1]
    assert install[:2] == [".venv/bin/pip", "install"] and "-e" in install
    extra = re.fullmatch(r"\.\[(\w+)\]", install[-1])
    assert extra, f"expected an editable install of an extra, got {install[-1]!r}"
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert extra.group(1) in extras


def test_readme_demo_command_runs(tmp_path):
    demo, _ = quick_start_commands()
    steps = split_steps(demo)
    program, *arguments = steps[-1]
    assert program == ".venv/bin/collisionkit", program
    script = Path(sys.executable).parent / "collisionkit"  # the script of the venv running the tests
    assert script.exists(), f"no collisionkit script next to {sys.executable}"
    result = subprocess.run([str(script), *arguments], cwd=tmp_path, capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stdout + result.stderr
    out = tmp_path / arguments[arguments.index("--out") + 1]
    assert (out / "summary.json").is_file()
    assert any(out.glob("*.png"))


def test_readme_test_command_is_what_ci_runs():
    _, tests = quick_start_commands()
    ci_lines = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    assert tests in ci_lines, f".ci/run does not run the README's test command {tests!r}"
