"""The motion benchmark's report: per method and planner, goals reached, frames near a
surface, times, misses by reason, broken invariants.
"""

from __future__ import annotations

from collections import Counter, defaultdict

import numpy as np
from oracles.geometry import DEFAULT_CLEARANCE

from armanim.scene.models import SolverModel
from runners.motion import planner_field_exists, twin_rows


def percent(part: float, whole: float) -> str:
    """``part/whole (x %)``, or ``-`` when whole is 0."""
    return f"{part}/{whole} ({100.0 * part / whole:.0f} %)" if whole else "-"


def summary_rows(results: list, methods: list, planners: list) -> list[list[str]]:
    """One table row per method and planner setting."""
    rows = []
    for method in methods:
        for planner in planners:
            runs = [(r, run) for r in results for run in r.runs if run.method == method and run.planner == planner]
            feasible = reached = bogus = frames = near = limit = broken = 0
            seconds = 0.0
            planned_times, any_planned_field = [], False
            for r, run in runs:
                for verdict, ok, was_planned, secs in zip(r.verdicts, run.reached, run.planned, run.goal_seconds):
                    feasible += verdict.feasible
                    reached += verdict.feasible and ok
                    bogus += (not verdict.feasible) and ok
                    any_planned_field |= was_planned is not None
                    if was_planned:
                        planned_times.append(secs)
                frames += run.frames
                near += run.near_surface
                limit += run.at_limit
                seconds += run.seconds
                broken += len(run.breaks)
            per_planned = (
                f"{np.nanmean(planned_times):.2f} s ({len(planned_times)})"
                if planned_times
                else ("0 planned" if any_planned_field else "n/a")
            )
            rows.append(
                [
                    method,
                    planner,
                    percent(reached, feasible),
                    str(bogus),
                    f"{100.0 * near / max(frames, 1):.1f} %",
                    f"{100.0 * limit / max(frames, 1):.1f} %",
                    f"{1000.0 * seconds / max(frames, 1):.2f}",
                    per_planned,
                    str(broken),
                ]
            )
    return rows


HEADER = [
    "method",
    "planner",
    "feasible reached",
    "reached infeasible",
    "frames <1e-3 of surface",
    "frames on a limit",
    "ms/frame",
    "s/planned goal",
    "invariants broken",
]


def print_table(header: list, rows: list) -> None:
    """A markdown table, columns padded."""
    widths = [max(len(str(x)) for x in col) for col in zip(header, *rows)]

    def line(cells):
        return "| " + " | ".join(str(c).ljust(w) for c, w in zip(cells, widths)) + " |"

    print(line(header))
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for row in rows:
        print(line(row))


def miss_reasons(results: list) -> dict:
    """Counter of miss reasons on feasible goals, per (method, planner); key ``easy`` counts the
    misses with a clear straight joint-space line to an oracle pose."""
    counts = defaultdict(Counter)
    for r in results:
        for run in r.runs:
            for verdict, ok, reason, easy in zip(r.verdicts, run.reached, run.reasons, run.easy):
                if verdict.feasible and not ok:
                    counts[(run.method, run.planner)][reason] += 1
                    counts[(run.method, run.planner)]["(easy)"] += bool(easy)
    return counts


def kind_rows(results: list, planners: list) -> list[list[str]]:
    """Feasible goals reached per arm kind and planner setting, all methods together."""
    rows = []
    for kind in sorted({r.kind for r in results}):
        cells = [kind, str(sum(r.kind == kind for r in results))]
        for planner in planners:
            feasible = reached = 0
            for r in (r for r in results if r.kind == kind):
                for run in (run for run in r.runs if run.planner == planner):
                    feasible += sum(v.feasible for v in r.verdicts)
                    reached += sum(v.feasible and ok for v, ok in zip(r.verdicts, run.reached))
            cells.append(percent(reached, feasible))
        rows.append(cells)
    return rows


