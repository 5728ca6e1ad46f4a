"""``python -m collisionkit``: the same entry point as the ``collisionkit`` script."""

from ._command import main

if __name__ == "__main__":
    main()
