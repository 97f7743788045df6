"""A path goal's tool along its path (:mod:`armanim.motion.paths.following`): one warm-started,
filtered pose solve per sample of the path, and the route from the start pose that gets farthest.
"""
