"""Every figure of the reports and trade studies fits: the check of
:mod:`diffsense.report.style` (``layout_problems``) first proven on figures broken on purpose
(a title wider than the figure, colliding tick labels, a legend over the data, a label under a
line or past its axes) and on the same figures drawn in the report's style, then run on every
figure of every shipped design's report and trade study as it is saved. And the two range
figures of one report agree: the ore pass's SNR and Pd figures draw the condition its
requirement states (the target in its 15 dB fade) and mark the same range."""

from pathlib import Path

import numpy as np
import pytest
from helpers.paths import REPO

from diffsense.report import style

DESIGNS = sorted(p.stem for p in (REPO / "designs").glob("*.toml"))
TRADES = [name for name in DESIGNS if "\n[trade]" in (REPO / "designs" / f"{name}.toml").read_text()]
LONG_TITLE = ("Ship-borne fire-control radar (Brooker 14.9 requirements, 14.6-14.7 tracking): elasticities of "
              "the detection margin at every range from 10 to 320 km in clear air and in heavy rain")


def _plain_figure(width=4.0, height=3.0):
    """A figure as matplotlib draws it by default (no fitting)."""
    return style.pyplot().subplots(figsize=(width, height), dpi=style.DPI)


def _close(fig):
    style.pyplot().close(fig)


def test_the_shipped_designs_are_ten_and_three_carry_a_trade():
    assert len(DESIGNS) == 10
    assert TRADES == ["air_surveillance", "fire_control", "ore_pass"]


# --- the check itself, on broken figures and on the same figures fitted -----------------------


def test_a_title_wider_than_the_figure_is_found_and_wrapping_fits_it_without_losing_a_word():
    fig, ax = _plain_figure()
    ax.set_title(LONG_TITLE)
    problems = style.layout_problems(fig)
    _close(fig)
    assert any(p.startswith("title 'Ship-borne") and "leaves the figure" in p for p in problems), problems

    fig, ax = style.new_figure(4.0, 3.0)
    style.set_title(ax, LONG_TITLE)
    assert style.fit(fig) == []
    lines = ax.title.get_text().split("\n")
    renderer = fig.canvas.get_renderer()
    width = ax.get_window_extent(renderer).width
    probe = ax.title.get_fontproperties()
    for line in lines:
        assert renderer.get_text_width_height_descent(line, probe, ismath=False)[0] <= width
    assert len(lines) >= 3 and " ".join(lines) == LONG_TITLE  # wrapped, never truncated
    _close(fig)


def test_overlapping_tick_labels_are_found():
    fig, ax = _plain_figure()
    ax.set_xticks([0.0, 0.02])
    ax.set_xticklabels(["first long label", "second long label"])
    ax.set_xlim(-1.0, 1.0)
    problems = style.layout_problems(fig)
    _close(fig)
    assert problems == ["x tick labels 'first long label' and 'second long label' overlap"]


def test_log_axis_minor_labels_that_collide_are_found_and_thinned_to_labels_that_do_not():
    # a log axis spanning less than a decade: matplotlib labels every minor tick 3×10^0, 4×10^0, ...
    fig, ax = _plain_figure(2.4, 2.0)
    ax.plot([2.2, 9.8], [0.0, 1.0])
    ax.set_xscale("log")
    ax.set_xlim(2.2, 9.8)
    problems = style.layout_problems(fig)
    _close(fig)
    assert any(p.startswith("x tick labels") and p.endswith("overlap") for p in problems), problems

    # in the report's style, on the same narrow axis with four-digit labels: thinned, not dropped
    fig, ax = style.new_figure(2.4, 2.0)
    ax.plot([2200.0, 9800.0], [0.0, 1.0])
    style.log_scale(ax, "x")
    ax.set_xlim(2200.0, 9800.0)
    assert style.fit(fig) == []
    shown = [t.get_text() for t, _ in style.drawn_tick_labels(ax.xaxis)]
    assert 2 <= len(shown) < 7 and all(s.isdigit() for s in shown), shown  # plain digits, some of 3000..9000
    _close(fig)


