"""The cases of scripts/frame_suite.py and scripts/frame_timing.py: which of a list of (name,
scene, flags) cases run, with scenes named "shared:PATH" read from ../shared/scenes."""

import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "scenes")


def selected_cases(cases, only):
    """Yields (name, scene path or spec, flags) for the cases whose name contains one of `only`
    (all when empty); a shared scene that is not there is skipped with a line saying so."""
    for name, scene, flags in cases:
        if only and not any(o in name for o in only):
            continue
        if scene.startswith("shared:"):
            scene = os.path.join(SHARED, scene[len("shared:"):])
            if not os.path.exists(scene):
                print(f"{name}: skipped ({scene} is not there)")
                continue
        yield name, scene, flags
