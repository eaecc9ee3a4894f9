"""The check that a report figure's text fits: :func:`layout_problems` lists, one sentence per
problem, a text (title, axis label, tick label, legend text, annotation) whose box leaves the
figure, a data label leaving its axes, two tick labels of one axis that overlap, a legend
covering data (a line, marker, bar, fill or data label of its axes), and a data label crossed by
a line drawn over it (a label drawn above a line on an opaque background is legible and
passes). Boxes are the renderer's window extents in pixels, compared with a tolerance of
:data:`TOL` pixels. :mod:`diffsense.report.style` fits a figure until this list is empty.
"""

from __future__ import annotations

from typing import Iterator, List, Optional, Tuple

import numpy as np

#: tolerance (pixels) of every fit test
TOL = 0.75
_TOL = TOL


def _renderer(fig):
    """Lay ``fig`` out and place every artist as drawing it would (no pixels), then the
    renderer that measures its texts."""
    fig.draw_without_rendering()
    return fig.canvas.get_renderer()


def _visible(t) -> bool:
    return t.get_visible() and bool(t.get_text().strip())


def _short(t) -> str:
    s = " ".join(t.get_text().split())
    return repr(s if len(s) <= 60 else s[:57] + "...")


def drawn_tick_labels(axis) -> List[Tuple[object, bool]]:
    """(label, is_minor) of every tick label ``axis`` draws: visible, not empty, at a tick
    inside the view interval."""
    lo, hi = sorted(axis.get_transform().transform(np.asarray(axis.get_view_interval(), dtype=float)))
    eps = 1e-9 * max(hi - lo, 1e-300)
    out = []
    for minor, locs, ticks in ((False, axis.get_majorticklocs(), axis.get_major_ticks),
                               (True, axis.get_minorticklocs(), axis.get_minor_ticks)):
        locs = np.asarray(locs, dtype=float)
        if locs.size == 0:
            continue
        tk = ticks(len(locs))
        where = axis.get_transform().transform(locs)
        for loc, tick in zip(where, tk):
            if not np.isfinite(loc) or not lo - eps <= loc <= hi + eps:
                continue
            for label in (tick.label1, tick.label2):
                if _visible(label):
                    out.append((label, minor))
    return out


def _texts(fig) -> Iterator[Tuple[str, object, Optional[object]]]:
    """(what, text artist, data axes or None) of every visible text of ``fig``."""
    from matplotlib.text import Text

    for t in fig.texts:
        if _visible(t):
            yield "figure text", t, None
    for leg in fig.legends:
        for t in [leg.get_title()] + list(leg.get_texts()):
            if _visible(t):
                yield "legend text", t, None
    for ax in fig.axes:
        for t in ax.get_children():  # the axes' three titles (centre, left, right)
            if isinstance(t, Text) and t not in ax.texts and _visible(t):
                yield "title", t, None
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            if _visible(axis.label):
                yield f"{name} axis label", axis.label, None
            if _visible(axis.offsetText):
                yield f"{name} axis offset", axis.offsetText, None
            for t, minor in drawn_tick_labels(axis):
                yield f"{name} {'minor ' if minor else ''}tick label", t, None
        leg = ax.get_legend()
        if leg is not None:
            for t in [leg.get_title()] + list(leg.get_texts()):
                if _visible(t):
                    yield "legend text", t, None
        for t in ax.texts:
            if isinstance(t, Text) and _visible(t):
                yield "data label", t, ax


def _inside(box, outer, tol: float = _TOL) -> bool:
    return (box.x0 >= outer.x0 - tol and box.x1 <= outer.x1 + tol and box.y0 >= outer.y0 - tol
            and box.y1 <= outer.y1 + tol)


def _overlap(a, b, tol: float = _TOL) -> bool:
    return (min(a.x1, b.x1) - max(a.x0, b.x0) > tol) and (min(a.y1, b.y1) - max(a.y0, b.y0) > tol)


def _shrunk(box, by: float):
    from matplotlib.transforms import Bbox

    return Bbox.from_extents(box.x0 + by, box.y0 + by, box.x1 - by, box.y1 - by)


def _line_runs(line) -> Iterator[np.ndarray]:
    """The display coordinates of ``line``'s finite stretches."""
    xy = np.asarray(line.get_xydata(), dtype=float)
    if xy.size == 0:
        return
    d = line.get_transform().transform(xy)
    ok = np.all(np.isfinite(d), axis=1)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
    for a, b in zip(edges[::2], edges[1::2]):
        yield d[a:b]


def _has_line(line) -> bool:
    return line.get_linestyle() not in ("None", "none", "", " ") and line.get_linewidth() > 0