def test_a_legend_over_the_curve_is_found_and_moved_below_the_axes():
    x = np.linspace(0.0, 1.0, 50)
    fig, ax = _plain_figure()
    ax.plot(x, 0.5 + 0.0 * x, label="a curve across the middle")
    ax.legend(loc="center")
    problems = style.layout_problems(fig)
    _close(fig)
    assert problems == ["legend covers line 'a curve across the middle'"]

    fig, ax = style.new_figure(4.0, 3.0)
    for k in range(9):  # curves everywhere: no place inside the axes is free
        ax.plot(x, k / 8.0 + 0.0 * x, label=f"level {k}")
    style.legend(ax)
    assert style.fit(fig) == []
    assert ax.get_legend() is None and len(fig.legends) == 1
    renderer = fig.canvas.get_renderer()
    assert fig.legends[0].get_window_extent(renderer).y1 < ax.get_window_extent(renderer).y0
    _close(fig)


def test_a_label_under_a_line_or_past_its_axes_is_found_and_the_style_fixes_both():
    fig, ax = _plain_figure()
    ax.set_xlim(0.0, 1.0)
    ax.axvline(0.5, linestyle="--", label="SNR needed")
    ax.text(0.45, 0.5, "+11.50 dB")
    ax.text(0.97, 0.2, "+203.98 dB")
    problems = style.layout_problems(fig)
    _close(fig)
    assert "data label '+11.50 dB' is crossed by line 'SNR needed'" in problems
    assert "data label '+203.98 dB' leaves its axes" in problems

    fig, ax = style.new_figure(4.0, 3.0)
    ax.set_xlim(0.0, 1.0)
    ax.axvline(0.5, linestyle="--", label="SNR needed")
    style.data_label(ax, 0.45, 0.5, "+11.50 dB")
    style.data_label(ax, 0.97, 0.2, "+203.98 dB")
    assert style.fit(fig) == []
    assert ax.get_xlim()[1] > 1.0  # widened for the label, not moved
    _close(fig)


def test_the_trade_front_carries_the_whole_title_and_fits(tmp_path, monkeypatch):
    # "Pareto front: " and the fire-control title are 91 characters: wrapped, not cut at 80; the front here is laid out by hand (points of both bands, the cost over more
    # than a decade: a log axis), the figure is the point, not the solver
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.design.trade import TradeResult, objective_label, objective_unit, trade_spec
    from diffsense.report.files import OutputFolder
    from diffsense.report.trade import front_figure

    model = DesignModel(trade_spec(load_spec(REPO / "designs" / "fire_control.toml")))
    objectives = list(model.spec.trade.objectives)
    cost = np.geomspace(3.4, 48.0, 8)
    error = 2.4e-5 + 1.4e-5 * (cost[-1] - cost) / (cost[-1] - cost[0])
    points = [{"F": np.array([c, e]), "combo_index": k % len(model.combinations), "anchor": 0 if k == 0 else
               1 if k == len(cost) - 1 else -1} for k, (c, e) in enumerate(zip(cost, error))]
    result = TradeResult(model, [objective_label(o) for o in objectives], [objective_unit(model, o) for o in objectives],
                         objectives, points, 3, {}, [], 0, 0, 0.0)
    titles = {}
    seen = _record_saved_figures(monkeypatch, titles)
    front_figure(result, OutputFolder(tmp_path).file("front.png"))
    assert seen == {"front.png": []}
    assert titles["front.png"] == f"Pareto front: {model.spec.title}"


# --- every figure of every shipped design -------------------------------------------------------


def _record_saved_figures(monkeypatch, titles=None):
    """Run ``layout_problems`` on every figure an output folder saves: {relative path: problems};
    ``titles``, a dict, receives each figure's title (its lines joined by spaces)."""
    from diffsense.report.files import OutputFolder

    seen = {}
    save = OutputFolder.save_figure

    def checked(self, relative, fig, dpi=None):
        seen[relative] = style.layout_problems(fig)
        if titles is not None:
            titles[relative] = " ".join(fig.axes[0].get_title().split())
        return save(self, relative, fig, dpi=dpi)

    monkeypatch.setattr(OutputFolder, "save_figure", checked)
    return seen


