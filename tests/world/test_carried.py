"""Pick and place (issue 54): the carried object's cover, its clearances by coal, the placed pose,
touch links, and the scene's checks."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from armanim.arm.kinematics import forward
from armanim.motion.carry import (
    TOUCH,
    CarryReport,
    World,
    after_goal,
    carried_clearance,
    frame_fingers,
    goal_problems,
    tool_transform,
)
from armanim.world.carried import Body, cover_capsules, cover_margin, grasp_offset, obstacle_body
from armanim.world.obstacles import BOX, CYLINDER, ROD, SPHERE

coal = pytest.importorskip("coal")

DATA = Path(__file__).parent.parent / "data"


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(p, k) distance of each point to each segment a-b."""
    ab = b - a
    t = np.clip(np.einsum("pkj,kj->pk", points[:, None] - a, ab) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
    return np.linalg.norm(points[:, None] - (a + t[..., None] * ab), axis=-1)


def _surface_points(body: Body, rng: np.random.Generator) -> np.ndarray:
    """Points on the solid's surface in its own frame: a box's corners and random face points, a
    cylinder's rims and random side points."""
    if body.kind == BOX:
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * body.half
        faces = rng.uniform(-1, 1, (300, 3))
        axis = rng.integers(0, 3, 300)
        faces[np.arange(300), axis] = np.sign(faces[np.arange(300), axis])
        return np.concatenate([corners, faces * body.half])
    angle = rng.uniform(0, 2 * np.pi, 300)
    z = np.concatenate([np.full(100, -1.0), np.full(100, 1.0), rng.uniform(-1, 1, 100)]) * body.half[2]
    return np.stack([body.radius * np.cos(angle), body.radius * np.sin(angle), z], axis=1)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from([BOX, CYLINDER]), st.lists(st.floats(0.005, 0.2), min_size=3, max_size=3), st.integers(0, 2**16))
@example(BOX, [0.02, 0.02, 0.06], 0)
@example(CYLINDER, [0.1, 0.1, 0.01], 1)
def test_cover_holds_the_whole_solid_within_its_margin(kind, sizes, seed):
    """Every point of the solid's surface lies in a capsule of its cover (so the cover's clearance is
    at most the solid's), and no capsule reaches farther than cover_margin beyond the solid."""
    half = np.array(sizes) if kind == BOX else np.array([0.0, 0.0, sizes[2]])
    body = Body(kind, np.eye(3), np.zeros(3), half, 0.0 if kind == BOX else sizes[0])
    start, end, radius = cover_capsules(body)
    points = _surface_points(body, np.random.default_rng(seed))
    inside = (_segment_distance(points, start, end) - radius).min(axis=1)
    assert inside.max() <= 1e-12
    probe = coal.Box(*(2 * half)) if kind == BOX else coal.Cylinder(body.radius, 2 * half[2])
    for a, b, r in zip(start, end, radius):  # the capsules' farthest points: along the six axes from both ends
        for p in (a, b):
            for d in np.concatenate([np.eye(3), -np.eye(3)]):
                far = p + r * d
                result = coal.DistanceResult()
                gap = coal.distance(
                    probe,
                    coal.Transform3s(),
                    coal.Sphere(1e-9),
                    coal.Transform3s(np.eye(3), far),
                    coal.DistanceRequest(),
                    result,
                )
                assert gap <= cover_margin(body) + 1e-9


@cache
def _pick_run():
    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(DATA / "pick-box.yaml").model)
    solution = solve_trajectory(problem)
    return problem, solution, retime(problem, solution, problem.fps)


def _coal_body(body: Body):
    shape = {
        BOX: lambda: coal.Box(*(2 * body.half)),
        SPHERE: lambda: coal.Sphere(body.radius),
        ROD: lambda: coal.Capsule(body.radius, 2 * body.half[0]),
        CYLINDER: lambda: coal.Cylinder(body.radius, 2 * body.half[2]),
    }[body.kind]()
    rotation = (
        body.rotation if body.kind != ROD else body.rotation @ np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]])
    )  # coal's capsule along z
    return shape, coal.Transform3s(rotation, body.center)


def _distance(one, two) -> float:
    return float(coal.distance(*one, *two, coal.DistanceRequest(), coal.DistanceResult()))


