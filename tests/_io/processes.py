"""A helper of the lock tests: another process that holds a lock while a test runs."""

import contextlib
import os


@contextlib.contextmanager
def held_by_another_process(code, path):
    """Run ``code`` (which takes a lock on ``path``, given as sys.argv[1]) in another process; yield its process id.

    The process holds what it took until the block ends.
    """
    import subprocess
    import sys
    from pathlib import Path

    source = f"import sys\n{code}\nprint('holding', flush=True)\nsys.stdin.read()\n"
    environment = os.environ | {"PYTHONPATH": str(Path(__file__).resolve().parents[2] / "src")}
    process = subprocess.Popen([sys.executable, "-c", source, str(path)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, env=environment)
    try:
        line = process.stdout.readline()
        assert line.strip() == "holding", process.stderr.read()
        yield process.pid
    finally:
        process.stdin.close()
        process.wait(timeout=60)


HOLD = "from collisionkit._io import exclusive\nheld = exclusive(sys.argv[1])\nheld.__enter__()"
