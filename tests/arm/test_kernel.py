"""The compiled kinematics (:mod:`armanim.arm.kernel`) against the numpy chain it compiles
(:mod:`armanim.arm.kinematics`, :mod:`armanim.arm.rotations`, the oracle: equal to 1e-12) on
random general chains and the bundled robots, and against pinocchio on the robots' URDFs."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import arms, poses

from armanim.arm import kernel
from armanim.arm.chain import serial_chain
from armanim.arm.kinematics import Arm, angular_jacobian, forward, tip_jacobian, tool_rotation
from armanim.arm.rotations import rotation_exp, rotation_log
from armanim.scene.robots import ROBOTS, bundled_robot
from armanim.scene.urdf import chain_joints, read_urdf

TOL = 1e-12
ROBOT_ARMS = {
    name: serial_chain(
        np.eye(4),
        chain_joints(
            read_urdf(Path(bundled_robot(name).urdf)), bundled_robot(name).base_link, bundled_robot(name).tip_link
        ),
        np.eye(4),
    ).arm
    for name in ROBOTS
}

vectors = st.lists(st.floats(-3.0, 3.0, allow_nan=False), min_size=3, max_size=3).map(np.array)


@st.composite
def general_arms(draw, max_links: int = 8) -> Arm:
    """Any chain: unit axes in any direction, offsets, turns and a base rotation of any kind (the URDF case)."""
    n = draw(st.integers(1, max_links))
    axes = [draw(vectors) for _ in range(n)]
    axes = [a / np.linalg.norm(a) if np.linalg.norm(a) > 1e-3 else np.array([0.0, 0, 1]) for a in axes]
    return Arm(
        base=draw(vectors),
        axes=np.array(axes),
        offsets=np.array([draw(vectors) for _ in range(n)]),
        base_rotation=rotation_exp(draw(vectors)),
        turns=np.array([rotation_exp(draw(vectors)) for _ in range(n)]),
    )


def any_arms():
    return st.one_of(general_arms(), arms(max_links=7), st.sampled_from(list(ROBOT_ARMS.values())))


@st.composite
def arm_and_poses(draw):
    arm = draw(any_arms())
    count = draw(st.integers(0, 4))
    return arm, draw(poses(arm.n)), np.array([draw(poses(arm.n)) for _ in range(count)]).reshape(count, arm.n)


def assert_same_pose(arm, phi):
    expected = forward(arm, phi)
    got, tool = kernel.forward_with_tool(arm, phi)
    np.testing.assert_allclose(got.points, expected.points, atol=TOL, rtol=0)
    np.testing.assert_allclose(got.frames, expected.frames, atol=TOL, rtol=0)
    np.testing.assert_allclose(got.axes, np.einsum("...jab,jb->...ja", expected.frames, arm.axes), atol=TOL, rtol=0)
    np.testing.assert_allclose(tool, tool_rotation(arm, expected), atol=TOL, rtol=0)
    jac = kernel.geometric_jacobian(got, arm)
    np.testing.assert_allclose(jac[..., :3, :], tip_jacobian(arm, expected), atol=TOL * max(1.0, arm.reach), rtol=0)
    np.testing.assert_allclose(jac[..., 3:, :], angular_jacobian(arm, expected), atol=TOL, rtol=0)


@settings(max_examples=150, deadline=None)
@given(arm_and_poses())
def test_compiled_forward_kinematics_equals_the_numpy_chain(case):
    arm, phi, batch = case
    assert_same_pose(arm, phi)
    assert_same_pose(arm, batch)  # a batch, possibly empty
    if len(batch):
        assert_same_pose(arm, batch.reshape(1, len(batch), arm.n))  # any leading shape
        one_by_one = [kernel.forward(arm, p).points for p in batch]
        np.testing.assert_array_equal(
            kernel.forward(arm, batch).points, one_by_one
        )  # a pose's numbers do not depend on its batch


def test_compiled_forward_kinematics_of_the_notes_arm_at_home():
    arm = Arm.from_names([2, 5, 5, 5], base=(5, 5, 0))
    pose = kernel.forward(arm, np.zeros(4))
    assert pose.tip.tolist() == [5.0, 5.0, 17.0]
    assert kernel.geometric_jacobian(pose)[:3].tolist() == [
        [0.0, 15.0, 10.0, 5.0],
        [0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0],
    ]


rotations = vectors.map(rotation_exp)
near_half_turns = st.tuples(vectors, st.floats(np.pi - 0.5, np.pi)).map(
    lambda va: (
        rotation_exp(va[1] * va[0] / np.linalg.norm(va[0]))
        if np.linalg.norm(va[0]) > 1e-3
        else rotation_exp(np.array([0.0, 0.0, va[1]]))
    )
)
tiny_turns = vectors.map(lambda v: rotation_exp(1e-6 * v))


@settings(max_examples=300, deadline=None)
@given(st.one_of(rotations, near_half_turns, tiny_turns), rotations)
def test_compiled_rotation_log_equals_the_numpy_one(rot, goal):
    np.testing.assert_allclose(kernel.rotation_log(rot), rotation_log(rot), atol=TOL, rtol=0)
    np.testing.assert_allclose(
        kernel.rotation_log(np.stack([rot, goal])), rotation_log(np.stack([rot, goal])), atol=TOL, rtol=0
    )
    np.testing.assert_allclose(kernel.rotation_error(goal, rot), rotation_log(goal @ rot.T), atol=TOL, rtol=0)


@pytest.mark.parametrize("axis", [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [1.0, 1, 0], [1.0, -2, 3]])
def test_compiled_rotation_log_of_a_half_turn_and_the_identity(axis):
    axis = np.array(axis) / np.linalg.norm(axis)
    log = kernel.rotation_log(rotation_exp(np.pi * axis))
    assert abs(np.linalg.norm(log) - np.pi) < TOL and abs(abs(log @ axis) - np.pi) < 1e-9  # either sign of a half turn
    np.testing.assert_allclose(log, rotation_log(rotation_exp(np.pi * axis)), atol=TOL, rtol=0)
    assert kernel.rotation_log(np.eye(3)).tolist() == [0.0, 0.0, 0.0]


@pytest.mark.parametrize("name", ROBOTS)
def test_compiled_tool_frame_and_jacobian_match_pinocchio(name):
    pin = pytest.importorskip("pinocchio")
    robot = bundled_robot(name)
    arm = ROBOT_ARMS[name]
    model = pin.buildModelFromUrdf(str(robot.urdf))
    data = model.createData()
    frame = model.getFrameId(robot.tip_link)
    joints = [model.joints[model.getJointId(j)] for j in arm.joint_names]
    rng = np.random.default_rng(20261205)
    phi = rng.uniform(-np.pi, np.pi, (8, arm.n))
    batch, tools = kernel.forward_with_tool(arm, phi)
    jacobians = kernel.geometric_jacobian(batch, arm)
    for k, angles in enumerate(phi):
        q = pin.neutral(model)
        for j, angle in zip(joints, angles):
            q[j.idx_q : j.idx_q + j.nq] = [np.cos(angle), np.sin(angle)] if j.nq == 2 else [angle]
        pin.framesForwardKinematics(model, data, q)
        np.testing.assert_allclose(batch.tip[k], data.oMf[frame].translation, atol=TOL, rtol=0)
        np.testing.assert_allclose(tools[k], data.oMf[frame].rotation, atol=TOL, rtol=0)
        jac = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(jacobians[k], jac[:, [j.idx_v for j in joints]], atol=TOL, rtol=0)


def test_the_packed_chain_is_computed_once_per_arm():
    arm = Arm.from_names([1.0, 2.0])
    assert kernel.packed_chain(arm) is kernel.packed_chain(arm)


def test_the_kernel_compiles_where_numba_finds_no_folder_to_cache_in():
    """A read-only install run by a user with no writable home: numba refuses ``cache=True``,
    and the kernel compiles in memory instead of every solve ending in a traceback."""
    import subprocess
    import sys

    program = (
        "import numba.core.caching as caching\n"
        "impl = getattr(caching, 'CacheImpl', None) or caching._CacheImpl  # its name in numba >= 0.61, before\n"
        "impl._locator_classes = []  # as numba finds none: no writable folder\n"
        "import numpy as np\n"
        "from armanim.arm import kernel\n"
        "from armanim.arm.kinematics import Arm\n"
        "pose = kernel.forward(Arm.from_names([2, 5, 5, 5], base=(5, 5, 0)), np.zeros(4))\n"
        "print(pose.tip.tolist(), kernel.geometric_jacobian(pose).shape, kernel.rotation_log(np.eye(3)).tolist())\n"
    )
    proc = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[5.0, 5.0, 17.0] (6, 4) [0.0, 0.0, 0.0]"


def test_the_public_forward_is_the_compiled_kernel():
    """docs/python-api.md: ``armanim.forward`` is the kinematics the solver runs on (issue 55,
    item 4), one pose or a batch, the numpy chain's numbers to rounding."""
    import armanim

    assert armanim.forward is kernel.forward
    arm = ROBOT_ARMS["panda"]
    phi = np.random.default_rng(5).uniform(-2, 2, (6, arm.n))
    for q in (phi[0], phi):
        np.testing.assert_allclose(armanim.forward(arm, q).points, forward(arm, q).points, rtol=0, atol=1e-12)