def print_report(results: list, methods: list, planners: list, list_misses: bool) -> int:
    """Print every table; return the number of broken invariants."""
    verdicts = [v for r in results for v in r.verdicts]
    why = Counter(v.why for v in verdicts)
    print(
        f"\n{len(results)} scenes, {len(verdicts)} goals: oracle says {why['feasible']} feasible, "
        f"{why['out_of_reach']} out of reach, {why['no_free_pose']} without a free pose inside the limits; "
        f"generator poses the oracle failed to match: {sum(r.witness_missed for r in results)}; "
        f"oracle time {sum(r.oracle_seconds for r in results):.1f} s"
    )
    print(
        f"armanim: planner field {'present' if planner_field_exists() else 'absent (only the current behaviour, labelled off)'}, "
        f"clearance field {'present' if 'clearance' in SolverModel.model_fields else f'absent (oracle clearance {DEFAULT_CLEARANCE})'}\n"
    )
    print_table(HEADER, summary_rows(results, methods, planners))
    print(
        "\nMisses of feasible goals by reason (easy: the straight joint-space line from the arm's last pose to the oracle's pose is clear):"
    )
    for (method, planner), counts in sorted(miss_reasons(results).items()):
        easy = counts.pop("(easy)")
        print(
            f"  {method:8s} {planner:4s} "
            + ", ".join(f"{reason} {n}" for reason, n in counts.most_common())
            + f"; easy {easy}"
        )
    if any(r.twin_runs for r in results):
        print(
            f"\nTime per frame against the same scenes with spheres only (each box and capsule replaced by the largest "
            f"sphere inside it, the floor dropped; planner {planners[0]}; each solve the best of its --timing-rounds, "
            f"taken in turn with its twin's):"
        )
        print_table(
            [
                "method",
                "ms/frame shapes",
                "ms/frame spheres twin",
                "ratio",
                "CPU ms/frame shapes",
                "CPU ms/frame twin",
                "CPU ratio",
            ],
            twin_rows(results, methods, planners[0]),
        )
        timed = np.array([r.distance_seconds for r in results if r.distance_seconds])
        if len(timed):
            single, batched = timed[:, 0].sum() / timed[:, 1].sum(), timed[:, 2].sum() / timed[:, 3].sum()
            print(
                f"armanim's clearances per pose (FK included), shapes / spheres twin: one pose at a time "
                f"{1e6 * timed[:, 0].mean():.0f} / {1e6 * timed[:, 1].mean():.0f} us = {single:.2f}x; "
                f"the smallest of 2000 at once {1e6 * timed[:, 2].mean():.1f} / {1e6 * timed[:, 3].mean():.1f} us = {batched:.2f}x"
            )
    print("\nFeasible goals reached per arm kind (all methods):")
    print_table(["arm kind", "scenes"] + [f"planner {p}" for p in planners], kind_rows(results, planners))
    broken = 0
    for r in results:
        for run in r.runs:
            for message in run.breaks:
                broken += 1
                print(f"INVARIANT scene {r.index} {run.method} {run.planner}: {message}")
    flagged = [
        (r, run, k)
        for r in results
        for run in r.runs
        for k, (v, ok) in enumerate(zip(r.verdicts, run.reached))
        if ok and not v.feasible
    ]
    for r, run, k in flagged:
        print(
            f"ORACLE? scene {r.index} goal {k} reached by {run.method}/{run.planner} but labelled {r.verdicts[k].why}"
        )
    if list_misses:
        print("\nFeasible goals missed (scene, goal, arm kind, method, planner, reason; easy: straight line clear):")
        for r in results:
            for run in r.runs:
                for k, (v, ok, reason, easy) in enumerate(zip(r.verdicts, run.reached, run.reasons, run.easy)):
                    if v.feasible and not ok:
                        print(
                            f"  scene {r.index:3d} goal {k} {r.kind:7s} {run.method:8s} {run.planner:4s} {reason}{' (easy)' if easy else ''}"
                        )
    return broken
