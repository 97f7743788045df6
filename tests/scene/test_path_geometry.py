"""Path goals' geometry (issue 39): each scene form, converted, against closed forms; the
written text against the font file read here on its own; the nearest point against dense
sampling."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armanim.motion.toolpath import Piece, ToolPath
from armanim.scene.convert import tool_path
from armanim.scene.models import PathModel

FONT = Path(__file__).resolve().parents[2] / "src" / "armanim" / "scene" / "fonts" / "futural.json"

coordinate = st.floats(-2.0, 2.0, allow_nan=False)
point = st.tuples(coordinate, coordinate, coordinate).map(list)


def far_apart(a, b, least=1e-3) -> bool:
    return math.dist(a, b) > least


@settings(max_examples=60, deadline=None)
@given(point, point)
def test_a_line_has_its_length_and_midpoint(p0, p1):
    if not far_apart(p0, p1):
        return
    path = tool_path(PathModel(line=[p0, p1]))
    assert path.length == pytest.approx(math.dist(p0, p1), rel=1e-12)
    middle = path.points(np.array([path.length / 2]))[0]
    assert np.allclose(middle, (np.array(p0) + p1) / 2, atol=1e-12)
    assert np.array_equal(path.start, p0) and np.allclose(path.end, p1, atol=1e-12)
    assert path.inked(np.array([0.0, path.length])).all()


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


@settings(max_examples=60, deadline=None)
@given(point, point, st.floats(-360, 360).filter(lambda a: abs(a) > 0.5), point)
def test_an_arc_has_its_length_end_and_plane(center, start, angle, normal):
    offset = np.subtract(start, center)
    if np.linalg.norm(normal) < 0.1 or np.linalg.norm(np.cross(unit(normal), offset)) < 0.05:
        return
    path = tool_path(PathModel(arc={"center": center, "start": start, "angle": angle, "normal": normal}))
    n = unit(normal)
    in_plane = offset - (offset @ n) * n  # the start is projected into the plane through the centre
    r = np.linalg.norm(in_plane)
    assert len(path.pieces) == 1 and path.length == pytest.approx(r * math.radians(abs(angle)), rel=1e-12)
    # Rodrigues: the start's offset turned by the angle (radians, right-hand rule) about the normal
    a = math.radians(angle)
    turned = in_plane * math.cos(a) + np.cross(n, in_plane) * math.sin(a) + n * (n @ in_plane) * (1 - math.cos(a))
    assert np.allclose(path.end, np.asarray(center) + turned, atol=1e-9 * max(1.0, r))
    # points at equal arc lengths: on the circle, in its plane, at equal angles, turning the angle's way
    ks = np.linspace(0.0, path.length, 9)
    pts = path.points(ks) - center
    assert np.allclose(np.linalg.norm(pts, axis=1), r, atol=1e-9)
    assert np.allclose(pts @ n, 0.0, atol=1e-9)
    steps = [math.atan2(np.cross(u, v) @ n, u @ v) for u, v in zip(pts[:-1], pts[1:])]
    assert np.allclose(steps, a / 8, atol=1e-9)


def test_an_arc_of_a_full_turn_ends_where_it_starts():
    path = tool_path(PathModel(arc={"center": [0, 0, 0], "start": [0.5, 0, 0], "angle": -360, "normal": [0, 0, 1]}))
    assert path.length == pytest.approx(math.pi)
    assert np.allclose(path.end, [0.5, 0, 0], atol=1e-12)
    quarter = path.points(np.array([math.pi / 4]))[0]
    assert np.allclose(quarter, [0, -0.5, 0], atol=1e-12)  # clockwise about +z: toward -y first


def test_a_polyline_keeps_its_corners_and_drops_repeated_points():
    vertices = [[0, 0, 0], [1, 0, 0], [1, 0, 0], [1, 2, 0], [1, 2, 3]]
    path = tool_path(PathModel(polyline=vertices))
    assert len(path.pieces) == 3 and path.length == pytest.approx(6.0)
    s = path.samples(0.7)
    assert np.all(np.diff(s) <= 0.7 + 1e-12) and np.all(np.diff(s) > 0)
    sampled = path.points(s)
    for corner in ([0, 0, 0], [1, 0, 0], [1, 2, 0], [1, 2, 3]):
        assert np.min(np.linalg.norm(sampled - corner, axis=1)) < 1e-12


@st.composite
def tool_paths(draw) -> ToolPath:
    """1-4 pieces end to end, lines and arcs, some without ink."""
    at = np.array(draw(point), dtype=float)
    pieces = []
    for _ in range(draw(st.integers(1, 4))):
        if draw(st.booleans()):
            end = at + draw(st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda d: np.linalg.norm(d) > 0.05))
            piece = Piece.line(at, end, ink=draw(st.booleans()))
        else:
            normal = np.array(draw(st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda d: np.linalg.norm(d) > 0.3)))
            side = np.cross(unit(normal), draw(st.sampled_from([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])))
            if np.linalg.norm(side) < 0.3:
                side = np.cross(unit(normal), [1.0, 1.0, 1.0])
            center = at - draw(st.floats(0.1, 1.0)) * unit(side)
            piece = Piece.arc(center, at, draw(st.floats(0.2, 6.2)) * draw(st.sampled_from([1, -1])), normal)
        pieces.append(piece)
        at = piece.end
    return ToolPath(tuple(pieces))


@settings(max_examples=60, deadline=None)
@given(tool_paths(), st.lists(st.tuples(*[st.floats(-4, 4)] * 3), min_size=1, max_size=6))
def test_nearest_point_agrees_with_dense_sampling(path, queries):
    queries = np.array(queries, dtype=float)
    h = 1e-3
    s_dense = np.linspace(0.0, path.length, max(2, math.ceil(path.length / h) + 1))
    dense = path.points(s_dense)
    spacing = path.length / (len(s_dense) - 1)
    s, d = path.nearest(queries)
    brute = np.min(np.linalg.norm(queries[:, None, :] - dense[None], axis=2), axis=1)
    assert np.all(d <= brute + 1e-9)  # nothing sampled is nearer than the point found
    assert np.all(
        brute <= d + spacing / 2 + 1e-9
    )  # and the point found is on the path (a sample lies within spacing / 2)
    assert np.allclose(np.linalg.norm(path.points(s) - queries, axis=1), d, atol=1e-9)
    # within a window, the nearest point of the window
    lo, hi = np.full(len(queries), path.length * 0.25), np.full(len(queries), path.length * 0.6)
    sw, dw = path.nearest(queries, lo, hi)
    inside = (s_dense >= lo[0]) & (s_dense <= hi[0])
    brute_w = np.min(np.linalg.norm(queries[:, None, :] - dense[inside][None], axis=2), axis=1)
    assert np.all((sw >= lo - 1e-12) & (sw <= hi + 1e-12))
    assert np.all(dw <= brute_w + 1e-9) and np.all(brute_w <= dw + spacing + 1e-9)


@settings(max_examples=60, deadline=None)
@given(tool_paths(), st.lists(st.floats(0, 1), min_size=1, max_size=8))
def test_a_reversed_path_runs_the_same_points_from_the_end(path, fractions):
    """The path walked backward (a line followed from its end, issue 54): its point at ``s`` is the
    path's at ``length - s``, its length and ink the same, and reversed twice it is the path again."""
    back = path.reversed()
    s = np.array(fractions) * path.length
    assert back.length == pytest.approx(path.length, rel=1e-12, abs=1e-12)
    np.testing.assert_allclose(back.points(path.length - s), path.points(s), atol=1e-9)
    np.testing.assert_array_equal(back.start, path.end)
    np.testing.assert_array_equal(back.end, path.start)
    np.testing.assert_allclose(back.reversed().points(s), path.points(s), atol=1e-9)
    inner = np.clip(s, 1e-6 * path.length, (1 - 1e-6) * path.length)  # away from a corner, where ink may change
    inner = inner[np.all(np.abs(inner[:, None] - path.corners[None]) > 1e-6, axis=1)]
    np.testing.assert_array_equal(back.inked(path.length - inner), path.inked(inner))


