#!/usr/bin/env python3
"""Writes the runtime tables of docs/performance.md and the plot docs/performance-cycle.svg from
the results of `cargo bench --bench runtime`.

Usage (from the repository root, after the benchmarks ran):

    python3 tools/bench_report.py [--criterion target/criterion] [--doc docs/performance.md]
                                  [--svg docs/performance-cycle.svg]

It reads criterion's `<group>/<function>/<parameter>/new/estimates.json` (the headline estimate:
the slope of linear sampling, or the mean of flat sampling, with its 95 % confidence interval)
and the benchmark's own `allocations.json`, and replaces the text between the generated-section
markers of the document. Standard library only; the output depends on the inputs only.
"""

import argparse
import json
import math
import sys
from pathlib import Path

BEGIN = "<!-- BEGIN GENERATED: runtime tables (python3 tools/bench_report.py) -->"
END = "<!-- END GENERATED: runtime tables -->"

SCENES = [1, 10, 100, 1_000, 10_000]
BATCHES = [1, 100, 10_000]
PHASE_SCENES = [1, 10, 1_000, 10_000]
PHASES = [
    ("update", "owners' updates"),
    ("query", "merged-decision queries"),
    ("outputs", "status and factor lists"),
]
LIBRARY, BASELINE, PER_MODULE = "library", "baseline", "baseline-per-module"


def estimate(criterion, group, function, parameter):
    """(point, lower, upper) in nanoseconds per iteration, or None if the benchmark did not run."""
    path = Path(criterion, group, function, str(parameter), "new", "estimates.json")
    if not path.is_file():
        return None
    data = json.loads(path.read_text())
    chosen = data.get("slope") or data["mean"]
    interval = chosen["confidence_interval"]
    return chosen["point_estimate"], interval["lower_bound"], interval["upper_bound"]


def duration(ns):
    """A duration with three significant digits and a fitting unit."""
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def ratio(slow, fast):
    if slow is None or fast is None:
        return "—"
    return f"{slow[0] / fast[0]:.3g}×"


def cell(value):
    return "—" if value is None else duration(value[0])


def with_interval(value):
    if value is None:
        return "—"
    point, lower, upper = value
    return f"{duration(point)} ({duration(lower)} – {duration(upper)})"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---:" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def count(n):
    return f"{n:,}".replace(",", " ")


def cycle_section(criterion):
    rows, results = [], {}
    for n in SCENES:
        lib = estimate(criterion, "cycle", LIBRARY, n)
        base = estimate(criterion, "cycle", BASELINE, n)
        per = estimate(criterion, "cycle", PER_MODULE, n)
        results[n] = (lib, base, per)
        per_scene = lambda v: "—" if v is None else duration(v[0] / n)
        rows.append([
            count(n),
            with_interval(lib),
            per_scene(lib),
            with_interval(base),
            per_scene(base),
            ratio(base, lib),
            cell(per),
            ratio(per, lib),
        ])
    header = [
        "N scenes",
        "library, per cycle (95 % CI)",
        "library, per scene",
        "baseline, per cycle (95 % CI)",
        "baseline, per scene",
        "baseline ÷ library",
        "per-module baseline, per cycle",
        "per-module ÷ library",
    ]
    return table(header, rows), results


def pair_section(criterion, group, parameters, name, unit_name):
    rows = []
    for p in parameters:
        lib = estimate(criterion, group, LIBRARY, p)
        base = estimate(criterion, group, BASELINE, p)
        per_unit = "—" if lib is None or unit_name is None else duration(lib[0] / p)
        row = [count(p), with_interval(lib), with_interval(base), ratio(base, lib)]
        if unit_name is not None:
            row.insert(2, per_unit)
        rows.append(row)
    header = [name, "library (95 % CI)", "baseline (95 % CI)", "baseline ÷ library"]
    if unit_name is not None:
        header.insert(2, f"library, per {unit_name}")
    return table(header, rows)


def ratio_range(criterion, group, parameters, name):
    """One sentence with the smallest and largest baseline ÷ library ratio of a group, so that
    prose can point to it instead of copying numbers that the next run changes."""
    pairs = [
        (estimate(criterion, group, BASELINE, p), estimate(criterion, group, LIBRARY, p))
        for p in parameters
    ]
    ratios = sorted(
        (base[0] / lib[0], ratio(base, lib)) for base, lib in pairs if base and lib
    )
    if not ratios:
        return "No ratio: the benchmarks did not run."
    return (
        f"Baseline ÷ library over {name} = {count(parameters[0])} … {count(parameters[-1])}: "
        f"{ratios[0][1]} to {ratios[-1][1]}."
    )