def _has_markers(line) -> bool:
    return line.get_marker() not in (None, "None", "none", "", " ")


def _line_crosses(line, box, dpi: float) -> bool:
    from matplotlib.path import Path as MPath

    for run in _line_runs(line):
        if _has_line(line) and len(run) >= 2 and MPath(run).intersects_bbox(box, filled=False):
            return True
        if _has_markers(line):
            r = 0.5 * line.get_markersize() * dpi / 72.0
            if np.any((run[:, 0] >= box.x0 - r) & (run[:, 0] <= box.x1 + r) & (run[:, 1] >= box.y0 - r)
                      & (run[:, 1] <= box.y1 + r)):
                return True
    return False


def _label(artist) -> str:
    lab = artist.get_label() if hasattr(artist, "get_label") else ""
    return repr(lab) if lab and not lab.startswith("_") else type(artist).__name__


def covered_data(ax, box, renderer) -> List[str]:
    """The data of ``ax`` (lines, markers, bars, fills, data labels) that the display box
    ``box`` covers inside the axes."""
    from matplotlib.transforms import Bbox

    frame = ax.get_window_extent(renderer)
    inner = Bbox.intersection(box, frame)
    if inner is None or inner.width <= _TOL or inner.height <= _TOL:
        return []
    inner = _shrunk(inner, 0.5)
    dpi = ax.figure.dpi
    hit = []
    for line in ax.lines:
        if line.get_visible() and _line_crosses(line, inner, dpi):
            hit.append(f"line {_label(line)}")
    for patch in ax.patches:
        if not patch.get_visible():
            continue
        path = patch.get_transform().transform_path(patch.get_path())
        ext = path.get_extents()
        if ext.width < 1.0 and ext.height < 1.0:
            continue  # a bar of zero length
        if path.intersects_bbox(inner, filled=True):
            hit.append(f"patch {_label(patch)}")
    for coll in ax.collections:
        if not coll.get_visible():
            continue
        t = coll.get_transform()
        if any(t.transform_path(p).intersects_bbox(inner, filled=True) for p in coll.get_paths()):
            hit.append(f"collection {_label(coll)}")
    for t in ax.texts:
        if _visible(t) and _overlap(t.get_window_extent(renderer), inner):
            hit.append(f"label {_short(t)}")
    return hit


def _opaque_above(text, line) -> bool:
    patch = text.get_bbox_patch()
    if patch is None or not patch.get_fill():
        return False
    return patch.get_facecolor()[3] >= 0.999 and text.get_zorder() > line.get_zorder()


def _legends(fig) -> Iterator[Tuple[object, Optional[object]]]:
    for ax in fig.axes:
        if ax.get_legend() is not None:
            yield ax.get_legend(), ax
    for leg in fig.legends:
        yield leg, None


def layout_problems(fig) -> List[str]:
    """Draw ``fig`` and list what does not fit (the module docstring's problems), one sentence each; empty
    when every text is inside the figure, every data label inside its axes and clear of the
    lines drawn over it, no two tick labels of an axis overlap and no legend covers data."""
    renderer = _renderer(fig)
    frame = fig.bbox
    problems = []
    for what, t, ax in _texts(fig):
        box = t.get_window_extent(renderer)
        if not _inside(box, frame):
            problems.append(f"{what} {_short(t)} leaves the figure ({box.x0:.0f}..{box.x1:.0f} x "
                            f"{box.y0:.0f}..{box.y1:.0f} px of {frame.width:.0f} x {frame.height:.0f})")
        if ax is None:
            continue
        if not _inside(box, ax.get_window_extent(renderer)):
            problems.append(f"{what} {_short(t)} leaves its axes")
        inner = _shrunk(box, 1.0)
        for line in ax.lines:
            if line.get_visible() and not _opaque_above(t, line) and _line_crosses(line, inner, fig.dpi):
                problems.append(f"{what} {_short(t)} is crossed by line {_label(line)}")
    for ax in fig.axes:
        for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            labels = [(t, t.get_window_extent(renderer)) for t, _ in drawn_tick_labels(axis)]
            for i in range(len(labels)):
                for j in range(i + 1, len(labels)):
                    if _overlap(labels[i][1], labels[j][1]):
                        problems.append(f"{name} tick labels {_short(labels[i][0])} and {_short(labels[j][0])} overlap")
    for leg, owner in _legends(fig):
        box = leg.get_window_extent(renderer)
        for ax in ([owner] if owner is not None else fig.axes):
            for item in covered_data(ax, box, renderer):
                problems.append(f"legend covers {item}")
    return problems
