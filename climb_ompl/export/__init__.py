"""Exports of a timed climb plan: samples as CSV or NPZ, a ROS 2 bag, a video of the playback."""
