"""The robot and its world: terrains and their wall frame, robot models from URDF, collision, limb inverse
kinematics, contact geometry and reach.

Every later layer (the stance manifolds, the climb, the verifier) reads these; nothing here knows about OMPL or
the search.
"""
