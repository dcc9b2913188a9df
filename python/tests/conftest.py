"""Shared fixtures: the repository, the CLI binary, a scratch working folder."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """Runs the platefield CLI (``$PLATEFIELD_BIN`` or target/release/platefield,
    which ``cargo test --release`` builds) and returns its stdout."""
    exe = os.environ.get("PLATEFIELD_BIN", str(ROOT / "target" / "release" / "platefield"))
    if not os.path.exists(exe):
        pytest.fail(f"{exe} not found: run `cargo build --release` (or set PLATEFIELD_BIN)")

    def run(*args):
        return subprocess.run([exe, *map(str, args)], check=True, capture_output=True, text=True).stdout

    return run


@pytest.fixture(autouse=True)
def scratch(tmp_path, monkeypatch):
    """Every test runs in its own empty folder (the basis cache lands there)."""
    monkeypatch.chdir(tmp_path)
    return tmp_path