def _assert_fits_and_exists(seen, out: Path, listed):
    assert seen, "no figure was saved"
    bad = [f"{name}: {problem}" for name, problems in seen.items() for problem in problems]
    assert not bad, "\n".join(bad)
    assert sorted(str(f) for f in listed) == sorted(seen)
    for name in seen:
        png = (out / name).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000, name


@pytest.mark.slow
@pytest.mark.parametrize("name", DESIGNS)
def test_every_report_figure_of_every_shipped_design_fits(tmp_path, monkeypatch, name):
    from diffsense.report import build_report

    seen = _record_saved_figures(monkeypatch)
    # the figures are the point, not the optimum: fire control's optimisation is slow, so its
    # report is the spec's initial design
    rep = build_report(REPO / "designs" / f"{name}.toml", tmp_path, optimize=name != "fire_control", n_starts=2)
    _assert_fits_and_exists(seen, tmp_path, [f["file"] for f in rep["figures"]])


@pytest.mark.slow
@pytest.mark.parametrize("name", TRADES)
def test_every_trade_figure_of_every_shipped_trade_fits(tmp_path, monkeypatch, name):
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.design.trade import trade_design, trade_spec
    from diffsense.report.trade import write_trade_report

    titles = {}
    seen = _record_saved_figures(monkeypatch, titles)
    result = trade_design(DesignModel(trade_spec(load_spec(REPO / "designs" / f"{name}.toml"))), points=4)
    files = write_trade_report(result, tmp_path)
    _assert_fits_and_exists(seen, tmp_path, [f.relative_to(tmp_path).as_posix() for f in files["figures"]])
    assert titles["figures/front.png"] == f"Pareto front: {result.model.spec.title}"  # whole, not cut


# --- the range figures of one report agree ------------------------------------------------------


def _figures_saved(monkeypatch):
    """{relative path: figure} of every figure an output folder saves (kept open)."""
    from diffsense.report.files import OutputFolder

    saved = {}
    monkeypatch.setattr(OutputFolder, "save_figure", lambda self, relative, fig, dpi=None: saved.setdefault(
        relative, fig) and self.target(relative))
    monkeypatch.setattr(style.pyplot(), "close", lambda fig=None: None)
    return saved


def _marker(fig) -> float:
    """The range of the one round marker of the figure (where a requirement is just met)."""
    (x,) = [line.get_xdata()[0] for line in fig.axes[0].lines
            if line.get_marker() == "o" and len(line.get_xdata()) == 1]
    return float(x)


