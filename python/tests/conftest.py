"""Shared fixtures: the atmosh command line whose --json output the bindings are
compared with (ATMOSH_BIN, set by ctest; else build/bin/atmosh of the source tree)."""

import json
import os
import subprocess

import pytest

_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _cli_path():
    p = os.environ.get("ATMOSH_BIN") or os.path.join(_ROOT, "build", "bin", "atmosh")
    return p if os.path.exists(p) else None


@pytest.fixture(scope="session")
def cli():
    """run(*args) -> parsed JSON of `atmosh args... --json`; err(*args) -> (exit code, stderr)."""
    path = _cli_path()
    if path is None:
        pytest.skip("the atmosh command line is not built")

    class Cli:
        @staticmethod
        def json(*args, cwd=None):
            out = subprocess.run([path, *map(str, args), "--json"], capture_output=True, text=True, check=True, cwd=cwd)
            return json.loads(out.stdout)

        @staticmethod
        def text(*args, cwd=None):
            return subprocess.run([path, *map(str, args)], capture_output=True, text=True, check=True, cwd=cwd).stdout

        @staticmethod
        def error(*args):
            r = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
            return r.returncode, r.stderr.strip()

    return Cli


def cli_message(stderr):
    """The one-line message of the CLI's "atmosh: error: MESSAGE" line."""
    prefix = "atmosh: error: "
    line = [s for s in stderr.splitlines() if s.startswith(prefix)][-1]
    return line[len(prefix):]
