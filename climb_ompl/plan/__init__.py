"""The plan: its data model and versioned JSON file (:mod:`climb_ompl.plan.file`), and the terrain changes a
re-plan records in it (:mod:`climb_ompl.plan.events`)."""
