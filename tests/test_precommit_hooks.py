"""The pre-commit hooks of .pre-commit-hooks.yaml, run by pre-commit itself (`try-repo`) on a
scratch git repository holding a copy of samples/project.

`pre-commit try-repo` installs the hook package with pip into a fresh environment on every
call (about 10 s on a quiet machine, 40-70 s on a busy one), so this module runs only when
`CI` is set (.ci/run passes it through) and is skipped otherwise:
`CI=1 .venv/bin/pytest tests/test_precommit_hooks.py` runs it locally (docs/ci.md). Two calls
keep it short: a clean project passes all three hooks; a broken one fails `mlc-check` and
`mlc-fmt-check` (with `mlc-fmt` skipped, so the check-only hook is seen to change nothing).
`mlc-fmt` rewriting a file is `mlc fmt` itself (tests/test_fmt.py) under pre-commit's
"files were modified" rule.

try-repo takes a git repository and only the files its HEAD holds plus uncommitted changes to
tracked files; the hooks are installed from a snapshot instead: the files git sees in this
checkout (tracked and new, not ignored), committed to a scratch repository, so a new module
not yet added to git is installed too and a worktree checkout works the same as a clone.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tests.conftest import MLC_COMMAND, ROOT, SAMPLES

pytestmark = [
    pytest.mark.skipif(not os.environ.get("CI"),
                       reason="slow (pre-commit installs the hook package with pip): runs when CI is set"),
    pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed"),
]
pre_commit = pytest.importorskip("pre_commit", reason="pre-commit is not installed (pip install -e '.[test]')")

GIT_ENV = {"GIT_AUTHOR_NAME": "mlc test", "GIT_AUTHOR_EMAIL": "test@example.invalid",
           "GIT_COMMITTER_NAME": "mlc test", "GIT_COMMITTER_EMAIL": "test@example.invalid",
           "GIT_CONFIG_NOSYSTEM": "1"}


def _git(*args: str, cwd: Path) -> str:
    env = {**os.environ, **GIT_ENV}
    return subprocess.run(["git", *args], cwd=cwd, env=env, check=True, capture_output=True, text=True).stdout


def _commit_all(folder: Path) -> None:
    _git("init", "-q", cwd=folder)
    _git("add", "-A", cwd=folder)
    _git("commit", "-q", "--no-gpg-sign", "-m", "snapshot", cwd=folder)


@pytest.fixture(scope="module")
def hooks_repo(tmp_path_factory) -> Path:
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                            cwd=ROOT, capture_output=True)
    if listed.returncode != 0:
        pytest.skip("this source tree is not a git checkout")
    dest = tmp_path_factory.mktemp("mlctool-hooks")
    for name in filter(None, listed.stdout.decode().split("\0")):
        src = ROOT / name
        if src.is_file():  # deleted but still tracked files are left out
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)
    _commit_all(dest)
    return dest


@pytest.fixture
def project(tmp_path: Path) -> Path:
    dest = tmp_path / "plc"
    shutil.copytree(SAMPLES / "project", dest, ignore=shutil.ignore_patterns("build", "out"))
    _commit_all(dest)
    return dest


def _try_repo(hooks_repo: Path, project: Path, *args: str, skip: str = "") -> subprocess.CompletedProcess:
    env = {**os.environ, **GIT_ENV, "PRE_COMMIT_HOME": str(project.parent / "pre-commit-home"),
           "SKIP": skip, "PIP_NO_COMPILE": "1"}
    return subprocess.run([sys.executable, "-m", "pre_commit", "try-repo", str(hooks_repo), *args,
                           "--color", "never"], cwd=project, env=env, capture_output=True, text=True)


def _status(output: str, hook_name: str) -> str:
    line = next(ln for ln in output.splitlines() if ln.startswith(hook_name + "."))
    return line.rsplit(".", 1)[1].strip()


def test_hooks_file_declares_three_hooks():
    hooks = {h["id"]: h for h in yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())}
    assert set(hooks) == {"mlc-check", "mlc-fmt", "mlc-fmt-check"}
    assert hooks["mlc-check"]["pass_filenames"] is False
    assert hooks["mlc-fmt"]["entry"] == "mlc fmt" and hooks["mlc-fmt-check"]["entry"] == "mlc fmt --check"


def test_a_commit_of_one_module_passes_on_a_clean_project(hooks_repo, project):
    # only conveyor.il is staged; a module of the project is checked with the whole project
    # loaded (docs/project.md), so the labels pickplace.il exports resolve
    main = project / "src" / "conveyor.il"
    main.write_text(main.read_text() + "; a staged change\n")
    _git("add", "src/conveyor.il", cwd=project)
    alone = subprocess.run([*MLC_COMMAND, "check", "src/conveyor.il"], cwd=project, capture_output=True, text=True)
    assert alone.returncode == 0 and "E304" not in alone.stderr, alone.stderr
    r = _try_repo(hooks_repo, project)
    assert r.returncode == 0, r.stdout + r.stderr
    for name in ("mlc check", "mlc fmt", "mlc fmt --check"):
        assert _status(r.stdout, f"{name} (PLC instruction lists)") == "Passed"


def test_hooks_fail_on_a_broken_project(hooks_repo, project):
    lib, main = project / "src" / "pickplace.il", project / "src" / "conveyor.il"
    lib.write_text(lib.read_text().replace(".export P10 P11", ".export P10"))  # E304 in conveyor.il
    main.write_text(main.read_text().replace("SET     PICKING", "SET PICKING"))  # not canonical
    _git("add", "-A", cwd=project)
    before = main.read_text()

    r = _try_repo(hooks_repo, project, "--all-files", skip="mlc-fmt")
    assert r.returncode == 1
    assert _status(r.stdout, "mlc check (PLC instruction lists)") == "Failed"
    assert "E304" in r.stdout
    assert _status(r.stdout, "mlc fmt (PLC instruction lists)") == "Skipped"
    assert _status(r.stdout, "mlc fmt --check (PLC instruction lists)") == "Failed"
    assert "+SET     PICKING" in r.stdout  # the diff
    assert main.read_text() == before  # the check-only hook changes nothing

