"""`python -m mlctool`: the `mlc` command of this very package (tests use it, never PATH)."""

from mlctool.cli import main

if __name__ == "__main__":  # pragma: no cover
    main()