def test_the_box_is_carried_and_placed_where_the_tool_put_it_to_1e_9():
    problem, solution, timed = _pick_run()
    assert all(g.reached for g in solution.goals)
    carry = timed.carry
    traj = timed.trajectory
    grasp_end, release_end = timed.goals[1].last_frame, timed.goals[4].last_frame
    part = obstacle_body(problem.obstacles, 1)
    tool = lambda frame: tool_transform(problem, forward(problem.arm, traj.phi[frame]))  # noqa: E731
    offset = grasp_offset(tool(grasp_end), part)
    placed = tool(release_end) @ offset
    final = carry.final.moved[1]
    assert np.abs(final.matrix() - placed).max() < 1e-9
    assert final.center[1] == pytest.approx(-0.2, abs=0.005)  # it really moved


def test_the_carried_box_keeps_its_clearances_by_coal():
    """Every frame that holds the box: the true box (by coal) keeps solver.clearance from the table
    and the floor's plane, and self_clearance from every capsule of a link that is not a touch link."""
    problem, _, timed = _pick_run()
    traj, carry = timed.trajectory, timed.carry
    held = carry.held_names(traj.goal) == "part"
    assert held.sum() > 10
    problems = goal_problems(problem, carry)
    table = _coal_body(obstacle_body(problem.obstacles, 0))
    d_safe, self_safe = problem.solver.clearance, problem.self_pairs.clearance
    touch = set(carry.worlds[2].held.touch)
    carried = carried_clearance(problem, carry, traj.phi, traj.goal)
    for frame in np.nonzero(held)[0]:
        world = problems[traj.goal[frame]]
        pose = forward(problem.arm, traj.phi[frame])
        box = world_box = carry.worlds[traj.goal[frame]].held.body.moved(
            tool_transform(problem, pose) @ carry.worlds[traj.goal[frame]].held.offset
        )
        shape = _coal_body(box)
        assert _distance(shape, table) >= d_safe * (1 - 1e-9)
        assert _distance(shape, table) >= carried[frame] - 1e-9  # the cover's clearance is at most the box's
        lowest = np.min(
            [
                (box.matrix() @ np.append(c, 1))[2]
                for c in np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * box.half
            ]
        )
        assert lowest - problem.obstacles.floor >= d_safe
        caps = problem.capsules
        from armanim.arm.capsules import capsule_ends

        a, b = capsule_ends(caps, pose)
        for i, name in enumerate(caps.names):
            if name in touch:
                continue
            axis = b[i] - a[i]
            length = float(np.linalg.norm(axis))
            z = axis / length if length > 0 else np.array([0.0, 0, 1])
            x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
            x /= np.linalg.norm(x)
            link = (
                coal.Capsule(caps.radius[i], length),
                coal.Transform3s(np.stack([x, np.cross(z, x), z], axis=1), (a[i] + b[i]) / 2),
            )
            assert _distance(shape, link) >= self_safe * (1 - 1e-9), (frame, name)
        del world_box, world


def test_touch_links_are_allowed_and_every_other_link_checked():
    problem, _, timed = _pick_run()
    world = timed.carry.worlds[2]
    carrying = goal_problems(problem, timed.carry)[2]
    touch = set(world.held.touch)
    assert touch == {"panda_link7", "panda_hand", "panda_leftfinger", "panda_rightfinger"}
    checked = {a for a, b in carrying.self_pairs.names if b == "part"}
    moving_links = {n for n, k in zip(problem.capsules.names, problem.capsules.link) if k != problem.arm.n - 1}
    assert checked == moving_links  # every link but those the last joint carries
    assert {(a, TOUCH) for a, b, r in carrying.self_pairs.allowed if b == "part"} == {(t, TOUCH) for t in touch}


BAD = {
    "grasp: nothing": ("goals[1].grasp", "'nothing' names no obstacle"),
    "release: true, grasp: part": ("goals[1].release", "is on a goal that grasps"),
}


def _scene(goals: list, **extra):
    from armanim.scene import scene_model

    return scene_model(
        {
            "version": 1,
            "arm": {"robot": "panda", "joint_values": {"panda_finger_joint1": 0.04}},
            "obstacles": [
                {"box": {"center": [0.5, 0.0, 0.1], "size": [0.4, 0.8, 0.2]}, "name": "table"},
                {"box": {"center": [0.5, 0.2, 0.28], "size": [0.04, 0.04, 0.12]}, "name": "part"},
            ],
            "floor": 0.0,
            "goals": goals,
            "solver": {"clearance": 0.01, "tolerance": 0.002, **extra},
        }
    )


GRASP = {"position": [0.5, 0.2, 0.332], "orientation": {"rpy": [180, 0, 0]}, "grasp": "part"}
RELEASE = {"position": [0.5, -0.2, 0.34], "orientation": {"rpy": [180, 0, 0]}, "release": True}


