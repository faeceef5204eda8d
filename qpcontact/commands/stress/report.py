"""The stress suite's report: the census per method and family (Markdown) and the
heat map."""

from __future__ import annotations

import csv
import math
import os
import statistics
from pathlib import Path

import numpy as np

from .cases import CATEGORIES, FAMILIES

__all__ = ["summarize", "write_markdown", "plot_heatmap"]


def _read(path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _wall(r) -> float:
    """The solve's whole wall time (older CSVs have only the method's)."""
    for key in ("wall", "seconds"):
        try:
            s = float(r.get(key, ""))
        except (TypeError, ValueError):
            continue
        if math.isfinite(s):
            return s
    return math.nan


def _over(r) -> int:
    try:
        return int(float(r.get("over_limit") or 0))
    except (TypeError, ValueError):
        return 0


def summarize(rows: list[dict]) -> dict:
    """{(method, family): {category: count, ..., "median_s", "max_s": seconds
    (whole wall time), "over": solves past their time share}}."""
    table: dict = {}
    for r in rows:
        cell = table.setdefault((r["method"], r["family"]),
                                {c: 0 for c in CATEGORIES} | {"_t": [], "over": 0})
        cell[r["category"]] += 1
        cell["over"] += _over(r)
        s = _wall(r)
        if math.isfinite(s):
            cell["_t"].append(s)
    for cell in table.values():
        t = cell.pop("_t")
        cell["median_s"] = statistics.median(t) if t else math.nan
        cell["max_s"] = max(t) if t else math.nan
    return table


def write_markdown(csv_path, md_path=None) -> tuple[Path, dict]:
    """Per method (rows) and per family: counts by category and median time;
    then per method over all families.  Returns (path, totals)."""
    rows = _read(csv_path)
    table = summarize(rows)
    md = Path(md_path) if md_path else Path(csv_path).with_suffix(".md")
    totals = {c: sum(cell[c] for cell in table.values()) for c in CATEGORIES}
    totals["over"] = sum(cell["over"] for cell in table.values())
    problems = len({(r["family"], r["n"], r["seed"]) for r in rows})
    lines = [
        "# qpcontact stress",
        "",
        f"{len(rows)} solves of {problems} problems; silent wrong: **{totals['silent_wrong']}**, "
        f"hung (time-limited): **{totals['hung']}**; over their time share: **{totals['over']}** "
        "(whole wall time past 1.5 x time_limit, \"auto\" included).",
        "",
        "Categories (judged against each instance's built-in answer, not by qpcontact.certify): "
        "certified · proved (no solution, proof checked) · inaccurate · failed · "
        "**silent wrong** · hung.",
        "",
        "## Per method",
        "",
        "| method | solves | certified | proved | inaccurate | failed | silent wrong | hung | median s "
        "| max s | over limit |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    methods = sorted({m for m, _ in table})
    families = [f for f in FAMILIES if any(f == fam for _, fam in table)]
    for m in methods:
        cells = [table[(m, f)] for f in families if (m, f) in table]
        counts = {c: sum(cell[c] for cell in cells) for c in CATEGORIES}
        times = [t for t in (_wall(r) for r in rows if r["method"] == m) if math.isfinite(t)]
        med = statistics.median(times) if times else math.nan
        top = max(times) if times else math.nan
        over = sum(cell["over"] for cell in cells)
        lines.append(f"| {m} | {sum(counts.values())} | " + " | ".join(
            str(counts[c]) for c in CATEGORIES) + f" | {med:.2g} | {top:.2g} | {over} |")
    lines += ["", "## Per method and family", "",
              "Each cell: certified+proved / solves (silent wrong, hung when nonzero); median and max "
              "seconds of the whole solve, and how many passed their time share.", "",
              "| method | " + " | ".join(families) + " |",
              "|---|" + "---|" * len(families)]
    for m in methods:
        cells = []
        for f in families:
            cell = table.get((m, f))
            if cell is None:
                cells.append("—")
                continue
            total = sum(cell[c] for c in CATEGORIES)
            text = f"{cell['certified'] + cell['proved']}/{total}"
            if cell["silent_wrong"]:
                text += f" **{cell['silent_wrong']} wrong**"
            if cell["hung"]:
                text += f" ({cell['hung']} hung)"
            text += f"; {cell['median_s']:.1g} s (max {cell['max_s']:.1g}"
            text += f", {cell['over']} over)" if cell["over"] else ")"
            cells.append(text)
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    slow = sorted((r for r in rows if _over(r)), key=_wall, reverse=True)
    if slow:
        lines += ["", "## Over their time share", ""]
        lines += [f"- {r['method']} on {r['family']} n={r['n']} seed={r['seed']} "
                  f"({r['accuracy']}): {_wall(r):.3g} s > {float(r.get('limit_s') or 0):.3g} s"
                  for r in slow[:30]]
    wrong = [r for r in rows if r["category"] == "silent_wrong"]
    if wrong:
        lines += ["", "## Silent wrong answers", ""]
        lines += [f"- {r['method']} on {r['family']} n={r['n']} seed={r['seed']} "
                  f"({r['accuracy']}): {r['reason']}" for r in wrong[:50]]
    bugs = [r for r in rows if r["status"] == "bug"]
    if bugs:
        lines += ["", "## Undocumented exceptions (bugs)", ""]
        lines += [f"- {r['method']} on {r['family']} n={r['n']} seed={r['seed']}: {r['reason']}"
                  for r in bugs[:50]]
    tmp = md.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, md)
    return md, totals | {"solves": len(rows), "problems": problems, "bugs": len(bugs)}


def plot_heatmap(csv_path, png_path=None) -> Path:
    """Methods x families, coloured by the certified-or-proved fraction;
    cells with silent wrong answers are outlined and labelled."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = _read(csv_path)
    table = summarize(rows)
    methods = sorted({m for m, _ in table})
    families = [f for f in FAMILIES if any(f == fam for _, fam in table)]
    frac = np.full((len(methods), len(families)), np.nan)
    for i, m in enumerate(methods):
        for j, f in enumerate(families):
            cell = table.get((m, f))
            if cell:
                total = sum(cell[c] for c in CATEGORIES)
                frac[i, j] = (cell["certified"] + cell["proved"]) / total
    fig, ax = plt.subplots(figsize=(1.0 + 0.75 * len(families), 1.2 + 0.38 * len(methods)))
    im = ax.imshow(frac, cmap="viridis", vmin=0, vmax=1, aspect="auto")
    ax.set_xticks(range(len(families)), families, rotation=45, ha="right")
    ax.set_yticks(range(len(methods)), methods)
    for i, m in enumerate(methods):
        for j, f in enumerate(families):
            cell = table.get((m, f))
            if not cell:
                continue
            label = f"{frac[i, j]:.0%}".replace("%", "")
            if cell["silent_wrong"]:
                label += f"\n{cell['silent_wrong']}W"
                ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="red", lw=2))
            ax.text(j, i, label, ha="center", va="center", fontsize=6,
                    color="white" if frac[i, j] < 0.6 else "black")
    fig.colorbar(im, ax=ax, label="certified or proved (fraction)")
    ax.set_title(f"qpcontact stress: {len(rows)} solves (W: silent wrong, must be 0)")
    fig.tight_layout()
    png = Path(png_path) if png_path else Path(csv_path).with_suffix(".png")
    tmp = png.with_name(png.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, png)
    return png