# ---- text ---------------------------------------------------------------------------------

RIGHT, UP = np.array([0.0, -1.0, 0.0]), np.array([0.0, 0.0, 1.0])
FRONT = np.array([-1.0, 0.0, 0.0])  # right x up: toward the writer
ORIGIN = np.array([0.556, 0.25, 0.45])


def font_file() -> dict:
    return json.loads(FONT.read_text(encoding="utf-8"))


def written(string: str, height: float = 0.06, lift: float | None = None) -> ToolPath:
    text = {"string": string, "origin": ORIGIN.tolist(), "height": height, "right": RIGHT.tolist(), "up": UP.tolist()}
    if lift is not None:
        text["lift"] = lift
    return tool_path(PathModel(text=text))


def inked_runs(path: ToolPath) -> list[list[Piece]]:
    """The path's pieces grouped into maximal runs that leave ink."""
    runs, current = [], []
    for piece in path.pieces:
        if piece.ink:
            current.append(piece)
        elif current:
            runs.append(current)
            current = []
    return runs + ([current] if current else [])


def on_board(points: np.ndarray) -> np.ndarray:
    """(k, 2): points as (along right, along up) from the origin."""
    return np.stack([(points - ORIGIN) @ RIGHT, (points - ORIGIN) @ UP], axis=1)


