"""A timed climb plan as a ROS 2 bag, written with the pure-Python ``rosbags`` library (no ROS installation).

Topics:

* ``/joint_trajectory`` (``trajectory_msgs/msg/JointTrajectory``): one message per step, the actuated joints named
  as in the URDF, one point per sample of the step with positions, velocities, accelerations, the feed-forward
  ``effort`` (static plus dynamic torques, :mod:`climb_ompl.export.samples`; empty for a robot without an
  equilibrium condition) and ``time_from_start`` from the step's start; the header stamp is zero, which
  ``joint_trajectory_controller`` reads as "start on receipt".
* ``/base_trajectory`` (``trajectory_msgs/msg/MultiDOFJointTrajectory``, floating-base robots only): the pose of the
  body the limbs hang from in the world frame (``frame_id`` ``world``), with its linear and angular velocity and
  acceleration in that frame, at the same samples.  The base is not actuated: it is where the limbs put it.
* ``/events`` (``std_msgs/msg/String``): the grasp or release that ends each step, as JSON
  (``{"step", "t", "action", "limb", "hold"}``, ``t`` in seconds since the climb began).

Each message is logged at the climb time its step starts (the events at the time they happen), so ``ros2 bag play``
sends each step when the previous one is done.  The bag (a folder) is written beside its target and renamed into
place when complete: a failure leaves nothing behind.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl.errors import InputError
from climb_ompl.export.samples import static_at, timed
from climb_ompl.trajectory.dynamics import dynamic_torques

#: The message definitions the bag records (ROS 2 Humble's; Jazzy's are the same for these types).
TYPESTORE = "ROS2_HUMBLE"
#: rosbag2 metadata version written (rosbags writes 8 or 9).
BAG_VERSION = 8
TOPICS = {"joints": "/joint_trajectory", "base": "/base_trajectory", "events": "/events"}


def _duration(ts: Any, t: float) -> Any:
    ns = int(round(t * 1e9))
    return ts.types["builtin_interfaces/msg/Duration"](sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def _base_frames(robot: Any, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> list[tuple[np.ndarray, ...]]:
    """The base body's placement (translation, quaternion x y z w), its velocity and acceleration (linear, angular;
    world-aligned) at each sample."""
    import pinocchio as pin

    m, d = robot.model, robot.data
    last = max(robot.base_indices)
    jid = next(j for j in range(1, m.njoints) if m.idx_qs[j] <= last < m.idx_qs[j] + m.nqs[j])
    frame = pin.LOCAL_WORLD_ALIGNED
    out = []
    for i in range(len(q)):
        pin.forwardKinematics(m, d, q[i], v[i], a[i])
        place = d.oMi[jid]
        vel = pin.getVelocity(m, d, jid, frame)
        acc = pin.getClassicalAcceleration(m, d, jid, frame)
        quat = pin.Quaternion(place.rotation).coeffs()  # x, y, z, w
        out.append((np.array(place.translation), np.array(quat), np.array(vel.linear), np.array(vel.angular),
                    np.array(acc.linear), np.array(acc.angular)))
    return out


def _twist(types: Any, linear: np.ndarray, angular: np.ndarray) -> Any:
    vec3 = types["geometry_msgs/msg/Vector3"]
    return types["geometry_msgs/msg/Twist"](linear=vec3(*map(float, linear)), angular=vec3(*map(float, angular)))


def _base_message(robot: Any, ts: Any, header: Any, t: np.ndarray, q: np.ndarray, v: np.ndarray,
                  a: np.ndarray) -> Any:
    """The step's ``MultiDOFJointTrajectory`` of the base body."""
    types = ts.types
    vec3, quat = types["geometry_msgs/msg/Vector3"], types["geometry_msgs/msg/Quaternion"]
    point = types["trajectory_msgs/msg/MultiDOFJointTrajectoryPoint"]
    pts = [point(transforms=[types["geometry_msgs/msg/Transform"](translation=vec3(*map(float, p)),
                                                                  rotation=quat(*map(float, r)))],
                 velocities=[_twist(types, vl, va)], accelerations=[_twist(types, al, aa)],
                 time_from_start=_duration(ts, t[i]))
           for i, (p, r, vl, va, al, aa) in enumerate(_base_frames(robot, q, v, a))]
    world = types["std_msgs/msg/Header"](stamp=header.stamp, frame_id="world")
    return types["trajectory_msgs/msg/MultiDOFJointTrajectory"](header=world, joint_names=["base"], points=pts)