@pytest.mark.parametrize(
    ("goals", "field", "words"),
    [
        (
            [{**GRASP, "grasp": "can"}],
            "goals[0].grasp",
            "'can' names no obstacle (expected the name of one: 'table', 'part')",
        ),
        ([RELEASE], "goals[0].release", "puts down nothing: the tool holds nothing here"),
        (
            [GRASP, {**GRASP, "grasp": "table"}],
            "goals[1].grasp",
            "takes 'table' while the tool still holds 'part' (grasped at goals[0]",
        ),
        ([{**GRASP, "release": True}], "goals[0].release", "is on a goal that grasps"),
        (
            [{**GRASP, "touch_links": ["panda_hand", "gripper"]}],
            "goals[0].touch_links[1]",
            "'gripper' names no link of the arm",
        ),
        (
            [{**GRASP, "grasp": "table", "position": [0.5, 0.0, 0.45]}],
            "goals[0].grasp",
            "wider than the gripper opens (0.08",
        ),
        ([{**GRASP, "position": [0.5, 0.2, 0.45]}], "goals[0].grasp", "'part' is 0.11 from the goal's tool point"),
    ],
)
def test_each_bad_grasp_is_reported_at_its_field(goals, field, words):
    from armanim.scene.checks import scene_problems

    problems = scene_problems(_scene(goals))
    assert any(f == field and words in m for f, m in problems), problems


def test_an_object_resting_within_clearance_of_its_table_is_reported():
    from armanim.scene.checks import scene_problems

    problems = scene_problems(_scene([GRASP], clearance=0.02))
    assert any(f == "obstacles[1]" and "'part' rests 0.0127 from obstacles[0] ('table')" in m for f, m in problems), (
        problems
    )


def test_the_viewer_and_the_video_draw_the_box_where_it_is():
    """The viewer's data place the box at rest before the grasp, in the tool while carried, and
    where it was put at the end; the table stays with the still obstacles."""
    from armanim.render.pictures.canvas import moving_objects
    from armanim.render.viewer.data import viewer_data
    from armanim.scene import load_scene, render_settings

    problem, _, timed = _pick_run()
    traj = timed.trajectory
    data = viewer_data(
        problem,
        traj,
        timed.goals,
        render_settings(load_scene(DATA / "pick-box.yaml").model),
        title="t",
        carry=timed.carry,
    )
    poses = np.array(data["carried"]["poses"]).reshape(traj.frames, 1, 7)
    assert data["carried"]["objects"] == [{"kind": "box", "name": "part", "size": [0.04, 0.04, 0.12]}]
    assert [b["center"] for b in data["boxes"]] == [[0.5, 0.0, 0.1]]
    assert poses[0, 0, :3] == pytest.approx([0.5, 0.2, 0.28])
    assert poses[-1, 0, :3] == pytest.approx(
        timed.carry.final.moved[1].center, abs=10.0 ** -data["decimals"]
    )  # the page's rounding
    carried = traj.goal == 3
    tips = traj.tip[carried]
    assert np.linalg.norm(poses[carried, 0, :3] - tips, axis=1) == pytest.approx(
        0.052, abs=0.002
    )  # in the tool, 5 cm below it
    still, frames = moving_objects(problem, timed)
    assert len(still.obstacles.boxes) == 1 and len(frames) == traj.frames
    assert frames[-1].boxes.centers[0] == pytest.approx(timed.carry.final.moved[1].center)


def test_a_carried_bar_that_would_hit_the_wall_goes_over_it_never_through():
    """moveit #1217's trap: the tool alone crosses the wall on its straight way; carrying a bar
    that would hit it, the arm goes over it, and by coal the bar keeps clearance from the wall in
    every frame it is held."""
    from dataclasses import replace

    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(DATA / "carry-over-wall.yaml").model)
    empty = replace(problem, goals=(replace(problem.goals[0], grasp=None),) + problem.goals[1:])
    alone = retime(empty, solve_trajectory(empty), problem.fps)
    solved = solve_trajectory(problem)
    carrying = retime(problem, solved, problem.fps)
    for run in (alone, carrying):
        assert all(g.reached or g.reason is not None for g in run.goals)
    crossing = lambda run: run.trajectory.tip[run.trajectory.goal == 2, 2].max()  # noqa: E731
    assert crossing(alone) < 0.535 < 0.55 < crossing(carrying)  # straight alone, over the wall with the bar
    traj, carry = carrying.trajectory, carrying.carry
    wall = _coal_body(obstacle_body(problem.obstacles, 2))
    held = np.nonzero(carry.held_names(traj.goal) == "bar")[0]
    assert len(held) > 20
    for frame in held:
        world = carry.worlds[traj.goal[frame]].held
        bar = world.body.moved(tool_transform(problem, forward(problem.arm, traj.phi[frame])) @ world.offset)
        assert _distance(_coal_body(bar), wall) >= problem.solver.clearance * (1 - 1e-9), frame


