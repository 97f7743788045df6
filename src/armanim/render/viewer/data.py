"""The data a viewer page shows: one solved run as plain, rounded JSON values.

Joint positions come from armanim's own forward kinematics (:func:`armanim.arm.kinematics.forward`),
so the page never computes a pose; the caption's activity per frame comes from
:func:`armanim.render.overlay.caption.frame_activity`, as in the video. The format is documented
in docs/viewer.md ("The data format"); :data:`FORMAT` names its version.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import cast

import numpy as np

from armanim import __version__
from armanim.arm.capsules import capsule_ends
from armanim.arm.kinematics import Pose, forward, joints_shown
from armanim.arm.rotations import rotation_quaternion
from armanim.arm.visuals import ArmMeshes
from armanim.motion.carry import CarryReport, frame_bodies, moving_columns
from armanim.motion.orientation import frame_orientations
from armanim.motion.problem import Problem
from armanim.motion.solution import GoalReport, Trajectory
from armanim.render.camera.framing import scene_content
from armanim.render.camera.projection import planar_normal, view_angles
from armanim.render.overlay.caption import frame_activity
from armanim.render.overlay.paths import arc_spacing, path_normal, sampled_paths
from armanim.render.overlay.triads import TRIAD_PER_REACH, has_orientations
from armanim.render.paint import scenery, style
from armanim.render.settings import RenderSettings
from armanim.world.carried import obstacle_body, with_bodies
from armanim.world.obstacles import BOX, CYLINDER, ROD, SPHERE

FORMAT = "armanim-viewer/1"
"""The data format's name and version (docs/viewer.md)."""

ANGLE_DECIMALS = 2  # joint angles in degrees: 0.01 degree, as the page shows them
RESOLUTION = 10_000  # positions and distances keep at least 1/RESOLUTION of the scene's size
CHORD_SHARE = 1 / 4000  # a path's arcs are sent as chords straying at most this share of the scene's size
INK_SHARE = 1 / 200  # the page's ink is a ribbon this share of the scene's size wide (about 2 px, as in the video)
SERIES_CHUNK = 2048
"""Frames of a per-frame list turned into JSON values at a time (:class:`FrameSeries`)."""
MAX_PAGE_FRAMES = 36_000
"""The most frames a page holds (20 minutes at 30 fps): a longer run's page shows one frame in
``step`` (:func:`page_frames`), so that it stays small enough for a browser to open."""


@dataclass(frozen=True)
class FrameSeries:
    """A per-frame list of the page's data, made a few frames at a time (never all at once).

    Attributes
    ----------
    frames : int
        The frames F it spans.
    values : callable
        ``values(start, stop)``: the list's entries of frames ``start .. stop - 1`` (plain JSON
        values, as many per frame as the list has), concatenated in frame order.
    """

    frames: int
    values: Callable[[int, int], list]

    def chunks(self, size: int | None = None) -> Iterator[list]:
        """The list ``size`` frames at a time (default :data:`SERIES_CHUNK`)."""
        size = size or SERIES_CHUNK
        for start in range(0, self.frames, size):
            yield self.values(start, min(start + size, self.frames))

    def whole(self) -> list:
        """The whole list."""
        return self.values(0, self.frames)


def rounded_series(values: np.ndarray, decimals: int) -> FrameSeries:
    """``values`` (F, ...) as a :class:`FrameSeries` of :func:`rounded` numbers, frame after frame."""
    return FrameSeries(len(values), lambda start, stop: rounded(values[start:stop], decimals))


def nullable_series(values: np.ndarray, decimals: int) -> FrameSeries:
    """``values`` (F,) rounded, null where not finite."""

    def part(start: int, stop: int) -> list:
        chunk = np.asarray(values[start:stop], dtype=float)
        finite = np.isfinite(chunk)
        return [v if ok else None for v, ok in zip(rounded(np.where(finite, chunk, 0.0), decimals), finite)]

    return FrameSeries(len(values), part)


def int_series(values: np.ndarray) -> FrameSeries:
    """``values`` (F,) as whole numbers (booleans as 0 and 1)."""
    return FrameSeries(len(values), lambda start, stop: np.asarray(values[start:stop]).astype(int).tolist())