def phase_section(criterion):
    """The cycle's three parts timed one by one: per scene, library against baseline."""
    rows = []
    for n in PHASE_SCENES:
        for part, what in PHASES:
            # Criterion writes a benchmark named `part/side` to the directory `part_side`.
            lib = estimate(criterion, "phase", f"{part}_{LIBRARY}", n)
            base = estimate(criterion, "phase", f"{part}_{BASELINE}", n)
            per_scene = lambda v: "—" if v is None else duration(v[0] / n)
            rows.append([count(n), what, per_scene(lib), per_scene(base), ratio(base, lib)])
    header = ["N scenes", "part of the cycle", "library, per scene", "baseline, per scene",
              "baseline ÷ library"]
    return table(header, rows)


def allocation_section(criterion):
    path = Path(criterion, "allocations.json")
    if not path.is_file():
        return "No allocation counts: `allocations.json` is missing.", None
    data = json.loads(path.read_text())
    rows = [
        [
            count(r["scenes"]),
            str(r["library"]),
            str(r["library_bytes"]),
            str(r["baseline"]),
            str(r["baseline_bytes"]),
        ]
        for r in data["rows"]
    ]
    header = [
        "N scenes",
        "library, allocations per cycle",
        "library, bytes per cycle",
        "baseline, allocations per cycle",
        "baseline, bytes per cycle",
    ]
    note = (
        f"Counted over {data['counted_cycles']} steady-state cycles after 3 warm-up cycles; "
        "allocations include reallocations."
    )
    return table(header, rows) + "\n\n" + note, data["rows"]


def targets_section(cycles, allocations):
    lines = []
    per_scene = {
        n: lib[0] / n for n, (lib, _, _) in cycles.items() if lib is not None and n >= 10
    }
    if per_scene:
        spread = max(per_scene.values()) / min(per_scene.values())
        verdict = "met" if spread <= 2 else "**missed**"
        lines.append(
            f"- Cost per scene roughly constant from N = 10 to 10 000 (within 2×): {verdict}; "
            f"the largest is {spread:.2g}× the smallest "
            f"({duration(min(per_scene.values()))} to {duration(max(per_scene.values()))})."
        )
    lib, base, per = cycles.get(1_000, (None, None, None))
    if lib is not None and base is not None:
        speedup = base[0] / lib[0]
        verdict = "met" if speedup >= 10 else "**missed**"
        extra = "" if per is None else f"; against the per-module baseline {per[0] / lib[0]:.2g}×"
        lines.append(
            f"- At N = 1 000 at least 10× faster than the linear baseline: {verdict} "
            f"({speedup:.2g}×{extra})."
        )
    small = {
        n: base[0] / lib[0]
        for n, (lib, base, _) in cycles.items()
        if n in (1, 10) and lib is not None and base is not None
    }
    # Judged only when both sizes were measured: the line names both.
    if len(small) == 2:
        worst = min(small.values())
        verdict = "met" if worst >= 1 else "**missed**"
        ratios = ", ".join(f"{ratio:.3g}× at N = {n}" for n, ratio in sorted(small.items()))
        lines.append(
            f"- At N = 1 and 10 no slower than the linear baseline: {verdict} ({ratios})."
        )
    if allocations is not None:
        worst = max(r["library"] for r in allocations)
        verdict = "met" if worst == 0 else "**missed**"
        lines.append(
            f"- Zero allocations per steady-state cycle: {verdict} "
            f"(at most {worst} per cycle over N = 1 … 10 000)."
        )
    return "\n".join(lines)


def generated(criterion):
    cycle_table, cycles = cycle_section(criterion)
    alloc_table, allocations = allocation_section(criterion)
    parts = [
        BEGIN,
        "",
        "### Targets",
        "",
        targets_section(cycles, allocations),
        "",
        "### Planning cycle (`cycle/N`)",
        "",
        cycle_table,
        "",
        "![Cycle cost against N, log-log](performance-cycle.svg)",
        "",
        "### The cycle part by part (`phase/PART/N`)",
        "",
        phase_section(criterion),
        "",
        "### Allocations per steady-state cycle",
        "",
        alloc_table,
        "",
        "### `set_commands` batch of K commands, 10 000 live scenes (`commands/K`)",
        "",
        pair_section(criterion, "commands", BATCHES, "K commands", "command"),
        "",
        ratio_range(criterion, "commands", BATCHES, "K"),
        "",
        "### Policy change of a module with N scenes (`policy/N`)",
        "",
        pair_section(criterion, "policy", SCENES, "N scenes", None),
        "",
        "### One registration and one removal, N live scenes (`churn/N`)",
        "",
        pair_section(criterion, "churn", SCENES, "N scenes", None),
        "",
        END,
    ]
    return "\n".join(parts)


