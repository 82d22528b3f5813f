#!/usr/bin/env python3
"""Times two dynrt binaries on the same frames of a set of scenes, alternately, and prints each
scene's per-frame median for both and their ratio.

For changes to the frame path that must not make a frame slower (issue 36): every case renders
a few frames at 1024x1024 with each binary in turn, `--rounds` times (the order alternating
round by round), and takes the median total_ms over the frames after the first (which builds
every tree and reads the textures), then the median over the rounds. It prints the stages'
medians too. Scenes from ../shared/scenes are skipped when absent.

    /usr/bin/python3 scripts/frame_timing.py --reference OLD_DYNRT [--candidate NEW_DYNRT]
        [--rounds 3] [--only NAME]

Or one binary under two sets of flags (a mode against the default, e.g. issue 43's compact
leaves):

    /usr/bin/python3 scripts/frame_timing.py --reference build/release/engine/dynrt \
        --candidate-flags="--leaves compact" --only sphere1M-still --only metalrough --only kitchen
"""

import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "scenes")
sys.path.insert(0, HERE)
from suite_cases import selected_cases  # noqa: E402

# Still scenes with --reuse off: the default exact reuse would skip the work being timed.
CASES = [
    ("kitchen", "shared:bart/kitchen/kitchen.aff", ["--frames", "0-7", "--reuse", "off"]),
    ("robots", "shared:bart/robots/Robot.aff", ["--frames", "0-7", "--reuse", "off"]),
    ("museum", "shared:bart/museum/museum5.aff", ["--frames", "0-7", "--reuse", "off"]),
    ("cesiumman", "shared:cesiumman/CesiumMan.glb", ["--frames", "0-15", "--reuse", "off"]),
    ("fox", "shared:fox/Fox.glb", ["--frames", "0-15", "--reuse", "off"]),
    ("metalrough", "shared:metalroughspheresnotextures/MetalRoughSpheresNoTextures.glb",
     ["--frames", "0-7", "--reuse", "off"]),
    ("sphere1M-still", "sphere:1000000", ["--frames", "0-7", "--reuse", "off"]),
    ("sphere1M-wave", "sphere:1000000", ["--frames", "0-7", "--anim", "wave"]),
    ("sphere1M-explode", "sphere:1000000", ["--frames", "0-7", "--anim", "explode"]),
]
STAGES = ["update_ms", "build_ms", "primary_ms", "shadow_ms", "shade_ms", "secondary_ms"]


def run(binary, scene, flags, work):
    report = os.path.join(work, "report.json")
    subprocess.run([binary, "render", scene, "--res", "1024x1024", "-q", *flags,
                    "--out", os.path.join(work, "f%04d.ppm"), "--report", report], check=True)
    frames = json.load(open(report))["frames"][1:]
    return (statistics.median(f["total_ms"] for f in frames),
            {k: statistics.median(f[k] for f in frames) for k in STAGES})


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--reference", required=True)
    parser.add_argument("--candidate", default=os.path.join(ROOT, "build", "release", "engine", "dynrt"))
    parser.add_argument("--reference-flags", default="", help="flags added to the reference's renders")
    parser.add_argument("--candidate-flags", default="", help="flags added to the candidate's renders")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--only", action="append", default=[])
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="dynrt_frame_timing_")
    sides = [("reference", args.reference, shlex.split(args.reference_flags)),
             ("candidate", args.candidate, shlex.split(args.candidate_flags))]
    for name, scene, flags in selected_cases(CASES, args.only):
        totals = {label: [] for label, _, _ in sides}
        stages = {label: [] for label, _, _ in sides}
        for r in range(args.rounds):
            for label, binary, extra in (sides if r % 2 == 0 else sides[::-1]):
                total, per_stage = run(binary, scene, flags + extra, work)
                totals[label].append(total)
                stages[label].append(per_stage)
        before, after = statistics.median(totals["reference"]), statistics.median(totals["candidate"])
        spread = lambda v: f"{min(v):.1f}-{max(v):.1f}"
        print(f"{name:18s} reference {before:8.1f} ms ({spread(totals['reference'])})  candidate "
              f"{after:8.1f} ms ({spread(totals['candidate'])})  candidate/reference {after / before:.3f}")
        for label, _, _ in sides:
            print(f"    {label}: " + " ".join(
                f"{k[:-3]}={statistics.median(s[k] for s in stages[label]):.1f}" for k in STAGES))
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
