"""What the benchmark scripts share: a function of a benchmark module run in a fresh process, the source tree of
another git revision, and the writing of a results table (Markdown and JSON) to ``benchmarks/results``."""

from __future__ import annotations

import io
import json
import subprocess
import sys
import tarfile
from pathlib import Path

from collisionkit._io import atomic_write_text

BENCHMARKS = Path(__file__).parent
RESULTS = BENCHMARKS / "results"


def json_in_fresh_process(module: str, call: str) -> dict:
    """``module.call`` (Python source, e.g. ``"one_run(864, 'cells')"``) evaluated in a fresh interpreter, its
    value JSON-encoded there and decoded here: each run gets its own peak memory and numba state."""
    code = (f"import json, sys; sys.path.insert(0, {str(BENCHMARKS)!r}); import {module}; "
            f"print(json.dumps({module}.{call}))")
    output = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    return json.loads(output.strip().splitlines()[-1])


def write_results(name: str, text: str, data: dict) -> None:
    """Print ``text`` and write it to ``results/<name>.md`` and ``data`` to ``results/<name>.json``, atomically."""
    print(text)
    RESULTS.mkdir(exist_ok=True)
    atomic_write_text(RESULTS / f"{name}.md", text)
    atomic_write_text(RESULTS / f"{name}.json", json.dumps(data, indent=2) + "\n")


def exported_source(revision: str, into: Path) -> str:
    """The ``src`` tree of git ``revision`` of this repository, written under ``into``; its path."""
    repository = BENCHMARKS.resolve().parent
    archive = subprocess.run(["git", "-C", str(repository), "archive", "--format=tar", revision, "src"],
                             check=True, capture_output=True).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(into, filter="data")
    return str(into / "src")
