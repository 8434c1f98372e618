"""The free-climbing planner of Bretl (2006): FIND-TRANSITION (:mod:`~climb_ompl.climb.transition`), FIND-PATH
(:mod:`~climb_ompl.climb.onestep`), the two-stage search on the stance graph (:mod:`~climb_ompl.climb.search`),
the start finder, the goal, the plan's assembly, the multi-step entry point (:mod:`~climb_ompl.climb.multistep`)
and re-planning when a hold fails (:mod:`~climb_ompl.climb.replan`).
"""