def _joint_message(s: Any, robot: Any, ts: Any, header: Any) -> Any:
    """The step's ``JointTrajectory`` of the actuated joints."""
    act = np.nonzero(np.asarray(robot.actuated, dtype=bool))[0]
    t, q = np.asarray(s.times, dtype=float), s.q
    v, a = np.array(s.velocities, dtype=float), np.array(s.accelerations, dtype=float)
    effort = np.zeros((len(t), 0))
    if s.forces:
        static = static_at(s, robot, tuple(lb.name for lb in robot.limbs), t)[0]
        effort = (static + dynamic_torques(robot, q, v, a))[:, act]
    arr, point = np.ascontiguousarray, ts.types["trajectory_msgs/msg/JointTrajectoryPoint"]
    pts = [point(positions=arr(q[i, act]), velocities=arr(v[i, act]), accelerations=arr(a[i, act]),
                 effort=arr(effort[i]), time_from_start=_duration(ts, t[i])) for i in range(len(t))]
    return ts.types["trajectory_msgs/msg/JointTrajectory"](
        header=header, joint_names=[robot.joint_names[j] for j in act], points=pts)


def _messages(plan: Any, robot: Any, ts: Any) -> list[tuple[str, int, Any]]:
    """``(topic, log time ns, message)`` of every message of the bag, in time order."""
    types = ts.types
    header = types["std_msgs/msg/Header"](stamp=types["builtin_interfaces/msg/Time"](sec=0, nanosec=0),
                                         frame_id="")
    out: list[tuple[str, int, Any]] = []
    t0 = 0.0
    for s in plan.steps:
        stamp = int(round(t0 * 1e9))
        out.append((TOPICS["joints"], stamp, _joint_message(s, robot, ts, header)))
        if robot.base_indices:
            t, v, a = np.asarray(s.times, dtype=float), np.array(s.velocities), np.array(s.accelerations)
            out.append((TOPICS["base"], stamp, _base_message(robot, ts, header, t, s.q, v, a)))
        t0 += s.duration
        event = {"step": s.index, "t": t0, "action": s.action, "limb": s.limb, "hold": s.hold}
        out.append((TOPICS["events"], int(round(t0 * 1e9)), types["std_msgs/msg/String"](data=json.dumps(event))))
    return out


def write_bag(plan: Any, robot: Any, path: str | os.PathLike[str]) -> Path:
    """Write the plan (timed first if it is not) as a ROS 2 bag folder at ``path``.

    Raises:
        InputError: ``path`` exists already or its folder does not exist or cannot be written.
    """
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    target = Path(path)
    if target.exists() or target.is_symlink():
        raise InputError(target, "output", "exists already (a bag is a new folder; remove it or name another)")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(target, "output", f"folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK):
        raise InputError(target, "output", f"folder {str(folder)!r} is not writable")
    ts = get_typestore(getattr(Stores, TYPESTORE))
    msgs = _messages(timed(plan, robot), robot, ts)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=folder))
    work = tmp / target.name
    try:
        with Writer(work, version=BAG_VERSION) as writer:
            conns = {topic: writer.add_connection(topic, typ, typestore=ts) for topic, typ in (
                (TOPICS["joints"], "trajectory_msgs/msg/JointTrajectory"),
                (TOPICS["base"], "trajectory_msgs/msg/MultiDOFJointTrajectory"),
                (TOPICS["events"], "std_msgs/msg/String")) if topic != TOPICS["base"] or robot.base_indices}
            for topic, stamp, msg in msgs:
                writer.write(conns[topic], stamp, ts.serialize_cdr(msg, msg.__msgtype__))
        os.replace(work, target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return target


def read_bag(path: str | os.PathLike[str]) -> list[tuple[str, int, Any]]:
    """Every message of a bag as ``(topic, log time ns, message)``, in log-time order."""
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(getattr(Stores, TYPESTORE))
    with Reader(path) as reader:
        return [(c.topic, stamp, ts.deserialize_cdr(raw, c.msgtype)) for c, stamp, raw in reader.messages()]


__all__ = ["TOPICS", "TYPESTORE", "BAG_VERSION", "write_bag", "read_bag"]