def test_ore_pass_snr_and_pd_figures_draw_the_faded_target_and_mark_one_range(tmp_path, monkeypatch):
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.report import figures
    from diffsense.report.batch import BatchEvaluator
    from diffsense.report.files import OutputFolder
    from diffsense.report.inputs import design_inputs
    from diffsense.report.sweeps import input_index, range_sweep

    model = DesignModel(load_spec(REPO / "designs" / "ore_pass.toml"))
    inputs = design_inputs(model, model.initial, 0)
    batch = BatchEvaluator(model, model.initial, 0)
    sweep = range_sweep(batch, model, inputs, "main")
    saved = _figures_saved(monkeypatch)
    folder = OutputFolder(tmp_path)
    figures.snr_vs_range(folder.file("snr.png"), sweep, title="SNR")
    figures.pd_vs_range(folder.file("pd.png"), sweep, required_pd=0.95, pfa=1e-12, title="Pd")
    r_snr, r_pd = _marker(saved["snr.png"]), _marker(saved["pd.png"])
    assert r_pd == pytest.approx(r_snr, rel=1e-12)

    # independently: the chain's own Pd and margin with the target's RCS lowered by its 15 dB fade
    v0 = np.array([i.value for i in inputs])
    k_r, k_rcs, k_fade = (input_index(inputs, p, "main") for p in ("range_m", "rcs_m2", "rcs_fade_db"))
    assert v0[k_fade] == 15.0

    def faded(ranges):
        V = np.repeat(v0[None, :], len(ranges), axis=0)
        V[:, k_r] = ranges
        V[:, k_rcs] *= 10.0 ** (-15.0 / 10.0)
        ev = batch(V)[0][0]["main"].values
        return np.asarray(ev["pd"]), np.asarray(ev["snr_db"] - ev["required_snr_db"])

    pd_at, margin_at = faded(np.array([r_snr]))
    assert pd_at[0] == pytest.approx(0.95, abs=2e-3)  # the requirement's Pd, at the marked range
    assert margin_at[0] == pytest.approx(0.0, abs=0.02)  # the faded SNR meets the required SNR there
    # the solid curves are the faded target's: Pd and SNR of the chain at 15 dB less RCS
    pd_line, snr_line = saved["pd.png"].axes[0].lines[0], saved["snr.png"].axes[0].lines[0]
    pd_faded, _ = faded(pd_line.get_xdata())
    assert np.max(np.abs(pd_line.get_ydata() - pd_faded)) < 1e-6
    assert np.max(np.abs(snr_line.get_ydata() - (sweep["outputs"]["snr_db"] - 15.0))) < 1e-9
    monkeypatch.undo()
    for fig in saved.values():
        style.pyplot().close(fig)


def test_range_figures_shade_the_interval_a_margin_requirement_holds_over(tmp_path, monkeypatch):
    """The corner radar's pedestrian must be detected at every range from 1 to 80 m (spec file);
    its fixed range_m (100 m) is read by no requirement: the SNR and Pd figures shade 1-80 m and
    draw no line at 100 m, and the range grid covers the interval."""
    import tomllib

    from matplotlib.patches import Polygon, Rectangle

    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.report import figures
    from diffsense.report.batch import BatchEvaluator
    from diffsense.report.files import OutputFolder
    from diffsense.report.inputs import design_inputs
    from diffsense.report.sweeps import range_sweep

    path = REPO / "designs" / "automotive_corner_radar.toml"
    raw = tomllib.loads(path.read_text())
    (req,) = [r for r in raw["requirements"] if r["output"] == "pedestrian.detection_margin_db"]
    assert req["over"]["range_m"] == ["1 m", "80 m"] and raw["fixed"]["range_m"] == "100 m"
    model = DesignModel(load_spec(path))
    inputs = design_inputs(model, model.initial, 0)
    sweep = range_sweep(BatchEvaluator(model, model.initial, 0), model, inputs, "pedestrian")
    assert sweep["required_range_m"] == (1.0, 80.0)
    assert sweep["range_m"][0] <= 1.0 and sweep["range_m"][-1] >= 100.0
    saved = _figures_saved(monkeypatch)
    folder = OutputFolder(tmp_path)
    figures.snr_vs_range(folder.file("snr.png"), sweep, title="SNR")
    figures.pd_vs_range(folder.file("pd.png"), sweep, required_pd=0.9, pfa=1e-6, title="Pd")
    for name in ("snr.png", "pd.png"):
        ax = saved[name].axes[0]
        spans = [p for p in ax.patches if isinstance(p, (Polygon, Rectangle))]
        assert len(spans) == 1
        xs = spans[0].get_path().transformed(spans[0].get_patch_transform()).vertices[:, 0] \
            if isinstance(spans[0], Rectangle) else spans[0].get_xy()[:, 0]
        assert (float(np.min(xs)), float(np.max(xs))) == pytest.approx((1.0, 80.0), rel=1e-12)
        vertical = [line for line in ax.lines if len(set(np.atleast_1d(line.get_xdata()).tolist())) == 1
                    and len(line.get_xdata()) == 2]
        assert not vertical  # no dotted line at the fixed range
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert "required at every range from 1 to 80 m" in labels
    monkeypatch.undo()
    for fig in saved.values():
        style.pyplot().close(fig)