def test_the_font_file_has_printable_ascii_and_its_notice():
    font = font_file()
    assert sorted(font["glyphs"]) == [chr(c) for c in range(32, 127)]
    assert font["cap_height"] == 21
    assert any("A. V. Hershey" in line for line in font["notice"])
    readme = (FONT.parent / "README.md").read_text(encoding="utf-8")
    assert "James Hurt" in readme and "USE RESTRICTION" in readme


def test_armanim_written_stroke_by_stroke_within_its_box():
    height = 0.06
    path = written("armanim", height)
    font = font_file()
    glyphs = [font["glyphs"][c] for c in "armanim"]
    assert (
        len(inked_runs(path)) == sum(len(g["strokes"]) for g in glyphs) == 16
    )  # a 2, r 2, m 3, a 2, n 2, i 2 (its dot), m 3
    # the box of the inked points, from the font file's own numbers
    scale, x, xs, ys = height / font["cap_height"], 0, [], []
    for g in glyphs:
        for stroke in g["strokes"]:
            xs += [x + v for v in stroke[0::2]]
            ys += stroke[1::2]
        x += g["advance"]
    inked = on_board(np.concatenate([p.points(np.linspace(0, p.length, 5)) for p in path.pieces if p.ink]))
    assert np.allclose(inked.min(axis=0), [min(xs) * scale, min(ys) * scale], atol=1e-12)
    assert np.allclose(inked.max(axis=0), [max(xs) * scale, max(ys) * scale], atol=1e-12)
    assert (
        max(ys) == 22 and min(ys) == 0
    )  # the i's dot tops a capital (21) by a unit; no descender: the baseline is the bottom
    assert inked[:, 1].max() == pytest.approx(height * 22 / 21)


def test_a_capital_i_is_a_stroke_of_the_height_and_three_stand_left_to_right():
    path = written("III", 0.21)
    runs = inked_runs(path)
    assert len(runs) == 3
    for k, run in enumerate(runs):
        (piece,) = run
        assert piece.length == pytest.approx(0.21)
        a, b = on_board(np.array([piece.start, piece.end]))
        assert a[0] == pytest.approx(b[0]) and a[1] == pytest.approx(0.21) and b[1] == pytest.approx(0.0, abs=1e-12)
        assert a[0] == pytest.approx((4 + 8 * k) * 0.01)  # the I's stem at 4 of its 8 units of advance


def test_characters_are_laid_left_to_right():
    string = "armanim"
    font = font_file()
    path = written(string)
    runs = inked_runs(path)
    counts = [len(font["glyphs"][c]["strokes"]) for c in string]
    centres, k = [], 0
    for count in counts:
        pts = np.concatenate([p.points(np.linspace(0, p.length, 5)) for run in runs[k : k + count] for p in run])
        centres.append(on_board(pts)[:, 0].mean())
        k += count
    assert np.all(np.diff(centres) > 0)


def test_ink_lies_on_the_board_and_the_pen_lifts_toward_its_front():
    path = written("armanim", 0.06, lift=0.02)
    for piece in path.pieces:
        pts = piece.points(np.linspace(0, piece.length, 7))
        depth = (pts - ORIGIN) @ FRONT
        if piece.ink:
            assert np.allclose(depth, 0.0, atol=1e-12)
        else:
            assert np.all(depth >= -1e-12) and np.all(depth <= 0.02 + 1e-12)
    lifted = [p for p in path.pieces if not p.ink]
    assert len(lifted) == 3 * (len(inked_runs(path)) - 1)  # up, across, down between strokes
    tops = [(p.end - ORIGIN) @ FRONT for p in lifted[0::3]]
    assert np.allclose(tops, 0.02)


def test_the_default_lift_is_three_tenths_of_the_height():
    path = written("ii", 0.1)
    assert max((p.end - ORIGIN) @ FRONT for p in path.pieces) == pytest.approx(0.03)


def test_a_text_path_runs_end_to_end_from_the_first_stroke_to_the_last():
    font = font_file()
    path = written("Hi!", 0.21)
    assert all(np.array_equal(a.end, b.start) for a, b in zip(path.pieces[:-1], path.pieces[1:]))
    first = font["glyphs"]["H"]["strokes"][0][:2]
    last = font["glyphs"]["!"]["strokes"][-1][-2:]
    advance = font["glyphs"]["H"]["advance"] + font["glyphs"]["i"]["advance"]
    assert np.allclose(on_board(path.start[None])[0], np.array(first) * 0.01, atol=1e-12)
    assert np.allclose(on_board(path.end[None])[0], (np.array(last) + [advance, 0]) * 0.01, atol=1e-12)
    assert path.pieces[0].ink and path.pieces[-1].ink


def test_spaces_only_advance():
    one, two = written("i i"), written("i  i")
    shift = font_file()["glyphs"][" "]["advance"] * 0.06 / 21
    assert len(one.pieces) == len(two.pieces)
    assert np.allclose(two.end - one.end, shift * RIGHT, atol=1e-12)