def frame_poses(problem: Problem, phi: np.ndarray) -> Callable[[int, int], Pose]:
    """The arm's poses of frames ``start .. stop - 1`` of ``phi`` (F, n), computed when asked
    (:func:`~armanim.arm.kinematics.forward`, the one kinematics): a page's lists are made a few
    frames at a time, each from its frames' poses, never from every frame's at once."""
    return lambda start, stop: forward(problem.arm, phi[start:stop])


def joint_extent(poses: Callable[[int, int], Pose], frames: int) -> np.ndarray:
    """(2, 3) the lowest and the highest x, y and z of any joint in any frame ((0, 3) for no frame),
    :data:`SERIES_CHUNK` frames at a time: what the view's box needs of every joint position."""
    if frames == 0:
        return np.zeros((0, 3))
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for start in range(0, frames, SERIES_CHUNK):
        points = poses(start, min(start + SERIES_CHUNK, frames)).points
        lo, hi = np.minimum(lo, points.min(axis=(0, 1))), np.maximum(hi, points.max(axis=(0, 1)))
    return np.stack([lo, hi])


def plain(value: object) -> object:
    """``value`` with every :class:`FrameSeries` in it made a whole list (the data as JSON values)."""
    if isinstance(value, FrameSeries):
        return value.whole()
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [plain(v) for v in value]
    return value


def page_frames(frames: int, limit: int = MAX_PAGE_FRAMES) -> np.ndarray:
    """The frames a page shows: all up to ``limit``; beyond, every ``step``-th (the smallest step
    that keeps them within ``limit``), the run's last frame always among them.

    >>> page_frames(5).tolist(), page_frames(10, limit=4).tolist()
    ([0, 1, 2, 3, 4], [0, 3, 6, 9])
    >>> page_frames(11, limit=4).tolist()
    [0, 4, 8, 10]
    """
    step = frame_step(frames, limit)
    if step == 1:
        return np.arange(frames)
    kept = np.arange(0, frames, step)
    return kept if kept[-1] == frames - 1 else np.append(kept, frames - 1)


