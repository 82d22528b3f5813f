"""The README and the user guide (docs/) against the code they describe (issue 37).

- README.md stays short (at most 150 lines), and every heading the README had before it was
  split (docs/readme_headings.txt) is still a heading of the README or of a page in docs/.
- Every relative link of README.md and docs/*.md names a file that exists, and a `#anchor` a
  heading of that file.
- Every code block below a `<!-- runnable -->` line runs (a block that builds or installs is not
  marked: it would write into the build under test, which the copy links to): `sh` with bash in a copy of the
  repository's layout (the dynrt under test on PATH and as build/release/engine/dynrt), `python`
  with this interpreter and the module under test, `cpp` compiled against the API headers and
  linked with the libdynrt under test. `<!-- runnable: embree -->` blocks are skipped when this
  dynrt was built without Embree.
- Every `--flag` the pages name is one `dynrt --help`, `dynrt render --help`, `dynrt bench --help`
  or `dynrt info --help` lists, or one of the other programs' flags in OTHER_PROGRAMS_FLAGS.
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest

import dynrt

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
CLI = os.environ.get("DYNRT_CLI", "")

# Flags the pages name that belong to other programs: scripts, examples, CMake, ctest, Google
# Benchmark, mpirun, pytest, Doxygen. A dynrt flag missing from --help is not to be added here.
OTHER_PROGRAMS_FLAGS = {
    # scripts/frame_suite.py, scripts/frame_timing.py, scripts/fuzz.sh
    "--reference", "--candidate", "--only", "--keep", "--regrouped", "--memory", "--rounds",
    # the examples (engine/examples, engine/python/examples)
    "--steps", "--order", "--azimuths", "--channels", "--check",
    # the stress suite (tests/stress)
    "--stress",
    # cmake, ctest, pkg-config, the compiler
    "--install", "--prefix", "--build", "--target", "--cflags", "--libs", "--output-on-failure",
    # Google Benchmark
    "--benchmark_filter", "--benchmark_repetitions", "--benchmark_report_aggregates_only",
    "--benchmark_min_time", "--benchmark_format", "--benchmark_out", "--benchmark_out_format",
    # mpirun
    "--oversubscribe", "--host", "--hostfile", "--np", "--allow-run-as-root", "--mca", "--bind-to",
    # git, timeout, ffmpeg, gnuplot, python
    "--signal",
}


def page_texts():
    return {page: page.read_text() for page in PAGES}


def strip_fences(text):
    return re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)


def headings(text):
    return [m.group(2).strip() for m in re.finditer(r"^(#{1,4}) (.+)$", strip_fences(text), flags=re.M)]


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation gone, spaces to hyphens."""
    s = re.sub(r"[`*]", "", heading.strip().lower())
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def test_readme_is_short():
    lines = (ROOT / "README.md").read_text().splitlines()
    assert len(lines) <= 150, f"README.md has {len(lines)} lines; move detail into docs/"


def test_every_heading_of_the_old_readme_has_a_home():
    old = [line.strip() for line in (ROOT / "docs" / "readme_headings.txt").read_text().splitlines()
           if line.strip() and not line.startswith("#")]
    assert len(old) > 30
    now = set()
    for text in page_texts().values():
        now.update(headings(text))
    missing = [h for h in old if h not in now]
    assert not missing, f"headings of the old README with no home in docs/: {missing}"


def links():
    for page, text in page_texts().items():
        for m in re.finditer(r"\[[^\]]*\]\(([^)\s]+)\)", strip_fences(text)):
            href = m.group(1)
            if re.match(r"^(https?:|mailto:)", href):
                continue
            yield page, href


def test_relative_links_resolve():
    broken = []
    for page, href in links():
        path, _, anchor = href.partition("#")
        target = (page.parent / path).resolve() if path else page
        if not target.exists():
            broken.append(f"{page.relative_to(ROOT)}: {href} (no such file)")
            continue
        if anchor and target.suffix == ".md":
            anchors = {slug(h) for h in headings(target.read_text())}
            if anchor not in anchors:
                broken.append(f"{page.relative_to(ROOT)}: {href} (no such heading)")
    assert not broken, "\n".join(broken)


