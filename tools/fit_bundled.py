"""Maintainer script: the bundled robots' capsules fitted to their own meshes, as package data.

For each bundled robot, every link of its shipped meshes (``visual.npz``, the simplified visual
meshes the pictures draw: :func:`armanim.scene.visuals.bundled_link_meshes`) is fitted with 1 to 3
capsules that hold every vertex and triangle (:func:`armanim.arm.fitting.fit_capsules`, the fit
``collision: auto`` runs on your own URDF's meshes), and the list is written to
``src/armanim/arm/robots/NAME/fitted-capsules.yaml`` in the scene's ``arm.collision`` format. A
scene asks for it with ``collision: fitted``; a run never fits a bundled robot. The fit is
deterministic: running this again writes the same bytes.

Usage::

    python tools/fit_bundled.py            # all bundled robots
    python tools/fit_bundled.py --check    # exit 1 if a committed file differs from a fresh fit
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

from armanim.arm.fitting import fit_capsules  # noqa: E402
from armanim.scene.fields import ROBOTS  # noqa: E402
from armanim.scene.meshcapsules import collision_yaml  # noqa: E402
from armanim.scene.robots import FITTED_FILE  # noqa: E402
from armanim.scene.visuals import bundled_link_meshes  # noqa: E402

FOLDER = ROOT / "src" / "armanim" / "arm" / "robots"


def fitted_text(name: str) -> str:
    """One robot's ``fitted-capsules.yaml``."""
    rows = []
    for mesh in bundled_link_meshes(FOLDER / name):
        for capsule in fit_capsules(mesh.vertices, mesh.faces):
            rows.append((mesh.link, capsule.start, capsule.end, capsule.radius))
    header = (
        f"{name}: capsules fitted to its shipped meshes (visual.npz) by tools/fit_bundled.py, each holding every\n"
        "vertex of its link's mesh; metres, each in its link's frame. A scene uses them with collision: fitted."
    )
    return collision_yaml(rows, header)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the committed files instead of writing them")
    args = parser.parse_args(argv)
    stale = []
    for name in ROBOTS:
        text, path = fitted_text(name), FOLDER / name / FITTED_FILE
        if args.check:
            if not path.is_file() or path.read_text(encoding="utf-8") != text:
                stale.append(name)
        else:
            path.write_text(text, encoding="utf-8")
            print(f"{name}: {text.count('- {link')} capsules -> {path.relative_to(ROOT)}")
    if stale:
        print(f"stale: {', '.join(stale)} (run python tools/fit_bundled.py)")
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