@settings(max_examples=4, deadline=None)
@given(
    st.floats(0.03, 0.05), st.floats(0.06, 0.1), st.floats(-0.45, -0.3), st.floats(0.45, 0.62), st.floats(-0.15, 0.15)
)
@example(0.04, 0.08, -0.45, 0.58, 0.0)
def test_pick_and_place_keeps_every_invariant(width, height, y, x_place, y_place):
    """A Panda takes a box of random size from a table and puts it on a shelf board at a random
    place: every trajectory invariant holds in each goal's world (tests/invariants.py), the box
    ends exactly where the tool put it, and no frame has its cover under clearance."""
    from hypothesis import assume
    from invariants import assert_trajectory_invariants

    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import scene_model, scene_to_problem
    from armanim.scene.checks import scene_problems

    rest = 0.2 + height / 2 + 0.034  # the box's centre: its cover 2.2 cm and more above the table
    grasp = rest + height / 2 - 0.02
    place = 0.4 + 0.034 + height / 2 - rest + grasp  # the tool where the box stands as high above the board
    down = {"orientation": {"rpy": [180, 0, 0]}}
    model = scene_model(
        {
            "version": 1,
            "arm": {"robot": "panda", "joint_values": {"panda_finger_joint1": 0.04}},
            "obstacles": [
                {"box": {"center": [0.62, 0.0, 0.39], "size": [0.3, 0.7, 0.02]}},
                {"box": {"center": [0.25, y, 0.1], "size": [0.3, 0.3, 0.2]}, "name": "table"},
                {"box": {"center": [0.25, y, rest], "size": [width, width, height]}, "name": "box"},
            ],
            "floor": 0.0,
            "goals": [
                {"position": [0.25, y, grasp + 0.1], **down},
                {"position": [0.25, y, grasp], **down, "grasp": "box"},
                {"position": [0.25, y, 0.6], **down},
                {"position": [x_place, y_place, place + 0.08], **down},
                {"position": [x_place, y_place, place], **down, "release": True},
                {"position": [x_place, y_place, place + 0.1], **down},
            ],
            "solver": {"method": "dls", "tolerance": 0.005, "clearance": 0.02, "max_step": 0.02},
        }
    )
    assume(not scene_problems(model))
    problem = scene_to_problem(model)
    timed = retime(problem, solve_trajectory(problem), problem.fps)
    assert_trajectory_invariants(problem, timed)
    traj, carry = timed.trajectory, timed.carry
    carried = carried_clearance(problem, carry, traj.phi, traj.goal)
    assert np.nanmin(carried) >= problem.solver.clearance - 1e-9
    if timed.goals[4].reached and timed.goals[1].reached:
        tool = lambda f: tool_transform(problem, forward(problem.arm, traj.phi[f]))  # noqa: E731
        expected = tool(timed.goals[4].last_frame) @ grasp_offset(
            tool(timed.goals[1].last_frame), obstacle_body(problem.obstacles, 2)
        )
        assert np.abs(carry.final.moved[2].matrix() - expected).max() < 1e-9


def test_a_finished_run_read_back_carries_the_box_again(tmp_path):
    """run writes held and carried_clearance; load_run (render, view) reads them back and replays
    each grasp and release at its goal's last frame: the box ends where summary.json put it."""
    import csv
    import json

    from armanim.runs.options import RunOptions
    from armanim.runs.pipeline import run_scene
    from armanim.runs.reload import load_run

    folder = run_scene(DATA / "pick-box.yaml", tmp_path, RunOptions(video=False, viewer=False)).folder
    rows = list(csv.DictReader(open(folder / "trajectory.csv", newline="")))
    assert {r["held"] for r in rows} == {"", "part"}
    assert all((r["carried_clearance"] == "") == (r["held"] == "") for r in rows)
    summary = json.loads((folder / "summary.json").read_text())
    assert [g["grasped"] for g in summary["goals"]] == [None, "part", None, None, None, None]
    assert [g["released"] for g in summary["goals"]] == [None, None, None, None, "part", None]
    assert summary["min_carried_clearance"] >= summary["clearance"]
    run = load_run(folder)
    assert run.solution.carry.final.moved[1].center == pytest.approx(summary["objects"]["part"]["center"], abs=1e-9)
    assert "part" in (folder / "self-collision.yaml").read_text()
    gripper = [float(r["gripper_m"]) for r in rows]  # the Panda's fingers: open, closed on the 4 cm part, open again
    assert gripper[0] == 0.04 and gripper[-1] == 0.04 and min(gripper) == pytest.approx(0.02, abs=1e-4)
    replayed = frame_fingers(run.problem, run.solution.carry, run.solution.trajectory.goal, run.solution.trajectory.fps)
    assert gripper == replayed.tolist()


