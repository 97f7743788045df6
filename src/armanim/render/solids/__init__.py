"""The solid things of a frame: the arm's parts and the obstacles, as shaded polygons and
sprites, and the painter's order that draws them far first.

- :mod:`.arm`: the arm's parts (link prisms culled per pose, joint discs, the base) and the
  samples every part is ordered by.
- :mod:`.mesh`: link prisms built in each joint's frame (pure numpy).
- :mod:`.spheres`: obstacle spheres as exact discs shaded once into sprites.
- :mod:`.shapes`: obstacle boxes, capsules and cylinders: shaded faces, ray depth, outlines, shadows.
- :mod:`.order`: the painter's order of overlapping parts.
- :mod:`.obstacle_order`: with boxes or capsules, the obstacles' order among themselves and
  among the arm's parts.

Projects through :mod:`armanim.render.camera`; draws on :mod:`armanim.render.paint`.
"""
