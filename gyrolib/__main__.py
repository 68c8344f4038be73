"""``python -m gyrolib``: see :mod:`gyrolib.cli`."""

from gyrolib.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
