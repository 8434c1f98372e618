"""Stance manifolds (Bretl 2006, sec. 2): stances, the OMPL constrained spaces of their configurations, the
validity checks (equilibrium, joint and torque limits, collision), the feasibility tests shared by the operators of
the search, and the samplers (straight-elbow, free-limb, joint-by-joint, the planar model reduction).

:mod:`climb_ompl.manifold._ompl` is the only module of the package that imports OMPL.
"""