def test_an_approach_comes_in_along_a_straight_line_and_the_grasp_and_release_still_hold():
    """approach: the tool comes to the grasp (along its own z: down) and to the release (along the
    world's -z) on straight lines, within the path tolerance, ending at the goal; the box still
    ends where the tool put it."""
    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(DATA / "pick-approach.yaml").model)
    timed = retime(problem, solve_trajectory(problem), problem.fps)
    assert all(g.reached for g in timed.goals)
    traj = timed.trajectory
    assert (
        problem.goals[4].to_approach and problem.goals[5].release
    )  # a release's approach starts with a goal of its own to the line
    for k, (target, distance) in {1: ([0.5, 0.2, 0.332], 0.08), 5: ([0.5, -0.2, 0.335], 0.06)}.items():
        along = (traj.goal == k) & (traj.mode == "path")
        tips = traj.tip[along]
        assert len(tips) > 5
        assert np.abs(tips[:, :2] - target[:2]).max() <= problem.solver.path_tolerance
        assert tips[0, 2] == pytest.approx(target[2] + distance, abs=0.005) and tips[-1, 2] == pytest.approx(
            target[2], abs=0.005
        )
        assert np.all(np.diff(tips[:, 2]) <= 1e-9)  # down all the way
    tool = lambda f: tool_transform(problem, forward(problem.arm, traj.phi[f]))  # noqa: E731
    expected = tool(timed.goals[5].last_frame) @ grasp_offset(
        tool(timed.goals[1].last_frame), obstacle_body(problem.obstacles, 1)
    )
    assert np.abs(timed.carry.final.moved[1].matrix() - expected).max() < 1e-9


def test_an_approach_along_the_tool_needs_the_tool_s_orientation():
    from armanim.scene.checks import scene_problems

    goal = {"position": [0.5, 0.2, 0.332], "grasp": "part", "approach": {"distance": 0.08}}
    assert ("goals[0].approach.axis",) == tuple(f for f, m in scene_problems(_scene([goal])) if "approach" in f)


def test_the_fingers_close_on_the_part_and_open_after_the_release_while_the_arm_stands_still():
    """The Panda's gripper (issue 54, item 3): open while the arm heads for the grasp, closed on the
    part's width across the fingers (pinocchio's panda_hand y axis at the grasp: 2 q = the box's
    extent along it) while it is carried, open again after the release; it moves only in frames
    where the arm stands still, at most the finger joint's 0.2 m/s, and the invariants (every
    frame's clearance with the fingers where they are) hold."""
    pin = pytest.importorskip("pinocchio")
    from invariants import assert_trajectory_invariants

    from armanim.scene.robots import bundled_robot

    problem, _, timed = _pick_run()
    traj = timed.trajectory
    fingers = frame_fingers(problem, timed.carry, traj.goal, traj.fps)
    moves = np.nonzero(np.diff(fingers))[0] + 1
    assert set(traj.goal[moves]) == {1, 4}  # the grasp closes them, the release opens them
    assert np.all(traj.phi[moves] == traj.phi[moves - 1])  # the arm stands still meanwhile
    assert np.abs(np.diff(fingers)).max() * traj.fps <= problem.gripper.speed + 1e-12
    model = pin.buildModelFromUrdf(str(bundled_robot("panda").urdf))
    data = model.createData()
    q = pin.neutral(model)
    for name, angle in zip(
        problem.arm.joint_names if hasattr(problem.arm, "joint_names") else [f"panda_joint{i}" for i in range(1, 8)],
        traj.phi[timed.goals[1].last_frame],
    ):
        joint = model.joints[model.getJointId(name)]
        q[joint.idx_q] = angle
    pin.framesForwardKinematics(model, data, q)
    across = data.oMf[model.getFrameId("panda_hand")].rotation[:, 1]
    extent = float(np.abs(across) @ np.array([0.04, 0.04, 0.12]))  # the part's box stands axis-aligned
    held = (traj.goal >= 2) & (traj.goal <= 3)
    assert 2 * fingers[held] == pytest.approx(extent, abs=1e-9)
    assert np.all(fingers[traj.goal <= 1][:-3] == 0.04) and fingers[-1] == 0.04
    assert_trajectory_invariants(problem, timed)