def svg_plot(cycles):
    """A log-log plot of the cost of one cycle against N, as an SVG document."""
    width, height = 720, 460
    left, right, top, bottom = 90, 200, 50, 60
    plot_w, plot_h = width - left - right, height - top - bottom
    series = [
        (LIBRARY, "library", "#1f77b4", ""),
        (BASELINE, "linear baseline", "#d62728", ""),
        (PER_MODULE, "per-module baseline", "#ff7f0e", "6 4"),
    ]
    points = {}
    for index, (key, _, _, _) in enumerate(series):
        points[key] = [
            (n, cycles[n][index][0]) for n in SCENES if cycles.get(n) and cycles[n][index]
        ]
    values = [ns for pts in points.values() for _, ns in pts]
    if not values:
        return None
    y_lo = 10 ** math.floor(math.log10(min(values)))
    y_hi = 10 ** math.ceil(math.log10(max(values)))
    x_lo, x_hi = 1, 10_000

    def x(n):
        return left + plot_w * (math.log10(n) - math.log10(x_lo)) / (
            math.log10(x_hi) - math.log10(x_lo)
        )

    def y(ns):
        return top + plot_h * (1 - (math.log10(ns) - math.log10(y_lo)) / (
            math.log10(y_hi) - math.log10(y_lo)
        ))

    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">',
        f'<rect width="{width}" height="{height}" fill="white"/>',
        f'<text x="{left + plot_w / 2:.1f}" y="28" text-anchor="middle" font-size="15">'
        "Cost of one planning cycle against the number of live scenes</text>",
    ]
    decade = y_lo
    while decade <= y_hi * 1.0001:
        py = y(decade)
        out.append(
            f'<line x1="{left}" y1="{py:.1f}" x2="{left + plot_w}" y2="{py:.1f}" '
            'stroke="#dddddd"/>'
        )
        out.append(
            f'<text x="{left - 8}" y="{py + 4:.1f}" text-anchor="end">{duration(decade)}</text>'
        )
        decade *= 10
    for n in SCENES:
        px = x(n)
        out.append(
            f'<line x1="{px:.1f}" y1="{top}" x2="{px:.1f}" y2="{top + plot_h}" stroke="#dddddd"/>'
        )
        out.append(
            f'<text x="{px:.1f}" y="{top + plot_h + 18}" text-anchor="middle">{count(n)}</text>'
        )
    out.append(
        f'<rect x="{left}" y="{top}" width="{plot_w}" height="{plot_h}" fill="none" '
        'stroke="black"/>'
    )
    out.append(
        f'<text x="{left + plot_w / 2:.1f}" y="{height - 18}" text-anchor="middle">'
        "N live scenes (log scale)</text>"
    )
    out.append(
        f'<text transform="translate(22 {top + plot_h / 2:.1f}) rotate(-90)" '
        'text-anchor="middle">time per cycle (log scale)</text>'
    )
    for index, (key, label, colour, dash) in enumerate(series):
        pts = points[key]
        if not pts:
            continue
        dashing = f' stroke-dasharray="{dash}"' if dash else ""
        path = " ".join(f"{x(n):.1f},{y(ns):.1f}" for n, ns in pts)
        out.append(
            f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"{dashing}/>'
        )
        for n, ns in pts:
            out.append(
                f'<circle cx="{x(n):.1f}" cy="{y(ns):.1f}" r="3.5" fill="{colour}">'
                f"<title>{label}, N = {count(n)}: {duration(ns)}</title></circle>"
            )
        ly = top + 20 + 22 * index
        lx = left + plot_w + 16
        out.append(
            f'<line x1="{lx}" y1="{ly}" x2="{lx + 28}" y2="{ly}" stroke="{colour}" '
            f'stroke-width="2"{dashing}/>'
        )
        out.append(f'<text x="{lx + 36}" y="{ly + 4}">{label}</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--criterion", default="target/criterion")
    parser.add_argument("--doc", default="docs/performance.md")
    parser.add_argument("--svg", default="docs/performance-cycle.svg")
    args = parser.parse_args()

    if not Path(args.criterion).is_dir():
        sys.exit(f"{args.criterion} does not exist: run `cargo bench --bench runtime` first")
    doc = Path(args.doc)
    text = doc.read_text()
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        sys.exit(f"{doc} needs exactly one pair of generated-section markers:\n{BEGIN}\n{END}")
    section = generated(args.criterion)
    before, rest = text.split(BEGIN)
    _, after = rest.split(END)
    doc.write_text(before + section + after)
    print(f"wrote {doc}")

    _, cycles = cycle_section(args.criterion)
    svg = svg_plot(cycles)
    if svg is None:
        sys.exit("no cycle results: the plot was not written")
    Path(args.svg).write_text(svg)
    print(f"wrote {args.svg}")


if __name__ == "__main__":
    main()