@pytest.mark.parametrize("shape", [(2,), (8,), (), (3, 2), (0,)])
def test_compiled_forward_refuses_angles_that_are_not_one_a_joint(shape):
    """Campaign 16: ``armanim.forward`` of a Panda given 2 angles returned a pose read past the
    array's end (two calls of the same short pose, two different tips); 8 angles or one number
    were taken silently. numpy's reference refuses them; so does the compiled one now."""
    arm = ROBOT_ARMS["panda"]
    with pytest.raises(ValueError, match=r"arm's 7 joints"):
        kernel.forward(arm, np.full(shape, 0.3))


def test_a_cache_numba_cannot_write_leaves_the_code_unkept_not_the_command_failed(tmp_path):
    """Campaign 16: with numba's cache on a full disk (``NUMBA_CACHE_DIR`` on a small tmpfs) every
    command that compiled, ``validate`` included, ended in exit 3, "armanim: output: No space left
    on device": numba raised the write's OSError. The kernel now runs compiled, unkept, and says so."""
    import subprocess
    import sys

    program = (
        "import errno\n"
        "import numba.core.caching as caching\n"
        "def full(self, key, data):\n"
        "    raise OSError(errno.ENOSPC, 'No space left on device')\n"
        "caching.IndexDataCacheFile.save = full  # the disk is full\n"
        "import numpy as np\n"
        "from armanim.arm import kernel\n"
        "from armanim.arm.kinematics import Arm\n"
        "print(kernel.forward(Arm.from_names([2, 5, 5, 5], base=(5, 5, 0)), np.zeros(4)).tip.tolist(), kernel.CODE_KEPT)\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    proc = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[5.0, 5.0, 17.0] False"


def test_numba_told_not_to_compile_still_runs_armanim_s_kernels_compiled_from_python(tmp_path):
    """Campaign 16: the Python API under ``NUMBA_DISABLE_JIT=1`` (which the command drops, but a
    program's environment keeps) ran the kernels as plain Python: ``run_scene`` of a plain scene
    ended in a ZeroDivisionError. armanim's kernels compile anyway, with a warning."""
    import subprocess
    import sys

    scene = tmp_path / "s.yaml"
    scene.write_text("version: 1\nname: s\narm: {links: [1, 1, 1]}\ngoals: [[1, 1, 1], [0.5, -1, 1]]\n")
    program = (
        "import sys\n"
        "from armanim import load_scene, scene_to_problem, solve_trajectory\n"
        "solution = solve_trajectory(scene_to_problem(load_scene(sys.argv[1]).model))\n"
        "print(solution.reached, len(solution.goals))\n"
    )
    env = {**os.environ, "NUMBA_DISABLE_JIT": "1"}
    proc = subprocess.run(
        [sys.executable, "-c", program, str(scene)], capture_output=True, text=True, timeout=900, env=env
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.split() == ["2", "2"]
    assert "NUMBA_DISABLE_JIT is ignored" in proc.stderr
