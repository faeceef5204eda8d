"""Variants of a scene: a key's value edited in the text (so that every variant
is a scene file a person can read), run serially or on Dask, one results
file per variant and a summary table."""

from __future__ import annotations

import re
from pathlib import Path

from .results_files import write_results
from .schema import SceneError, SourceLines, load_scene, parse_scene

__all__ = ["vary_scene", "split_values", "sweep"]


def vary_scene(text: str, key: str, value: str) -> str:
    """The scene text with ``key`` (dotted: ``time.steps_per_period``,
    ``effect.damping.ratio``, ``logs.1.diameter`` for the second [[logs]])
    set to ``value`` (TOML: ``0.05``, ``"bpp"``), edited in place so the
    variant's text is a scene file of its own."""
    parts = key.split(".")
    index = None
    if len(parts) >= 3 and parts[-2].isdigit():
        index = int(parts[-2])
        table, name = tuple(parts[:-2]), parts[-1]
    else:
        table, name = tuple(parts[:-1]), parts[-1]
    lines = text.splitlines()
    where = SourceLines(text)
    no = None
    for ln, t, i, k in where.entries:
        if t == table and k == name and (index is None or i == index):
            no = ln
            break
    if no is not None:
        m = re.match(r"^(\s*[^=]+=\s*)(.*?)(\s+#.*)?$", lines[no - 1])
        lines[no - 1] = m.group(1) + value + (m.group(3) or "")
        return "\n".join(lines) + "\n"
    header = where.line(table, None, index) if table else None
    if table and header is None:
        if index is not None:
            raise SceneError(f"--vary {key}: the scene has no [[{'.'.join(table)}]] number {index}")
        return text.rstrip("\n") + f"\n\n[{'.'.join(table)}]\n{name} = {value}\n"
    insert_at = header if table else 0   # right after the table's header (or at the top)
    lines.insert(insert_at, f"{name} = {value}")
    return "\n".join(lines) + "\n"


def split_values(values: str) -> list[str]:
    """A ``--vary`` list: TOML values separated by commas, where commas
    inside brackets or quotes belong to the value (``[0.01,0.02],[0.02,0.01]``
    is two lists)."""
    out, depth, quote, start = [], 0, None, 0
    for i, ch in enumerate(values):
        if quote:
            quote = None if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
            if depth < 0:
                raise SceneError(f"unbalanced '{ch}' at character {i + 1} of {values!r}")
        elif ch == "," and depth == 0:
            out.append(values[start:i].strip())
            start = i + 1
    if depth or quote:
        raise SceneError(f"unclosed {'quote' if quote else 'bracket'} in {values!r}")
    out.append(values[start:].strip())
    if not all(out):
        raise SceneError(f"an empty value in {values!r}")
    return out


def _run_text(text: str, label: str):
    scene = parse_scene(text, label)
    _, run = scene.schema.build(scene)
    return run()


def sweep(path, variations: dict, out_dir, *, grid: bool = False, workers: int = 0,
          scheduler: str | None = None, progress: bool = True):
    """Run variants of a scene: ``variations`` {key: [values as TOML text]},
    zipped (all lists the same length) or, with ``grid``, every combination.
    Serial, or on Dask (``workers`` local processes or a ``scheduler``
    address) — the same code per variant either way, so the results are the
    same.  Writes one HDF5 file per variant and summary.csv (the varied
    values and the schema's summary of each run); returns the summary rows."""
    import itertools

    from ..core.files import make_folder, write_csv_atomic
    from ..core.progress import ProgressBar

    path = Path(path)
    base = load_scene(path)
    keys = list(variations)
    if not keys:
        raise SceneError("sweep: give at least one --vary KEY=v1,v2,...")
    if grid:
        combos = list(itertools.product(*(variations[k] for k in keys)))
    else:
        sizes = {len(v) for v in variations.values()}
        if len(sizes) != 1:
            raise SceneError("sweep: the --vary lists differ in length "
                             f"({', '.join(f'{k}: {len(v)}' for k, v in variations.items())}); "
                             "give lists of one length, or --grid for every combination")
        combos = list(zip(*(variations[k] for k in keys)))
    texts, labels, scenes = [], [], []
    for n, combo in enumerate(combos):
        text = base.text
        for k, v in zip(keys, combo):
            text = vary_scene(text, k, v)
        # every variant checked before any runs
        scenes.append(parse_scene(text, f"{path} with {dict(zip(keys, combo))}"))
        texts.append(text)
        labels.append(f"{path.stem}-{n:03d}")
    out = make_folder(Path(out_dir))
    if workers or scheduler:
        results = _dask_runs(texts, labels, workers, scheduler)
    else:
        results = (_run_text(t, lb) for t, lb in zip(texts, labels))
    bar = ProgressBar(len(texts), "sweep variants", progress)
    rows = []
    for n, (scene, label, result) in enumerate(zip(scenes, labels, results), 1):
        write_results(scene, result, out / f"{label}.h5", completed=len(result.t) - 1,
                      total=len(result.t) - 1)
        row = {"variant": label, **dict(zip(keys, combos[n - 1]))}
        if scene.schema.summary is not None:
            row.update(scene.schema.summary(result))
        rows.append(row)
        bar.update(n)
    bar.close()
    fields = list(dict.fromkeys(k for r in rows for k in r))
    write_csv_atomic(out / "summary.csv", rows, fields)
    return rows


def _dask_runs(texts, labels, workers, scheduler):
    from ..core.cluster import dask_client

    with dask_client(workers, scheduler) as client:
        futures = [client.submit(_run_text, t, lb, pure=False) for t, lb in zip(texts, labels)]
        for fut in futures:   # in order: files and rows follow the variants
            yield fut.result()
