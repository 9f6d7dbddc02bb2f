"""Scenes (scenes.csv): per scene and structure, steps per second and the stages that ran.
The evidence that unused effects cost nothing: a scene has rows only for the stages it calls
for, and the stages' medians add up to (about) the whole step — the share quoted per scene."""

from collections import defaultdict

from .. import quotes
from ..latex import key_part, name, ref, tabular

SUITE = "scenes"
STEP = "step"


def _stages(ctx):
    for entry in ctx.registry.get("suites", []):
        if entry.get("name") == SUITE:
            return entry.get("stages", []), entry.get("once_stages", ["build"])
    return [], ["build"]


def generate(ctx):
    rows = ctx.rows.find(suite=SUITE, metric="time")
    if not ctx.suite_measured(SUITE, bool(rows)):
        return
    stage_order, once = _stages(ctx)
    cells = defaultdict(lambda: defaultdict(list))  # (scene, n, structure) -> operation -> rows
    for row in rows:
        cells[(row["workload"], row.n, row["structure"])][row["operation"]].append(row)
    body = []
    for (scene, n, structure), by_stage in sorted(cells.items()):
        if STEP not in by_stage:
            continue
        base = f"scenes.{key_part(scene)}.{key_part(structure)}"
        rate = ctx.rows.find(suite=SUITE, workload=scene, n=n, structure=structure,
                             operation=STEP, metric="steps_per_second")
        quotes.plain(ctx.book, base + ".rate", [rate])
        stages = [s for s in by_stage if s not in once and s != STEP]
        stages.sort(key=lambda s: stage_order.index(s) if s in stage_order else len(stage_order))
        quotes.percent(ctx.book, base + ".share",
                       [by_stage[STEP]] + [by_stage[s] for s in stages], "share")
        body.append([name(scene), name(structure), ", ".join(name(s) for s in stages),
                     ref(base + ".rate"), ref(base + ".share")])
    ctx.table("scenes.tex", tabular("llp{0.42\\linewidth}rr",
                                    ["scene", "structure", "stages run", "steps/s",
                                     "stages / step"], body))