def test_the_fingers_capsules_follow_the_finger_joint_as_pinocchio_places_the_fingers():
    """Each finger capsule at a gripper value q lies where pinocchio puts the URDF's capsule of that
    finger with both finger joints at q (the mimic's too), at random arm poses."""
    pin = pytest.importorskip("pinocchio")
    from armanim.arm.capsules import capsule_ends
    from armanim.arm.gripper import moved_fingers
    from armanim.scene import scene_to_problem
    from armanim.scene.robots import bundled_robot

    model_scene = _scene([GRASP])
    problem = scene_to_problem(model_scene)
    gripper = problem.gripper
    assert gripper.joint == "panda_finger_joint1" and gripper.span == 2.0 and gripper.speed == 0.2
    specs = model_scene.arm.urdf_arm.capsules
    fingers = [i for i, spec in enumerate(specs) if "finger" in spec.link]
    assert fingers and set(np.nonzero(gripper.rate.any(axis=1))[0]) == set(fingers)
    model = pin.buildModelFromUrdf(str(bundled_robot("panda").urdf))
    data = model.createData()
    rng = np.random.default_rng(54)
    for value in (0.0, 0.013, 0.04):
        phi = rng.uniform(-1.5, 1.5, 7)
        q = pin.neutral(model)
        for k, angle in enumerate(phi):
            q[model.joints[model.getJointId(f"panda_joint{k + 1}")].idx_q] = angle
        for name in ("panda_finger_joint1", "panda_finger_joint2"):
            if model.existJointName(name):
                q[model.joints[model.getJointId(name)].idx_q] = value
        pin.framesForwardKinematics(model, data, q)
        starts, ends = capsule_ends(moved_fingers(problem.capsules, gripper, value), forward(problem.arm, phi))
        for i in fingers:
            place = data.oMf[model.getFrameId(specs[i].link)]
            np.testing.assert_allclose(
                starts[i], place.rotation @ specs[i].start + place.translation, atol=1e-9, rtol=0
            )
            np.testing.assert_allclose(ends[i], place.rotation @ specs[i].end + place.translation, atol=1e-9, rtol=0)


def test_the_fingers_open_before_a_grasp_when_the_scene_holds_them_nearly_closed():
    """arm.joint_values leaves the fingers at 0.01: the goal before the grasp holds 0.2 s longer and
    opens them at its end (0.01 to 0.04 at 0.2 m/s: 5 frames at 30 fps), the grasp closes them
    (0.04 to 0.02: 3 frames); a robot-less arm has no gripper."""
    from armanim.scene import scene_model, scene_to_problem

    scene = _scene([{"position": [0.5, 0.2, 0.4], "orientation": {"rpy": [180, 0, 0]}}, GRASP])
    scene = scene.model_copy(
        update={"arm": scene.arm.model_copy(update={"joint_values": {"panda_finger_joint1": 0.01}})}
    )
    problem = scene_to_problem(scene)
    assert problem.gripper.rest == 0.01 and [g.hold for g in problem.goals] == pytest.approx([0.2, 0.2])
    opened = after_goal(problem, World(), 0, True, forward(problem.arm, problem.home))
    assert opened.fingers == 0.04
    carry = CarryReport((World(), opened), World(fingers=0.02))
    fingers = frame_fingers(problem, carry, np.repeat([0, 1], 10), 30.0)
    assert fingers[:5].tolist() == [0.01] * 5 and fingers[9] == 0.04 and fingers[10:16].tolist() == [0.04] * 6
    assert fingers[-1] == 0.02 and np.abs(np.diff(fingers)).max() * 30.0 <= 0.2 + 1e-12
    links = scene_model(
        {
            "version": 1,
            "arm": {"links": [1, 1]},
            "obstacles": [{"center": [1, 1, 0], "radius": 0.1, "name": "ball"}],
            "goals": [{"position": [1.0, 0.9, 0.0], "grasp": "ball"}],
        }
    )
    assert scene_to_problem(links).gripper is None


