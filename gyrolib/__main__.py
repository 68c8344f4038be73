"""``python -m gyrolib``: see :mod:`gyrolib.cli`."""

from gyrolib.cli import entry

if __name__ == "__main__":
    entry()
