"""A run as a ROS ``trajectory_msgs/JointTrajectory`` message in JSON: no ROS needed to write it.

The message's fields, and nothing else, so that ROS 2 tools that fill a message from a
dictionary (``rosidl_runtime_py.set_message_fields``, which refuses unknown keys) load it::

    {"header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""},
     "joint_names": [...],
     "points": [{"positions": [...], "velocities": [...], "accelerations": [], "effort": [],
                 "time_from_start": {"sec": 0, "nanosec": 0}}, ...]}

Positions in radians, velocities in rad/s, ``time_from_start`` a ``builtin_interfaces/Duration``.
"""

from __future__ import annotations

import json

import numpy as np

MESSAGE_KEYS = ("header", "joint_names", "points")
POINT_KEYS = ("positions", "velocities", "accelerations", "effort", "time_from_start")
"""The fields of ``trajectory_msgs/JointTrajectory`` and of each ``JointTrajectoryPoint``."""


def ros_duration(seconds: float) -> dict:
    """A ``builtin_interfaces/Duration`` of ``seconds`` >= 0, to the nearest nanosecond.

    >>> ros_duration(1.5), ros_duration(1 / 3), ros_duration(0.0)
    ({'sec': 1, 'nanosec': 500000000}, {'sec': 0, 'nanosec': 333333333}, {'sec': 0, 'nanosec': 0})
    """
    sec, nanosec = divmod(round(seconds * 1e9), 1_000_000_000)
    return {"sec": int(sec), "nanosec": int(nanosec)}


def joint_trajectory(joint_names, time_s: np.ndarray, positions: np.ndarray, velocities: np.ndarray) -> dict:
    """The ``JointTrajectory`` message of a trajectory, as plain data.

    Parameters
    ----------
    joint_names : sequence of str, n names
    time_s : (F,) seconds from the start, increasing
    positions : (F, n) radians
    velocities : (F, n) rad/s

    Returns
    -------
    dict
        The message (see the module's docstring).

    >>> msg = joint_trajectory(["a"], np.array([0.0, 0.5]), np.array([[0.0], [0.25]]), np.array([[0.0], [0.5]]))
    >>> msg["joint_names"], msg["points"][1]["positions"], msg["points"][1]["time_from_start"]
    (['a'], [0.25], {'sec': 0, 'nanosec': 500000000})
    """
    points = [
        {
            "positions": [float(v) for v in p],
            "velocities": [float(v) for v in v_],
            "accelerations": [],
            "effort": [],
            "time_from_start": ros_duration(float(t)),
        }
        for t, p, v_ in zip(time_s, positions, velocities)
    ]
    return {
        "header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""},
        "joint_names": list(joint_names),
        "points": points,
    }


def unwrapped(positions: np.ndarray, unlimited: np.ndarray) -> np.ndarray:
    """(F, n) ``positions`` (radians) with each ``unlimited`` joint's column made continuous: such a
    joint's angle is written wrapped to (-180, 180] in trajectory.csv, so a joint that turns past
    180 degrees would jump to -179 between two points while its velocity says it turned one degree
    (campaign 10: a controller interpolating the positions would turn it a full turn back within a
    frame); here it goes on to 181, the way it turned. Every step is the shorter way, as the CSV's
    velocities and the trajectory's speed checks take it.

    >>> unwrapped(np.radians([[179.0, 179.0], [-179.0, -179.0]]), np.array([True, False])).round(6).tolist()
    [[3.124139, 3.124139], [3.159046, -3.124139]]
    """
    out = np.array(positions, dtype=float)
    if np.any(unlimited):
        out[:, unlimited] = np.unwrap(out[:, unlimited], axis=0)
    return out


def finite_difference_velocities(time_s: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """(F, n) velocities of positions sampled at ``time_s``: central differences inside, one-sided
    at the ends (second order on uneven steps: :func:`numpy.gradient`); zeros for one frame.

    >>> finite_difference_velocities(np.array([0.0, 1.0, 2.0]), np.array([[0.0], [1.0], [4.0]]))[:, 0].tolist()
    [1.0, 2.0, 3.0]
    """
    if len(time_s) < 2:
        return np.zeros_like(positions)
    return np.gradient(positions, time_s, axis=0)


def joint_trajectory_text(message: dict) -> str:
    """The message as JSON text: one point per line, so that a long run stays readable and diffable."""
    head = json.dumps({k: message[k] for k in ("header", "joint_names")})[:-1]
    points = ",\n".join(json.dumps(p) for p in message["points"])
    return f'{head}, "points": [\n{points}\n]}}\n'
