"""Scene generators of the benchmarks: seeded random scenes by family (arms among spheres,
the bundled robots, shapes, goals across the body), each accepted by armanim's own validation.
"""