def runnable_blocks():
    blocks = []
    for page, text in page_texts().items():
        for m in re.finditer(r"^<!-- runnable(?::\s*(\w+))? -->\n```(\w+)\n(.*?)^```$", text, flags=re.S | re.M):
            need, language, code = m.group(1), m.group(2), m.group(3)
            line = text[:m.start()].count("\n") + 1
            blocks.append(pytest.param(need, language, code, id=f"{page.relative_to(ROOT)}:{line}"))
    return blocks


def test_runnable_blocks_exist():
    assert len(runnable_blocks()) >= 4


def dynrt_has_embree():
    run = subprocess.run([CLI, "bench", "sphere:200", "--res", "16x16", "--repeat", "1", "--warmup", "0",
                          "--vs", "embree", "-q"], capture_output=True, text=True, timeout=300)
    return "built without Embree" not in run.stderr


def layout(tmp_path):
    """A folder laid out as the repository (its top-level entries linked), with the build under
    test as build/release and ../shared beside it, where a block writes what it makes."""
    repo = tmp_path / "repo"
    repo.mkdir()
    for entry in ROOT.iterdir():
        if entry.name not in ("build", "out", ".git"):
            (repo / entry.name).symlink_to(entry)
    build = pathlib.Path(CLI).resolve().parents[1]
    (repo / "build").mkdir()
    (repo / "build" / "release").symlink_to(build)
    shared = ROOT.parent / "shared"
    if shared.exists():
        (tmp_path / "shared").symlink_to(shared)
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "dynrt").symlink_to(pathlib.Path(CLI).resolve())
    return repo, bin_dir, build


@pytest.mark.heavy
@pytest.mark.parametrize("need,language,code", runnable_blocks())
def test_runnable_block_runs(need, language, code, tmp_path):
    if not CLI:
        pytest.skip("DYNRT_CLI is not set (scripts/run_tests.sh sets it)")
    if need == "embree" and not dynrt_has_embree():
        pytest.skip("this dynrt was built without Embree")
    repo, bin_dir, build = layout(tmp_path)
    module_dir = str(pathlib.Path(dynrt.__file__).resolve().parents[1])
    env = dict(os.environ, PATH=f"{bin_dir}:{os.environ.get('PATH', '')}", PYTHONPATH=module_dir)
    if language == "sh":
        command = ["bash", "-euo", "pipefail", "-c", code]
    elif language == "python":
        (tmp_path / "block.py").write_text(code)
        command = [sys.executable, str(tmp_path / "block.py")]
    elif language == "cpp":
        compiler = shutil.which("c++") or shutil.which("g++")
        if compiler is None:
            pytest.skip("no C++ compiler")
        (tmp_path / "block.cpp").write_text(code)
        lib = build / "engine"
        subprocess.run([compiler, "-std=c++20", "-I", str(ROOT / "engine" / "include"), str(tmp_path / "block.cpp"),
                        "-o", str(tmp_path / "block"), f"-L{lib}", "-ldynrt", f"-Wl,-rpath,{lib}", "-ltbb"],
                       check=True, timeout=300)
        command = [str(tmp_path / "block")]
    else:
        pytest.fail(f"a runnable block of unknown language {language!r}")
    run = subprocess.run(command, cwd=repo, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"exit {run.returncode}\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}"


def documented_flags():
    flags = {}
    for page, text in page_texts().items():
        for m in re.finditer(r"(?<![\w\-/.=])(--[a-z][a-z0-9_\-]*[a-z0-9])", text):
            flags.setdefault(m.group(1), f"{page.relative_to(ROOT)}:{text[:m.start()].count(chr(10)) + 1}")
    return flags


def test_documented_flags_exist():
    if not CLI:
        pytest.skip("DYNRT_CLI is not set (scripts/run_tests.sh sets it)")
    help_text = ""
    for command in ([], ["render"], ["bench"], ["info"], ["view"]):
        run = subprocess.run([CLI, *command, "--help"], capture_output=True, text=True, timeout=60)
        assert run.returncode == 0, run.stderr
        help_text += run.stdout
    listed = set(re.findall(r"(--[a-z][a-z0-9_\-]*[a-z0-9])", help_text))
    missing = {flag: where for flag, where in documented_flags().items()
               if flag not in listed and flag not in OTHER_PROGRAMS_FLAGS}
    assert not missing, "flags the docs name that no --help lists: " + ", ".join(
        f"{flag} ({where})" for flag, where in sorted(missing.items()))
