"""`mlc init`: the files of a new project (docs/getting-started.md).

A target gives its starter project as data beside its tables (`<tables>/starter/`: mlc.toml,
src/main.il, tests/start.stim, and what else the target needs, FBs its positioning table),
a project that passes `mlc check`, `mlc fmt --check` and `mlc test` as it is; every project
gets the same CI workflow (GitHub Actions) and pre-commit configuration, which run the same
commands. Writing (never over an existing file) is the CLI's.
"""

from __future__ import annotations

from pathlib import Path

from mlctool.targetapi.registry import target_package

STARTER = "starter"

WORKFLOW = """\
# CI for this PLC project (GitHub Actions; written by `mlc init`, docs/ci.md): check the
# sources, their layout, and run the scenarios with coverage; the reports are kept.
name: plc
on: [push, pull_request]
permissions:
  contents: read
jobs:
  plc:
    runs-on: ubuntu-latest
    steps:
      - uses: actions/checkout@v4
      - uses: actions/setup-python@v5
        with:
          python-version: "3.11"
      - run: pip install mlctool
      - name: check
        run: mlc check
      - name: layout
        run: mlc fmt --check
      - name: test
        run: mlc test --coverage --junit junit.xml
      - name: test report
        if: always()
        uses: actions/upload-artifact@v4
        with:
          name: plc-test-results
          path: |
            junit.xml
            coverage.xml
            mlc-test-out/
"""

PRE_COMMIT = """\
# pre-commit hooks (https://pre-commit.com; written by `mlc init`, docs/ci.md): run
# `pre-commit install` once; each commit then checks the project, its layout and its tests
# with the mlc on PATH.
repos:
  - repo: local
    hooks:
      - id: mlc-check
        name: mlc check
        entry: mlc check
        language: system
        pass_filenames: false
        files: (\\.(il|IL|pos|mpos|stim)|(^|/)mlc\\.toml)$
      - id: mlc-fmt-check
        name: mlc fmt --check
        entry: mlc fmt --check
        language: system
        files: \\.(il|IL)$
      - id: mlc-test
        name: mlc test
        entry: mlc test
        language: system
        pass_filenames: false
        files: (\\.(il|IL|pos|mpos|stim)|(^|/)mlc\\.toml)$
"""


def starter_folder(target_name: str) -> Path | None:
    """The target's starter project, or None when it gives none."""
    folder = target_package(target_name).tables / STARTER
    return folder if (folder / "mlc.toml").is_file() else None


def project_files(target_name: str) -> dict[str, bytes]:
    """Relative path ("src/main.il") -> content of a new project of the target, sorted by
    path (the same files in the same order on every run). {} when the target gives none."""
    folder = starter_folder(target_name)
    if folder is None:
        return {}
    files = {p.relative_to(folder).as_posix(): p.read_bytes()
             for p in sorted(folder.rglob("*")) if p.is_file() and "__pycache__" not in p.parts}
    files[".github/workflows/plc.yml"] = WORKFLOW.encode()
    files[".pre-commit-config.yaml"] = PRE_COMMIT.encode()
    return dict(sorted(files.items()))
