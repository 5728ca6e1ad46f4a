"""Sphinx configuration of the collisionkit documentation.

Build: ``python -m sphinx -W --keep-going -b html docs docs/_build/html``
(needs ``pip install -e '.[docs]'``).

The API reference is generated here, at configuration time: one page per
public module found by walking the ``collisionkit`` package, so modules added
later are documented without editing these files. The CLI reference is
generated from the typer app (every registered command and its options), and
the gallery and the validation page run their scripts at build time
(sphinx-gallery).
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
os.environ.setdefault("NUMBA_CACHE_DIR", str(ROOT / ".numba_cache"))
os.environ.setdefault("MPLBACKEND", "Agg")

import collisionkit  # noqa: E402

project = "collisionkit"
author = "collisionkit developers"
copyright = "collisionkit developers"
release = version = collisionkit.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]

exclude_patterns = ["_build", "**/GALLERY_HEADER.rst", "validation_src"]
templates_path = []
html_theme = "alabaster"
html_theme_options = {"description": "Exact binary-collision physics", "fixed_sidebar": True}
html_static_path = []

autodoc_member_order = "bysource"
autodoc_typehints = "none"  # the numpydoc docstrings carry the types
autodoc_default_options = {
    "members": True,
    "show-inheritance": True,
    "ignore-module-all": True,
    # methods from private base classes (HardSphereSystem's, the run parameters') are documented on the class;
    # those of Python's own bases are not
    "inherited-members": "object,BaseException,Exception,ValueError,RuntimeError,UserWarning,Warning,dict,tuple,"
                         "BaseModel,TwoBodyOrbit,RelativeOrbit,ContactMixin",  # public bases: their own pages
}
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_ivar = True
napoleon_use_rtype = False

sphinx_gallery_conf = {
    "examples_dirs": ["../examples", "validation_src"],
    "gallery_dirs": ["auto_examples", "validation"],
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "show_memory": False,
}


# ---------------------------------------------------------------- API pages, generated


def public_modules(package=collisionkit):
    """Names of collisionkit and every submodule without a leading underscore in its path."""
    names = [package.__name__]
    for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


def _write_if_changed(path: Path, text: str) -> None:
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _module_page(name: str) -> str:
    title = f"``{name}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {name}", ""]
    module = importlib.import_module(name)
    exported = [
        item for item in getattr(module, "__all__", [])
        if getattr(getattr(module, item), "__module__", name) not in (name, None)
        and not isinstance(getattr(module, item), type(module))
    ]  # fmt: skip
    if exported:
        lines += ["Also available here (documented where they are defined):", ""]
        for item in exported:
            obj = getattr(module, item)
            role = "class" if isinstance(obj, type) else "func" if callable(obj) else "data"
            lines.append(f"- :py:{role}:`{item} <{obj.__module__}.{getattr(obj, '__qualname__', item)}>`")
        lines.append("")
    return "\n".join(lines)


def write_api_pages(app=None) -> None:
    folder = HERE / "api"
    folder.mkdir(exist_ok=True)
    modules = public_modules()
    for stale in folder.glob("*.rst"):
        if stale.stem != "index" and stale.stem not in modules:
            stale.unlink()
    for name in modules:
        _write_if_changed(folder / f"{name}.rst", _module_page(name))
    toc = "\n".join(f"   {name}" for name in modules)
    index = (
        "API reference\n=============\n\n"
        "Every public module of the package, from its numpydoc docstrings. The collision core is also\n"
        "importable from the top level (``import collisionkit as ck; ck.resolve_contact(...)``).\n\n"
        f".. toctree::\n   :maxdepth: 1\n\n{toc}\n"
    )
    _write_if_changed(folder / "index.rst", index)


# ---------------------------------------------------------------- CLI reference, generated


def _rst_text(text: str) -> str:
    """Help text as RST: rich's escaped brackets kept, inline markup characters escaped."""
    text = " ".join((text or "").split())
    return re.sub(r"([*|`])", r"\\\1", text)


def _option_signature(param) -> str:
    names = [*param.opts, *getattr(param, "secondary_opts", [])]
    if getattr(param, "is_flag", False) or getattr(param, "count", False):
        return ", ".join(names)
    return ", ".join(f"{name} <{param.name}>" for name in param.opts) + "".join(
        f", {name}" for name in getattr(param, "secondary_opts", [])
    )


def cli_reference() -> str:
    """RST for every command of the ``collisionkit`` typer app and its options."""
    import typer.main

    from collisionkit.cli import app

    group = typer.main.get_command(app)
    lines = []
    for name in sorted(group.commands):
        command = group.commands[name]
        title = f"collisionkit {name}"
        lines += [title, "-" * len(title), "", f".. program:: collisionkit-{name}", ""]
        help_text = (command.help or "").strip()
        if help_text:
            lines += [_rst_text(help_text.split("\n\n")[0]), ""]
        lines += [".. code-block:: text", "", f"   collisionkit {name} [OPTIONS]", ""]
        for param in command.params:
            if param.param_type_name != "option" or param.name == "help" or getattr(param, "hidden", False):
                continue
            lines += [f".. option:: {_option_signature(param)}", "", f"   {_rst_text(param.help)}", ""]
    return "\n".join(lines)


def write_generated_pages(app=None) -> None:
    write_api_pages()
    _write_if_changed(HERE / "api" / "cli_commands.rst.inc", cli_reference())


write_generated_pages()


# ---------------------------------------------------------------- docstrings: |x| is an absolute value

_CODE = re.compile(r"(:\w+:`[^`]*`|``[^`]*``|`[^`]*`_?)")


def _escape_bars(line: str) -> str:
    """Escape ``|`` outside inline code and roles: docstrings write |v| for a norm, not a substitution."""
    parts = _CODE.split(line)
    return "".join(part if index % 2 else part.replace("|", "\\|") for index, part in enumerate(parts))


def escape_absolute_values(app, what, name, obj, options, lines) -> None:
    """Keep plain-text |x| in docstrings from being read as RST substitutions (math and code untouched)."""
    block_indent = None  # indentation of a literal, math or doctest block being skipped
    for index, line in enumerate(lines):
        stripped = line.strip()
        indent = len(line) - len(line.lstrip())
        if block_indent is not None:
            if not stripped and block_indent >= 0:
                continue
            if block_indent == -1:  # a doctest block ends at a blank line
                if not stripped:
                    block_indent = None
                continue
            if indent > block_indent:
                continue
            block_indent = None
        if stripped.startswith(">>>"):
            block_indent = -1
            continue
        if stripped.startswith(".. ") or stripped.endswith("::"):
            block_indent = indent
            continue
        lines[index] = _escape_bars(line)


def setup(app):
    app.connect("autodoc-process-docstring", escape_absolute_values)
