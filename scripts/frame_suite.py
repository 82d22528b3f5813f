#!/usr/bin/env python3
"""Renders a suite of scenes and modes with two dynrt binaries and says where they differ.

For refactoring the frame path (issue 36): the images, AOVs and the reports' counts must stay
bit-identical to a reference binary's (an older build: `git worktree add ../ref REV` and build
it there). Every case renders a few frames at a small size with both binaries into their own
folders, then compares
  - each frame's image (binary PPM, so the bytes are the pixels) byte for byte,
  - each AOV (float EXR) byte for byte, but for the second it was written (its capDate),
  - each report's numbers (and its frames' .jsonl stream), leaving out what measures time (keys ending in _ms, _per_s or _per_s_per_depth, the
    summary of medians, the update planner's measured choices) and the thread count.

    /usr/bin/python3 scripts/frame_suite.py --reference ../ref/build/release/engine/dynrt \\
        [--candidate build/release/engine/dynrt] [--only NAME] [--keep DIR] [--regrouped]

Exit status 0 when every case agrees, 1 when one differs (each difference is printed), 2 on a
usage error. Scenes from ../shared/scenes are skipped, with a line saying so, when absent.
"""

import argparse
import filecmp
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "scenes")
sys.path.insert(0, HERE)
from suite_cases import selected_cases  # noqa: E402

# Deterministic updates: the default planner ('auto') picks refit or rebuild from measured
# times, which may differ between two runs of the same binary.
COMMON = ["--res", "160x120", "--update", "threshold", "-q"]