def test_an_object_wider_than_the_gripper_opens_is_refused_at_its_line(cli, tmp_path, monkeypatch):
    text = (
        (DATA / "pick-box.yaml")
        .read_text()
        .replace("size: [0.04, 0.04, 0.12]}, name: part", "size: [0.09, 0.09, 0.12]}, name: part")
    )
    (tmp_path / "wide.yaml").write_text(text)
    monkeypatch.chdir(tmp_path)
    result = cli("validate", "wide.yaml")
    line = 1 + text.splitlines().index(next(t for t in text.splitlines() if "grasp: part" in t))
    assert result.exit_code == 2
    assert (
        f"wide.yaml:{line}: goals[1].grasp: 'part' is 0.09 across at its narrowest, wider than the gripper opens (0.08"
        in result.stdout + result.stderr
    ), result.stdout + result.stderr


def test_a_retreat_leaves_along_a_straight_line_in_the_world_after_its_goal():
    """retreat (issue 54, item 2): after the grasp the tool goes back up along its own z, carrying
    the part, and after the release up along the world's z, the part left where it was put; each
    is a path goal of its own right after its goal, straight within the path tolerance, upward all
    the way over its distance; every invariant holds and the part ends where the tool put it."""
    from invariants import assert_trajectory_invariants

    from armanim.motion.timing.retime import retime
    from armanim.motion.trajectory import solve_trajectory
    from armanim.scene import load_scene, scene_to_problem

    problem = scene_to_problem(load_scene(DATA / "pick-retreat.yaml").model)
    assert [g.retreat for g in problem.goals] == [False, False, True, False, False, True]
    timed = retime(problem, solve_trajectory(problem), problem.fps)
    assert all(g.reached for g in timed.goals)
    traj = timed.trajectory
    held = timed.carry.held_names(traj.goal)
    for k, (start, distance, holding) in {
        2: ([0.5, 0.2, 0.332], 0.07, "part"),
        5: ([0.5, -0.2, 0.335], 0.06, ""),
    }.items():
        along = (traj.goal == k) & (traj.mode == "path")
        tips = traj.tip[along]
        assert len(tips) > 5 and set(held[traj.goal == k]) == {holding}
        assert np.abs(tips[:, :2] - start[:2]).max() <= problem.solver.path_tolerance
        assert tips[0, 2] == pytest.approx(start[2], abs=0.005) and tips[-1, 2] == pytest.approx(
            start[2] + distance, abs=0.005
        )
        assert np.all(np.diff(tips[:, 2]) >= -1e-9)  # up all the way
    tool = lambda f: tool_transform(problem, forward(problem.arm, traj.phi[f]))  # noqa: E731
    expected = tool(timed.goals[4].last_frame) @ grasp_offset(
        tool(timed.goals[1].last_frame), obstacle_body(problem.obstacles, 1)
    )
    assert np.abs(timed.carry.final.moved[1].matrix() - expected).max() < 1e-9
    assert_trajectory_invariants(problem, timed)
    from armanim.output.summary import summary_dict

    summary = summary_dict(problem, timed, name="pick-retreat", scene_file="pick-retreat.yaml", sha256="")
    assert [g["retreat_of"] for g in summary["goals"]] == [None, None, 1, None, None, 3]  # the scene's goals 1 and 3


@pytest.mark.parametrize(
    ("goal", "field", "words"),
    [
        (
            {**GRASP, "retreat": {"distance": 0.05}, "orientation": None},
            "goals[0].retreat.axis",
            "is tool on a goal without orientation",
        ),
        (
            {"joints": [0, 0, 0, -90, 0, 90, 45], "retreat": {"distance": 0.05, "axis": [0, 0, 1]}},
            "goals[0].retreat",
            "is on a joint goal",
        ),
        (
            {"joints": [0, 0, 0, -90, 0, 90, 45], "retreat": {"distance": 0.05}},
            "goals[0].retreat",
            "is on a joint goal",
        ),
        (
            {"joints": [0, 0, 0, -90, 0, 90, 45], "approach": {"distance": 0.05}},
            "goals[0].approach",
            "is on a joint goal",
        ),  # not its axis
        (
            {
                "path": {"line": [[0.5, 0.2, 0.4], [0.5, 0.0, 0.4]]},
                "speed": 0.1,
                "retreat": {"distance": 0.05, "axis": [0, 0, 1]},
            },
            "goals[0].retreat",
            "is on a path goal",
        ),
    ],
)
def test_a_retreat_it_cannot_make_is_reported_at_its_field(goal, field, words):
    from armanim.scene.checks import scene_problems

    goal = {k: v for k, v in goal.items() if v is not None}
    problems = scene_problems(_scene([goal]))
    assert any(f == field and words in m for f, m in problems), problems