def frame_step(frames: int, limit: int = MAX_PAGE_FRAMES) -> int:
    """The step between the frames a page of a run of ``frames`` shows (1: every frame).

    >>> frame_step(36_000), frame_step(36_001), frame_step(108_001)
    (1, 2, 4)
    """
    limit = max(limit, 2)  # the first and the last frame
    if frames <= limit:
        return 1
    step = -(-(frames - 1) // (limit - 1))  # ceil: (limit - 1) steps span the run's frames
    while len(range(0, frames, step)) + ((frames - 1) % step != 0) > limit:
        step += 1
    return step


def reports_at(reports: Sequence[GoalReport], kept: np.ndarray) -> list[GoalReport]:
    """``reports`` with their first and last frames as indices into ``kept`` (the frames a page
    shows): the first kept frame at or after a goal's first, the last at or before its last."""
    return [
        replace(
            r,
            first_frame=int(np.searchsorted(kept, r.first_frame)) if r.first_frame >= 0 else r.first_frame,
            last_frame=int(np.searchsorted(kept, r.last_frame, side="right")) - 1
            if r.last_frame >= 0
            else r.last_frame,
        )
        for r in reports
    ]


def position_decimals(size: float) -> int:
    """Decimals that keep positions to at least ``size / RESOLUTION`` (between 0 and 12).

    >>> position_decimals(20.0), position_decimals(1.0), position_decimals(0.3)
    (3, 4, 5)
    """
    if not np.isfinite(size) or not size / RESOLUTION > 0:  # (a subnormal size divides to 0)
        return 4
    return int(np.clip(-np.floor(np.log10(size / RESOLUTION)), 0, 12))


def rounded(values: np.ndarray, decimals: int) -> list:
    """A flat list of ``values`` rounded to ``decimals``; whole numbers become ints (shorter JSON).

    >>> rounded(np.array([[1.0, 2.345], [-0.0, 3.0]]), 2)
    [1, 2.35, 0, 3]
    """
    flat = np.round(np.asarray(values, dtype=float).ravel(), decimals) + 0.0  # + 0.0: no "-0"
    return [int(v) if v.is_integer() else v for v in flat.tolist()]


def hex_color(rgb) -> str:
    """An RGB colour in 0..1 as ``#rrggbb``.

    >>> hex_color((1.0, 0.5, 0.0))
    '#ff8000'
    """
    return "#" + "".join(f"{int(round(float(c) * 255)):02x}" for c in rgb[:3])


def page_style() -> dict:
    """The video's colours and sizes (:mod:`armanim.render.paint.style`), for the page to draw with."""
    return {
        "background": hex_color(style.BACKGROUND),
        "floor": hex_color(style.FLOOR_COLOR),
        "grid": hex_color(style.GRID_COLOR),
        "arm": hex_color(style.ARM_COLOR),
        "self_near": hex_color(style.SELF_NEAR_COLOR),
        "joint": hex_color(style.JOINT_COLOR),
        "base": hex_color(style.BASE_COLOR),
        "obstacle": hex_color(style.OBSTACLE_COLOR),
        "trail": hex_color(style.TRAIL_COLOR),
        "goals": {state: hex_color(rgb) for state, rgb in style.GOAL_COLORS.items()},
        "joint_scale": style.JOINT_SCALE,
        "base_scale": style.BASE_SCALE,
    }


def goal_entries(problem: Problem, reports: Sequence[GoalReport]) -> list[dict]:
    """One entry per goal: position, outcome and the frames it spans (summary.json's)."""
    entries = []
    for i, goal in enumerate(problem.goals):
        report = reports[i] if i < len(reports) else None
        entries.append(
            {
                "position": [float(v) for v in goal.position],
                "reached": bool(report.reached) if report else False,
                "reason": report.reason if report else None,
                "first": int(report.first_frame) if report else -1,
                "last": int(report.last_frame) if report else -1,
                **goal_orientation_entry(goal),
            }
        )
    return entries


def orientation_entry(problem: Problem, trajectory: Trajectory, decimals: int) -> dict | None:
    """For a run with a goal that has an orientation (else None): the tool frame's quaternion per
    frame (flat F x 4, w x y z), the tool's angle to the frame's goal orientation per frame
    (degrees, null where the goal has none), the triads' length and their x, y, z colours."""
    if not has_orientations(problem.goals):
        return None
    recorded = trajectory.tool_quaternion

    def quaternions(start: int, stop: int) -> list:
        if recorded is not None:
            return rounded(recorded[start:stop], 6)
        orientations = [g.orientation for g in problem.goals]
        at = frame_orientations(problem.arm, orientations, trajectory.phi[start:stop], trajectory.goal[start:stop])
        return rounded(at[1], 6)

    angles = (
        trajectory.orientation_error if trajectory.orientation_error is not None else np.full(trajectory.frames, np.nan)
    )
    return {
        "quaternion_wxyz": FrameSeries(trajectory.frames, quaternions),
        "angle_deg": FrameSeries(
            len(angles),
            lambda a, b: [None if not np.isfinite(v) else round(float(np.degrees(v)), 3) for v in angles[a:b]],
        ),
        "triad": round(float(TRIAD_PER_REACH * problem.arm.reach), decimals + 2),
        "colors": [hex_color(c) for c in style.AXIS_COLORS],
    }


def camera_toward(elevation: float, azimuth: float) -> np.ndarray:
    """(3,) the unit direction from the scene toward the video's camera (angles in degrees).

    >>> camera_toward(90.0, 0.0).round(12).tolist()
    [0.0, 0.0, 1.0]
    """
    e, a = np.radians(elevation), np.radians(azimuth)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def path_entry(problem: Problem, trajectory: Trajectory, decimals: int, size: float, toward: np.ndarray) -> dict | None:
    """For a run with a path goal (else None): each path goal's path as a polyline (``goal``, the
    arc length ``s`` and the point of every sample, flat x y z, and ``ink``, 1 where the pen is
    down from a sample to the next; corners kept, arcs as chords within ``size`` x
    :data:`CHORD_SHARE`) with the ``normal`` of the plane its ink lies in (the path's own, or
    the one facing the camera, ``toward``), the arc length done per frame (``path_s``: the
    CSV's, null off the paths' frames), the ink's ``width`` and the colours: the page draws ink
    and the path ahead as the video does (:mod:`armanim.render.overlay.paths`)."""
    paths = sampled_paths(problem.goals, lambda path: arc_spacing(path, size * CHORD_SHARE))
    if not paths:
        return None
    done = trajectory.path_s if trajectory.path_s is not None else np.full(trajectory.frames, np.nan)
    return {
        "goals": [
            {
                "goal": p.goal,
                "s": rounded(p.s, decimals),
                "points": rounded(p.points, decimals),
                "ink": [int(b) for b in p.ink],
                "normal": rounded(path_normal(p.points, toward), 4),
            }
            for p in paths
        ],
        "path_s": nullable_series(done, decimals),
        "width": round(size * INK_SHARE, decimals),
        "ink": hex_color(style.INK_COLOR),
        "ahead_opacity": style.AHEAD_ALPHA,
    }


def goal_orientation_entry(goal) -> dict:
    """A goal's orientation for the page: its rotation (rows) or its tool axis; {} for none."""
    o = goal.orientation
    if o is None:
        return {}
    if o.rotation is not None:
        return {"rotation": [[float(v) for v in row] for row in o.rotation]}
    return {"tool_axis": [float(v) for v in o.axis]}


def activity_codes(trajectory: Trajectory, reports: Sequence[GoalReport]) -> tuple[list[str], np.ndarray]:
    """The caption's activities (``moving``, ``holding``, ...) as names and (F,) one index per frame."""
    names, codes = np.unique(frame_activity(trajectory, reports).astype(str), return_inverse=True)
    return names.tolist(), codes.reshape(-1)


def view_settings(problem: Problem, settings: RenderSettings, points: np.ndarray) -> dict:
    """The video's camera angles, the box the page fits its views to, and the floor."""
    elevation, azimuth = view_angles(problem.arm, settings.elevation, settings.azimuth)
    content, radii = scene_content(problem, settings, points)
    lo, hi = (content - radii[:, None]).min(axis=0), (content + radii[:, None]).max(axis=0)
    size = float(np.max(hi - lo))
    floor_lo, floor_hi = scenery.floor_rect(lo[:2], hi[:2])
    given = problem.obstacles.floor
    floor_z = scenery.floor_height(lo[2], size) if given is None else float(given)  # the scene's floor, when it has one
    return {
        "elevation": float(elevation),
        "azimuth": float(azimuth),
        "planar": planar_normal(problem.arm) is not None,
        "box": [[float(v) for v in lo], [float(v) for v in hi]],
        "floor": {
            "z": float(floor_z),
            "lo": [float(v) for v in floor_lo],
            "hi": [float(v) for v in floor_hi],
            "step": scenery.nice_step(float(np.max(floor_hi - floor_lo))),
        },
        "bounds": None if settings.bounds is None else np.asarray(settings.bounds, dtype=float).reshape(3, 2).tolist(),
        "trail": bool(settings.trail),
    }


def viewer_data(
    problem: Problem, trajectory: Trajectory, reports: Sequence[GoalReport], settings: RenderSettings, **options
) -> dict:
    """:func:`viewer_parts` (the same parameters; ``options``, its keywords) with every per-frame
    list made whole: the page's data as plain lists, numbers and strings."""
    return cast(dict, plain(viewer_parts(problem, trajectory, reports, settings, **options)))  # a dict in, a dict out


def viewer_parts(
    problem: Problem,
    trajectory: Trajectory,
    reports: Sequence[GoalReport],
    settings: RenderSettings,
    *,
    title: str,
    joint_names: Sequence[str] | None = None,
    meshes: ArmMeshes | None = None,
    carry: CarryReport | None = None,
    max_frames: int | None = None,
) -> dict:
    """Everything the viewer page needs about a run: JSON values, each per-frame list a
    :class:`FrameSeries` (made a few frames at a time when the page is written;
    :func:`viewer_data` makes them whole).

    Parameters
    ----------
    problem : Problem
        The run's arm, obstacles and goals.
    trajectory : Trajectory
        Its frames (angles in radians; the joints' positions are computed here).
    reports : sequence of GoalReport
        One per goal, as in summary.json.
    settings : RenderSettings
        The camera angles, bounds and trail of the video.
    title : str
        Shown as the page's title (any text: the page escapes it).
    joint_names : sequence of str, optional
        One per joint (default ``phi1`` .. ``phiN``, the CSV's columns without ``_deg``).
    meshes : ArmMeshes, optional
        The robot's visual meshes: drawn instead of its capsules (a toggle shows those).
    carry : CarryReport, optional
        A run that grasps (:mod:`armanim.motion.carry`): the objects it moves are drawn where
        they are in each frame (``carried``), not with the obstacles.
    max_frames : int, optional
        The most frames the page holds (default :data:`MAX_PAGE_FRAMES`): a longer run shows one
        frame in ``step`` (:func:`page_frames`; the data's ``step`` and ``run_frames`` say so).

    Returns
    -------
    dict
        Plain lists, numbers, strings and :class:`FrameSeries` (no NaN or infinity): the format of
        docs/viewer.md.

    Examples
    --------
    >>> from armanim.scene import SceneModel, scene_to_problem
    >>> from armanim.scene import render_settings
    >>> from armanim.motion.trajectory import solve_trajectory
    >>> model = SceneModel.model_validate({"version": 1, "arm": {"links": [1, 1]}, "goals": [[1, 0, 1]]})
    >>> problem = scene_to_problem(model)
    >>> solution = solve_trajectory(problem)
    >>> data = plain(viewer_parts(problem, solution.trajectory, solution.goals, render_settings(model), title="two"))
    >>> data["format"], data["joints"], data["frames"] == solution.trajectory.frames
    ('armanim-viewer/1', ['phi1', 'phi2'], True)
    >>> len(data["points"]) == data["frames"] * 3 * 3  # (frames, joints + 1, xyz), frame after frame
    True
    """
    n = problem.arm.n
    run_frames = trajectory.frames
    max_frames = max_frames or MAX_PAGE_FRAMES
    fingers = None
    if carry is not None and problem.gripper is not None:
        from armanim.motion.carry import frame_fingers

        fingers = frame_fingers(problem, carry, trajectory.goal, trajectory.fps)  # ramps timed on every frame
    names, codes = activity_codes(trajectory, reports)  # the caption's, read on every frame
    kept = page_frames(run_frames, max_frames)
    if len(kept) < run_frames:
        trajectory, reports = trajectory.at_frames(kept), reports_at(reports, kept)
        codes = codes[kept]
        fingers = None if fingers is None else fingers[kept]
    poses = frame_poses(problem, trajectory.phi)
    view = view_settings(problem, settings, joint_extent(poses, trajectory.frames))  # the same box as every joint's
    decimals = position_decimals(float(np.max(np.subtract(view["box"][1], view["box"][0]))))
    data = {
        "format": FORMAT,
        "armanim": __version__,
        "title": str(title),
        "fps": float(trajectory.fps),
        "frames": int(trajectory.frames),
        **(
            {}
            if len(kept) == run_frames
            else {"step": frame_step(run_frames, max_frames), "run_frames": int(run_frames)}
        ),
        "joints": [
            f"{name} (m)" if slide else name
            for name, slide in zip(
                [str(j) for j in joint_names] if joint_names is not None else [f"phi{i + 1}" for i in range(n)],
                problem.arm.slides,
            )
        ],
        "decimals": decimals,
        "arm": {
            "links": [float(v) for v in problem.arm.links],
            "half_width": float(problem.half_width),
            "base": [float(v) for v in problem.arm.base],
        },
        **frame_entries(problem, trajectory, poses, decimals, fingers),
        "activities": names,
        "activity": int_series(codes),
        "goals": goal_entries(problem, reports),
        "obstacles": sphere_entries(still_obstacles(problem, carry)),
        **shape_entries(still_obstacles(problem, carry)),
        "view": view,
        "style": page_style(),
    }
    if carry is not None and moving_columns(carry):  # only runs that move an object carry it
        data["carried"] = carried_entries(problem, carry, trajectory, decimals)
    oriented = orientation_entry(problem, trajectory, decimals)
    if oriented is not None:  # only runs with an oriented goal carry it: other pages are as they were
        data["orientation"] = oriented
    paths = path_entry(
        problem,
        trajectory,
        decimals,
        float(np.max(np.subtract(view["box"][1], view["box"][0]))),
        camera_toward(view["elevation"], view["azimuth"]),
    )
    if paths is not None:  # only runs with a path goal carry it
        data["paths"] = paths
    if meshes is not None and meshes.triangles:  # only robots drawn with meshes carry them
        names = list(
            problem.capsules.names or ("",) * len(problem.capsules.radius)
        )  # an arm of links: no link has a mesh
        uncovered = [i for i, name in enumerate(names) if name not in set(meshes.links)]
        entries = mesh_entries(
            meshes, poses, trajectory.frames, decimals, problem.gripper if fingers is not None else None, fingers
        )
        group_of = {(g["carrier"], g.get("link")): i for i, g in enumerate(entries["groups"])}
        covered = [
            group_of.get((int(k), name), group_of.get((int(k), None), -1)) if i not in uncovered else -1
            for i, (k, name) in enumerate(zip(problem.capsules.link, names))
        ]
        data["meshes"] = entries | {
            "look": settings.robot,
            "uncovered": uncovered,
            "robot": len(uncovered) < len(names),
            "capsule_group": covered,
        }
    return data


def mesh_entries(
    meshes: ArmMeshes,
    poses: Callable[[int, int], Pose],
    frames: int,
    decimals: int,
    gripper=None,
    fingers: np.ndarray | None = None,
) -> dict:
    """The robot's meshes, each carrier's triangles once (vertices in its frame, RGB per vertex,
    two decimals), and per frame (``poses`` of ``frames``, :func:`frame_poses`) where each moving
    carrier is: its joint's position and its frame's quaternion (w, x, y, z), (F, K, 7) frame after frame. Carrier -1 (links that never
    move) is in the world. With a gripper (:class:`~armanim.arm.gripper.Gripper`) and its value
    in each frame (``fingers`` (F,)), each finger is a group of its own (``link``) that slides in
    its carrier's frame by ``slide`` (per metre) times the frame's ``fingers`` entry (the value
    less the one its vertices were placed at)."""
    vertex_part = np.zeros(len(meshes.vertices), dtype=int)
    vertex_part[meshes.faces] = meshes.part[:, None]
    finger = np.full(len(meshes.vertices), -1)
    sliding = gripper.links if gripper is not None else ()
    for j, link in enumerate(sliding):
        finger[np.isin(vertex_part, [k for k, name in enumerate(meshes.links) if name == link])] = j
    groups = []
    for carrier, j in sorted({(int(c), int(f)) for c, f in zip(meshes.carrier, finger)}):
        used = np.nonzero((meshes.carrier == carrier) & (finger == j))[0]
        mine = np.all((meshes.carrier[meshes.faces] == carrier) & (finger[meshes.faces] == j), axis=1)
        local = np.full(len(meshes.vertices), -1)
        local[used] = np.arange(len(used))
        color = np.zeros((len(meshes.vertices), 3))
        color[meshes.faces[mine][::-1].ravel()] = np.repeat(meshes.colors[mine][::-1], 3, axis=0)  # the first face's
        groups.append(
            {
                "carrier": int(carrier),
                "positions": rounded(meshes.vertices[used], decimals),
                "colors": rounded(color[used], 2),
                "indices": [int(v) for v in local[meshes.faces[mine]].ravel()],
            }
            | ({} if j < 0 else {"link": sliding[j], "slide": [float(v) for v in gripper.link_rate[j]]})
        )
    moving = [int(k) for k in np.unique(meshes.carrier) if k >= 0]

    def placement(start: int, stop: int) -> list:
        pose = poses(start, stop)
        at = np.concatenate([pose.points[:, moving, :], rotation_quaternion(pose.frames[:, moving])], axis=-1)
        return rounded(at, max(decimals, 6))

    out = {"groups": groups, "carriers": moving, "frames": FrameSeries(frames, placement)}
    if sliding and fingers is not None:
        out["fingers"] = rounded_series(np.asarray(fingers) - gripper.rest, 6)
    return out


def frame_capsule_ends(problem: Problem, pose: Pose, fingers: np.ndarray | None = None) -> np.ndarray:
    """(F, c, 2, 3) each capsule's two ends in each frame of ``pose``: the shapes clearance is
    measured on, the fingers' where the gripper is in each frame (``fingers`` (F,), metres)."""
    starts, ends = capsule_ends(problem.capsules, pose)  # (F, c, 3) each
    if fingers is not None and problem.gripper is not None:
        from armanim.arm.gripper import moved_fingers

        starts, ends = np.array(starts), np.array(ends)
        for value in np.unique(fingers[fingers != problem.gripper.rest]):
            mine = fingers == value
            at = type(pose)(pose.points[mine], pose.frames[mine])
            starts[mine], ends[mine] = capsule_ends(moved_fingers(problem.capsules, problem.gripper, float(value)), at)
    return np.stack([starts, ends], axis=2)


def frame_entries(
    problem: Problem,
    trajectory: Trajectory,
    poses: Callable[[int, int], Pose],
    decimals: int,
    fingers: np.ndarray | None = None,
) -> dict:
    """What changes frame by frame: the joints' positions (``poses``' points, (F, n+1, 3),
    :func:`frame_poses`), the capsules' ends, the angles, the goal, its distance, the clearance
    and ``reached``, each a :class:`FrameSeries`."""
    frames = trajectory.frames

    def ends(start: int, stop: int) -> list:
        part = None if fingers is None else fingers[start:stop]
        return rounded(frame_capsule_ends(problem, poses(start, stop), part), decimals)

    return {
        "points": FrameSeries(frames, lambda start, stop: rounded(poses(start, stop).points, decimals)),
        "capsules": {
            "radius": [float(r) for r in problem.capsules.radius],
            "ends": FrameSeries(frames, ends),
            **near_entries(problem, poses, frames),
        },
        "angles_deg": FrameSeries(  # metres for a prismatic joint
            frames,
            lambda start, stop: rounded(
                joints_shown(trajectory.phi[start:stop], problem.arm.prismatic), ANGLE_DECIMALS
            ),
        ),
        "goal": int_series(trajectory.goal),
        "distance": rounded_series(trajectory.distance, decimals),
        "clearance": nullable_series(trajectory.clearance, decimals),
        "reached": int_series(np.asarray(trajectory.reached, dtype=bool)),
    }


def sphere_entries(obstacles) -> list[dict]:
    """The sphere obstacles: centre, radius and influence (and name, where the scene gives one)."""
    return [
        _named({"center": [float(v) for v in c], "radius": float(r), "influence": float(i)}, obstacles, k)
        for c, r, i, k in zip(
            obstacles.centers,
            obstacles.radii,
            obstacles.influence[obstacles.columns(SPHERE)],
            obstacles.columns(SPHERE),
        )
    ]


def _named(entry: dict, obstacles, column: int) -> dict:
    """``entry`` with the obstacle's ``name`` where it has one (an unnamed obstacle's entry is as it always was)."""
    name = obstacles.name(int(column))
    return entry if name is None else {**entry, "name": name}


def shape_entries(obstacles) -> dict:
    """The boxes (centre, full edges, world-from-box rotation as rows), capsule obstacles
    (ends, radius) and cylinders (centre, length, radius, world-from-cylinder rotation as rows,
    the axis its local z), each with its influence (and name, where the scene gives one); the
    keys only when there are any (a scene of spheres writes the page it always wrote)."""
    out = {}
    boxes, rods, cylinders = obstacles.boxes, obstacles.rods, obstacles.cylinders
    if len(boxes):
        out["boxes"] = [
            _named(
                {
                    "center": [float(v) for v in c],
                    "size": [float(2 * v) for v in h],
                    "rotation": np.asarray(r, dtype=float).tolist(),
                    "influence": float(i),
                },
                obstacles,
                k,
            )
            for c, h, r, i, k in zip(
                boxes.centers,
                boxes.half,
                boxes.rotations,
                obstacles.influence[obstacles.columns(BOX)],
                obstacles.columns(BOX),
            )
        ]
    if len(rods):
        out["obstacle_capsules"] = [
            _named(
                {"from": [float(v) for v in a], "to": [float(v) for v in b], "radius": float(r), "influence": float(i)},
                obstacles,
                k,
            )
            for a, b, r, i, k in zip(
                rods.start, rods.end, rods.radius, obstacles.influence[obstacles.columns(ROD)], obstacles.columns(ROD)
            )
        ]
    if len(cylinders):
        out["cylinders"] = [
            _named(
                {
                    "center": [float(v) for v in c],
                    "length": float(2 * h),
                    "radius": float(r),
                    "rotation": np.asarray(m, dtype=float).tolist(),
                    "influence": float(i),
                },
                obstacles,
                k,
            )
            for c, m, h, r, i, k in zip(
                cylinders.centers,
                cylinders.rotations,
                cylinders.half_length,
                cylinders.radius,
                obstacles.influence[obstacles.columns(CYLINDER)],
                obstacles.columns(CYLINDER),
            )
        ]
    return out


def near_entries(problem: Problem, poses: Callable[[int, int], Pose], frames: int) -> dict:
    """``near``: per frame (``poses`` of ``frames``), the capsules of an enabled pair of the arm's
    own links within twice ``self_clearance`` (tinted, as in the video); nothing without enabled pairs."""
    pairs = problem.self_pairs
    if not len(pairs):
        return {}
    from armanim.render.solids.arm import NEAR_FACTOR
    from armanim.world.selfdistances import self_gaps

    def part(start: int, stop: int) -> list:
        close = self_gaps(poses(start, stop), problem.capsules, pairs).d < NEAR_FACTOR * pairs.clearance  # (f, P)
        return [sorted({int(c) for c in np.concatenate([pairs.first[row], pairs.second[row]])}) for row in close]

    return {"near": FrameSeries(frames, part)}


def still_obstacles(problem: Problem, carry: CarryReport | None):
    """The obstacles that never move: the run's, less the objects it moves."""
    if carry is None or not moving_columns(carry):
        return problem.obstacles
    return with_bodies(problem.obstacles, {c: None for c in moving_columns(carry)})


def carried_entries(problem: Problem, carry: CarryReport, trajectory: Trajectory, decimals: int) -> dict:
    """The objects a run moves: each one's shape in its own frame (``kind``: box with ``size``,
    sphere, capsule along its x or cylinder along its z with ``radius`` and ``length``; its
    ``name``) and, per frame, where each is: its centre and quaternion (w, x, y, z), (F, k, 7)
    frame after frame."""
    from armanim.arm.rotations import rotation_quaternion

    columns = moving_columns(carry)
    first = frame_bodies(problem, carry, trajectory.phi[:1], trajectory.goal[:1])
    shapes = []
    for k, column in enumerate(columns):
        body = first[0][k] if first else obstacle_body(problem.obstacles, column)
        kind = {BOX: "box", SPHERE: "sphere", ROD: "capsule", CYLINDER: "cylinder"}[body.kind]
        entry: dict = {"kind": kind, "name": problem.obstacles.name(column) or f"obstacles[{column}]"}
        if body.kind == BOX:
            entry["size"] = [float(2 * v) for v in body.half]
        else:
            entry["radius"] = float(body.radius)
            entry["length"] = float(2 * body.half[0] if body.kind == ROD else 2 * body.half[2])
        shapes.append(entry)

    def places(start: int, stop: int) -> list:
        frames = frame_bodies(problem, carry, trajectory.phi[start:stop], trajectory.goal[start:stop])
        poses = np.array(
            [[np.concatenate([b.center, rotation_quaternion(b.rotation)]) for b in bodies] for bodies in frames]
        ).reshape(-1, 7)
        at = np.concatenate([np.round(poses[:, :3], decimals), np.round(poses[:, 3:], 6)], axis=1)
        return [float(v) + 0.0 for v in at.ravel()]

    return {"objects": shapes, "poses": FrameSeries(trajectory.frames, places)}
