"""What the tests share: the repository's fixtures, and the holo command-line tool they run beside the package
(HOLO_CLI must name it; the tests that run it fail, not skip, without it)."""

import os
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "fixtures"


def cli():
    path = os.environ.get("HOLO_CLI")
    assert path, "HOLO_CLI must name the holo command-line tool (e.g. target/debug/holo)"
    return path
