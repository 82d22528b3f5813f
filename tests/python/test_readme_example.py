"""docs/python.md shows a complete program; this runs it as a user would, in a fresh
interpreter in an empty folder, and checks what it prints, so the page cannot drift from the
module."""

import os
import pathlib
import re
import subprocess
import sys

import dynrt

PAGE = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def python_example():
    blocks = re.findall(r"^```python\n(.*?)^```$", PAGE.read_text(), flags=re.S | re.M)
    assert blocks, "docs/python.md has no ```python block"
    return blocks[0]


def test_readme_python_example_runs(tmp_path):
    script = tmp_path / "example.py"
    script.write_text(python_example())
    # The module under test, wherever this run imported it from.
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(dynrt.__file__).resolve().parents[1]))
    run = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert len(lines) == 10, run.stdout
    # Every step after the first refits the whole cloth (19,602 triangles) and rays hit it.
    for line in lines[1:]:
        refitted, hits = map(int, re.match(r"step \d+: (\d+) triangles refitted in .* ms, (\d+) rays hit", line).groups())
        assert refitted == 2 * 99 * 99
        assert hits > 500
    image = tmp_path / "cloth.png"
    assert image.exists() and image.stat().st_size > 1000
