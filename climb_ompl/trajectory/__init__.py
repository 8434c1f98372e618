"""Time-parameterisation of a climb's steps: each step's waypoints timed along a spline through them, time-optimal
within the joint velocity and acceleration limits (toppra; Pham & Pham 2018), at rest at every grasp and release
(:mod:`climb_ompl.trajectory.timing`), and the dynamic joint torques that timing implies checked against the torque
margin the quasi-static plan left (:mod:`climb_ompl.trajectory.dynamics`); :mod:`climb_ompl.trajectory.retime`
times a whole plan, including one written before plans were timed this way."""