@pytest.mark.parametrize(
    ("line", "field", "words"),
    [
        (
            {"distance": 5e-324},
            "goals[0].{}.distance",
            "is too small",
        ),  # the campaign's IndexError at run: a line of no pieces
        ({"distance": 1e300}, "goals[0].{}.distance", "is too large"),  # an OverflowError counting its steps
        ({"distance": 0.05, "speed": 5e-324}, "goals[0].{}.speed", "is too small"),  # a ZeroDivisionError
        (
            {"distance": 0.5, "speed": 1e-9},
            "goals[0].{}.speed",
            "frames, 15,000,000,000 of them along this",
        ),  # validate said ok, run refused
    ],
)
@pytest.mark.parametrize("name", ["approach", "retreat"])
def test_an_approach_or_retreat_beyond_its_bounds_is_reported_at_its_field(name, line, field, words):
    """The sixth campaign's tracebacks and its run-only refusal: an approach's or a retreat's distance
    and speed are lengths and a frame count that validate bounds, as a path goal's are."""
    from armanim.scene.checks import scene_problems

    goal = {"position": [0.5, 0.0, 0.4], name: {**line, "axis": [0, 0, 1]}}
    problems = scene_problems(_scene([goal]))
    assert any(f == field.format(name) and words in m for f, m in problems), problems


def test_the_retreat_scene_validates():
    from armanim.scene import load_scene
    from armanim.scene.checks import scene_problems

    assert scene_problems(load_scene(DATA / "pick-retreat.yaml").model) == []


def test_the_fingers_stay_where_opening_them_would_bring_one_under_its_clearance():
    """The fingers open before a grasp (arm.joint_values holds them closed) unless a ball stands
    at the middle of the opened left finger's capsule: then they stay closed (fingers_free measures
    every capsule at 17 values along the way)."""
    from armanim.arm.capsules import capsule_ends
    from armanim.arm.gripper import moved_fingers
    from armanim.scene import scene_model, scene_to_problem

    def problem_with(extra: list) -> object:
        scene = _scene([{"position": [0.5, 0.2, 0.4], "orientation": {"rpy": [180, 0, 0]}}, GRASP]).model_dump(
            by_alias=True, exclude_none=True
        )
        scene["arm"] = {"robot": "panda", "joint_values": {"panda_finger_joint1": 0.0}}
        scene["obstacles"] += extra
        return scene_to_problem(scene_model(scene))

    free = problem_with([])
    pose = forward(free.arm, free.home)
    assert after_goal(free, World(), 0, True, pose).fingers == 0.04
    left = free.capsules.names.index("panda_leftfinger")
    starts, ends = capsule_ends(moved_fingers(free.capsules, free.gripper, 0.04), pose)
    middle = (starts[left] + ends[left]) / 2
    blocked = problem_with([{"center": middle.tolist(), "radius": 0.005}])
    assert after_goal(blocked, World(), 0, True, pose).fingers is None  # they stay at joint_values


@pytest.mark.parametrize(("yaw", "refused"), [(0, True), (90, False)])
def test_a_part_wider_across_the_fingers_than_they_open_is_refused_at_that_orientation(yaw, refused):
    """A 3 x 10 cm part fits the Panda's 8 cm gripper across its narrow side only: the grasp with
    the fingers closing along the world's y (yaw 0) is refused, turned 90 degrees it is not."""
    from armanim.scene import scene_model
    from armanim.scene.checks import scene_problems

    scene = _scene([{**GRASP, "orientation": {"rpy": [180, 0, yaw]}}]).model_dump(by_alias=True, exclude_none=True)
    scene["obstacles"][1]["box"]["size"] = [0.03, 0.10, 0.12]
    problems = scene_problems(scene_model(scene))
    found = [m for f, m in problems if f == "goals[0].grasp"]
    assert bool(found) == refused, problems
    if refused:
        assert (
            "'part' is 0.1 across the fingers at this goal's orientation, wider than the gripper opens (0.08"
            in found[0]
        )


def test_validation_s_finger_axis_is_the_run_s_finger_direction():
    """checks.finger_axis (from a tool rotation, at validate time) and carry.finger_direction (from
    the pose, at the grasp) agree at random poses."""
    from armanim.arm.kinematics import tool_rotation
    from armanim.motion.carry import finger_direction
    from armanim.scene import scene_to_problem
    from armanim.scene.checks import finger_axis

    problem = scene_to_problem(_scene([GRASP]))
    for phi in np.random.default_rng(7).uniform(-1.5, 1.5, (5, 7)):
        pose = forward(problem.arm, phi)
        np.testing.assert_allclose(
            finger_axis(problem, tool_rotation(problem.arm, pose)), finger_direction(problem, pose), atol=1e-12
        )