# (name, scene, extra flags). A scene starting with "shared:" is read from ../shared/scenes.
CASES = [
    ("bundled-packet", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-3"]),
    ("bundled-single", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-3", "--tracer", "single"]),
    ("bundled-binary", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-1", "--bvh", "binary"]),
    ("bundled-aovs", os.path.join(ROOT, "scenes", "default.gltf"),
     ["--frames", "0-1", "--aov", "depth,object,prim,normal"]),
    ("bundled-reuse-exact", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-5", "--reuse", "exact"]),
    ("bundled-reuse-off", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-2", "--reuse", "off"]),
    ("bundled-cache", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-5", "--reuse", "cache:0.25"]),
    ("bundled-frameless", os.path.join(ROOT, "scenes", "default.gltf"),
     ["--frames", "0-5", "--reuse", "frameless:0.25"]),
    ("bundled-adaptive", os.path.join(ROOT, "scenes", "default.gltf"), ["--frames", "0-2", "--adaptive", "0.02"]),
    ("sphere-wave", "sphere:20000", ["--frames", "0-3", "--anim", "wave"]),
    ("sphere-explode", "sphere:20000", ["--frames", "0-3", "--anim", "explode"]),
    ("sphere-flat", "sphere:20000", ["--frames", "0", "--normals", "flat"]),
    ("cesiumman-textured", "shared:cesiumman/CesiumMan.glb", ["--frames", "0-3"]),
    ("fox-reuse-exact", "shared:fox/Fox.glb", ["--frames", "0-3", "--reuse", "exact"]),
    ("kitchen-whitted-0", "shared:bart/kitchen/kitchen.aff", ["--frames", "0-1", "--depth", "0"]),
    ("kitchen-whitted-5", "shared:bart/kitchen/kitchen.aff", ["--frames", "0-2", "--depth", "5"]),
    ("kitchen-whitted-5-single", "shared:bart/kitchen/kitchen.aff",
     ["--frames", "0", "--depth", "5", "--tracer", "single"]),
    ("robots-instances", "shared:bart/robots/Robot.aff", ["--frames", "0-2"]),
    ("museum", "shared:bart/museum/museum5.aff", ["--frames", "0-1"]),
]

TIMING_SUFFIXES = ("_ms", "_per_s", "_per_s_per_depth")
# Where each side writes (the journal's settings name it) differs by design.
UNCOMPARED_KEYS = {"--out", "--report", "summary", "threads", "rebuilds", "objects_refitted", "objects_rebuilt",
                   "triangles_refitted", "triangles_rebuilt", "sah_cost", "nodes", "leaves",
                   "leaf_tris_mean", "leaf_tris_max", "depth",
                   # The process's resident set varies from run to run.
                   "rss_bytes", "peak_rss_bytes"}


# How the secondary rays were grouped into packets: what regrouping them changes (--regrouped).
GROUPING_KEYS = {"secondary_packet_rays", "secondary_single_rays", "secondary_packet_rays_per_depth"}
uncompared = set(UNCOMPARED_KEYS)


def counts_of(value):
    """The report without what measures time or follows from measured times."""
    if isinstance(value, dict):
        return {k: counts_of(v) for k, v in value.items()
                if k not in uncompared and not k.endswith(TIMING_SUFFIXES)}
    if isinstance(value, list):
        return [counts_of(v) for v in value]
    return value


def render(binary, scene, flags, folder):
    os.makedirs(folder, exist_ok=True)
    command = [binary, "render", scene, *COMMON, *flags,
               "--out", os.path.join(folder, "%04d.ppm"), "--report", os.path.join(folder, "report.json")]
    run = subprocess.run(command, capture_output=True, text=True, timeout=900)
    return run.returncode, run.stdout + run.stderr


def without_new_keys(reference, candidate, added, path=""):
    """`candidate` without the keys `reference` lacks (a report field or job setting the
    candidate added); their paths go into `added`."""
    if isinstance(reference, dict) and isinstance(candidate, dict):
        kept = {}
        for k, v in candidate.items():
            if k in reference:
                kept[k] = without_new_keys(reference[k], v, added, path + "." + k)
            else:
                added.add((path + "." + k).lstrip("."))
        return kept
    if isinstance(reference, list) and isinstance(candidate, list) and len(reference) == len(candidate):
        return [without_new_keys(a, b, added, path) for a, b in zip(reference, candidate)]
    return candidate


def without_capture_date(data):
    """An EXR's bytes with its capDate attribute's value (the second it was written) blanked."""
    at = data.find(b"capDate\0string\0")
    if at < 0:
        return data
    start = at + len(b"capDate\0string\0")
    length = int.from_bytes(data[start:start + 4], "little")
    return data[:start + 4] + b"\0" * length + data[start + 4 + length:]


def same_file(a, b):
    if not a.endswith(".exr"):
        return filecmp.cmp(a, b, shallow=False)
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return without_capture_date(fa.read()) == without_capture_date(fb.read())


def compare(case, reference_folder, candidate_folder, added):
    """The differences between two folders' renders; keys only the candidate's reports have go
    into `added` (reported, not differences)."""
    problems = []
    reference_files = sorted(f for f in os.listdir(reference_folder) if not f.startswith("."))
    candidate_files = sorted(f for f in os.listdir(candidate_folder) if not f.startswith("."))
    if reference_files != candidate_files:
        problems.append(f"{case}: different files: {reference_files} against {candidate_files}")
    for name in reference_files:
        if name == "report.json" or name not in candidate_files:
            continue
        if name.endswith(".jsonl"):  # the report's frames as they came: numbers compared
            with open(os.path.join(reference_folder, name)) as a, open(os.path.join(candidate_folder, name)) as b:
                ca, cb = [counts_of(json.loads(l)) for l in a], [counts_of(json.loads(l)) for l in b]
                if ca != without_new_keys(ca, cb, added):
                    problems.append(f"{case}: {name} differs in its counts")
            continue
        if not same_file(os.path.join(reference_folder, name), os.path.join(candidate_folder, name)):
            problems.append(f"{case}: {name} differs")
    with open(os.path.join(reference_folder, "report.json")) as a, open(os.path.join(candidate_folder, "report.json")) as b:
        ra, rb = counts_of(json.load(a)), counts_of(json.load(b))
    rb = without_new_keys(ra, rb, added)
    if ra != rb:
        for i, (fa, fb) in enumerate(zip(ra.get("frames", []), rb.get("frames", []))):
            differing = sorted(k for k in set(fa) | set(fb) if fa.get(k) != fb.get(k))
            if differing:
                problems.append(f"{case}: report frame {i}: " +
                                ", ".join(f"{k} {fa.get(k)!r} against {fb.get(k)!r}" for k in differing))
        if ra.get("run") != rb.get("run") or len(ra.get("frames", [])) != len(rb.get("frames", [])):
            problems.append(f"{case}: report run or frame count differs")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--reference", required=True, help="the dynrt binary whose frames are right")
    parser.add_argument("--candidate", default=os.path.join(ROOT, "build", "release", "engine", "dynrt"))
    parser.add_argument("--only", action="append", default=[], help="run the cases whose name contains this")
    parser.add_argument("--keep", help="render into this folder and keep it (default: a temporary one)")
    parser.add_argument("--regrouped", action="store_true",
                        help="leave out how secondary rays were grouped into packets (for a change that regroups them)")
    parser.add_argument("--memory", action="store_true",
                        help="leave out the memory figures (for a change that moves what is held, not what is drawn)")
    args = parser.parse_args()
    if args.regrouped:
        uncompared.update(GROUPING_KEYS)
    if args.memory:
        uncompared.add("memory")
    for binary in (args.reference, args.candidate):
        if not os.access(binary, os.X_OK):
            print(f"frame_suite: error: {binary} is not an executable dynrt", file=sys.stderr)
            return 2
    work = args.keep or tempfile.mkdtemp(prefix="dynrt_frame_suite_")
    problems, ran, added = [], 0, set()
    for name, scene, flags in selected_cases(CASES, args.only):
        results = []
        for side, binary in (("reference", args.reference), ("candidate", args.candidate)):
            folder = os.path.join(work, name, side)
            shutil.rmtree(folder, ignore_errors=True)
            results.append((folder, *render(binary, scene, flags, folder)))
        (ref_folder, ref_code, ref_out), (new_folder, new_code, new_out) = results
        ran += 1
        if ref_code != 0 or new_code != 0:
            problems.append(f"{name}: exit {ref_code} against {new_code}\n{ref_out}{new_out}")
            continue
        found = compare(name, ref_folder, new_folder, added)
        problems += found
        print(f"{name}: {'same' if not found else 'DIFFERS'}")
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    for problem in problems:
        print(problem)
    if added:
        print("only in the candidate's reports (not compared): " + ", ".join(sorted(added)))
    print(f"{ran} cases, {len(problems)} differences")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
