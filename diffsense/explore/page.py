"""The explorer page (Panel): widgets for the design, the charts and tables of a snapshot, and
the buttons. The same page is served by ``diffsense explore`` and shown in a Jupyter cell.

Widgets: per continuous design variable a slider (over log10 of the value where the spec's
scale is log) with a text box holding the value in its unit; per integer variable an integer
slider with its text box; per catalog a selector; folded away, a text box per fixed parameter.
A typed value is checked as the spec would be (:meth:`ExplorerSession.type_fixed`); a bad one
leaves the point where it was and shows the command line's message on the page.

Every change re-evaluates the compiled program (:meth:`ExplorerSession.snapshot`) and replaces
the numbers of the charts' data sources inside one held document update.
"""

from __future__ import annotations

import asyncio
import math
import time
from html import escape
from pathlib import Path
from typing import Dict

import panel as pn
from bokeh.models import ColumnDataSource

from diffsense.errors import DomainError, SpecError, UnitError
from diffsense.explore import figures as F
from diffsense.explore.session import ExplorerSession, FileExists
from diffsense.explore.tables import headline_html, requirements_html
from diffsense.report.files import OutputError
from diffsense.report.render import fmt, si_text

SIDEBAR_WIDTH = 390
USER_ERRORS = (SpecError, DomainError, UnitError, OutputError)


def _text(value: float, unit: str) -> str:
    """A value as the user would type it: SI prefixes for Hz, W, s and m ("50 MHz"), otherwise
    the number and the parameter's unit; six significant digits."""
    if unit in ("Hz", "W", "s", "m"):
        return si_text(value, unit, 6)
    return f"{fmt(value, 6)} {unit.replace('**', '^')}" if unit not in ("", "1") else fmt(value, 6)


def _shown_path(path) -> str:
    """``path`` relative to the working folder when inside it, else absolute."""
    path = Path(path).absolute()
    try:
        return str(path.relative_to(Path.cwd()))
    except ValueError:
        return str(path)


class ExplorerPage:
    """The page of one :class:`ExplorerSession` (``.layout`` is the Panel object to show)."""

    def __init__(self, session: ExplorerSession, *, save_name=None, report_name=None):
        self.session = session
        self.spec = session.spec
        self._syncing = False
        self.update_ms = None
        stem = self.spec.name
        self.case = pn.widgets.Select(name="case", options=list(self.spec.scenes), width=220,
                                      visible=len(self.spec.scenes) > 1)
        self.output = pn.widgets.Select(name="elasticities of", options=session.output_labels(), width=300)
        self.message = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["ds-message"])
        self.progress = pn.indicators.Progress(active=False, value=-1, visible=False, sizing_mode="stretch_width")
        # file names only: everything is written in the session's one output folder
        self.save_path = pn.widgets.TextInput(name="save as (.toml)", value=str(save_name or f"{stem}_explored"),
                                              width=230)
        self.report_dir = pn.widgets.TextInput(name="report folder", value=str(report_name or f"{stem}_report"),
                                               width=230)
        self.folder_note = pn.pane.HTML(f"<div style='color:#57606a;font-size:90%'>files go to "
                                        f"{escape(_shown_path(session.out_dir))}/</div>", sizing_mode="stretch_width")
        self.confirm_text = pn.pane.HTML("", sizing_mode="stretch_width", css_classes=["ds-confirm"])
        self.confirm_button = pn.widgets.Button(name="replace", button_type="danger", width=100)
        self.cancel_button = pn.widgets.Button(name="cancel", button_type="default", width=100)
        self.confirm = pn.Column(self.confirm_text, pn.Row(self.confirm_button, self.cancel_button), visible=False,
                                 sizing_mode="stretch_width")
        self._pending = None
        # the numbers first (the core program); the curves and elasticities once their larger
        # program is compiled, after the page is shown (prepare_extras)
        self.snap = session.snapshot(extras=None)
        self._build_design_widgets()
        self._build_charts()
        self._build_buttons()
        self.layout = self._layout()
        self.refresh()
        if not session.program.extras_ready:
            pn.state.onload(self.prepare_extras)

    def _note(self, text: str, ready: bool = False) -> None:
        flag = " data-ready='1'" if ready else ""
        self.extras_note.object = f"<div style='color:#57606a;font-size:12px' data-role='extras'{flag}>{escape(text)}</div>"

    async def prepare_extras(self) -> None:
        """Compile, off the event loop, the interval requirements' searches and then the curves'
        and elasticities' program, drawing what each adds as soon as it is ready."""
        loop = asyncio.get_running_loop()
        core_s = 0.0
        if not self.session.program.core_ready:
            self._note("compiling the searches of the requirements over intervals …")
            core_s = await loop.run_in_executor(None, self.session.prepare_core)
            self.refresh()
        self._note("compiling the range sweeps, interval curves and elasticities …")
        extras_s = await loop.run_in_executor(None, self.session.prepare_extras)
        self._note(f"interval searches compiled in {core_s:.1f} s, curves and elasticities in {extras_s:.1f} s",
                   ready=True)
        self.refresh()

    # --- widgets ----------------------------------------------------------------------------
    def _build_design_widgets(self) -> None:
        s = self.session
        self.sliders: Dict[str, pn.widgets.Widget] = {}
        self.boxes: Dict[str, pn.widgets.TextInput] = {}
        for name in s.variable_names:
            var = self.spec.variables[name]
            if var.integer:
                slider = pn.widgets.IntSlider(name=f"{name} (integer)", start=int(math.ceil(var.lower)),
                                              end=int(math.floor(var.upper)), value=int(s.value(name)),
                                              show_value=False, tooltips=False, sizing_mode="stretch_width")
            else:
                lo, hi = (math.log10(var.lower), math.log10(var.upper)) if var.log_scale else (var.lower, var.upper)
                slider = pn.widgets.FloatSlider(name=f"{name} ({'log' if var.log_scale else 'linear'} scale)",
                                                start=lo, end=hi, step=(hi - lo) / 1000.0,
                                                value=self._slider_value(name, s.value(name)),
                                                show_value=False, tooltips=False, sizing_mode="stretch_width")
            slider.param.watch(lambda e, n=name: self._on_slider(n, e.new), "value")
            box = pn.widgets.TextInput(value=_text(s.value(name), var.unit), width=130, margin=(22, 5, 5, 5))
            box.param.watch(lambda e, n=name: self._on_variable_text(n, e.new), "value")
            self.sliders[name], self.boxes[name] = slider, box
        self.selects = {}
        for catalog, options in s.catalogs.items():
            select = pn.widgets.Select(name=catalog, options=options, value=options[s.options[catalog]],
                                       sizing_mode="stretch_width")
            select.param.watch(lambda e, c=catalog: self._on_option(c, e.new), "value")
            self.selects[catalog] = select
        self.fixed_boxes = {}
        for name in s.fixed_names:
            inp = s.input(name)
            box = pn.widgets.TextInput(name=name, value=_text(inp.value, inp.unit), width=170)
            box.param.watch(lambda e, n=name: self._on_fixed_text(n, e.new), "value")
            self.fixed_boxes[name] = box

    def _slider_value(self, name: str, value: float) -> float:
        var = self.spec.variables[name]
        if var.integer:
            return int(round(value))
        return math.log10(value) if var.log_scale else value

    def _build_charts(self) -> None:
        self.budget_source = ColumnDataSource(F.waterfall_data(self._case_budget()))
        self.required = F.required_span()
        self.snr_source = ColumnDataSource(F.sweep_data(None, "snr_db"))
        self.threshold_source = ColumnDataSource(F.sweep_data(None, "snr_db"))
        self.pd_source = ColumnDataSource(F.sweep_data(None, "pd"))
        self.design_snr, self.design_pd = F.design_range_span(), F.design_range_span()
        self.required_pd = F.required_pd_span()
        self.tornado_source = ColumnDataSource(F.tornado_data([], []))
        self.waterfall = F.waterfall_figure(self.budget_source, self.required)
        self.snr_fig = F.snr_figure(self.snr_source, self.threshold_source, self.design_snr)
        self.pd_fig = F.pd_figure(self.pd_source, self.required_pd, self.design_pd)
        self.tornado = F.tornado_figure(self.tornado_source)
        self.extras_note = pn.pane.HTML("", sizing_mode="stretch_width")
        names = list(self.session.program.interval_requirements)
        labels = [self.session.model.requirements[j].name for j in names]
        self.interval = pn.widgets.Select(name="requirement over its interval", options=labels, width=300,
                                          visible=bool(labels))
        self.interval_source = ColumnDataSource(F.interval_data(None))
        self.interval_worst = ColumnDataSource(F.interval_worst_data(None))
        log_x = bool(names) and all(bool(self.session.model.intervals.boxes[j].log[0]) for j in names)
        self.interval_fig = F.interval_figure(self.interval_source, self.interval_worst, log_x)
        self.interval_fig.visible = bool(labels)
        self.interval.param.watch(lambda e: self._draw_interval(), "value")
        self.headline = pn.pane.HTML("", sizing_mode="stretch_width")
        self.requirements = pn.pane.HTML("", sizing_mode="stretch_width")
        self.timing = pn.pane.HTML("", sizing_mode="stretch_width")
        self.case.param.watch(lambda e: self.refresh(), "value")
        self.output.param.watch(lambda e: self._draw_tornado(), "value")

    def _case_budget(self):
        return self.snap["cases"][self.case.value]["budget"]

    def _build_buttons(self) -> None:
        self.optimize_button = pn.widgets.Button(name="optimize from here", button_type="primary", width=170)
        self.reset_button = pn.widgets.Button(name="reset to spec", button_type="default", width=170)
        self.save_button = pn.widgets.Button(name="save as TOML", button_type="success", width=120,
                                             margin=(24, 5, 5, 5))
        self.report_button = pn.widgets.Button(name="report", button_type="default", width=120,
                                               margin=(24, 5, 5, 5))
        self.optimize_button.on_click(self._on_optimize)
        self.reset_button.on_click(lambda e: self.reset())
        self.save_button.on_click(lambda e: self.save())
        self.report_button.on_click(self._on_report)
        self.confirm_button.on_click(self._on_confirm)
        self.cancel_button.on_click(lambda e: self._ask(None))

    def _layout(self):
        design = [pn.pane.HTML("<b>Design variables</b>")]
        for name in self.session.variable_names:
            design.append(pn.Row(self.sliders[name], self.boxes[name], sizing_mode="stretch_width"))
        design += list(self.selects.values())
        fixed = pn.Card(pn.GridBox(*self.fixed_boxes.values(), ncols=2), title=f"Fixed parameters ({len(self.fixed_boxes)})",
                        collapsed=True, sizing_mode="stretch_width")
        buttons = pn.Column(pn.Row(self.optimize_button, self.reset_button), self.progress,
                            pn.Row(self.save_path, self.save_button), pn.Row(self.report_dir, self.report_button),
                            self.folder_note, self.confirm)
        sidebar = pn.Column(buttons, self.message, *design, fixed, width=SIDEBAR_WIDTH)
        # the spec's strings are data: escaped, never markup (a title may hold any text)
        title = pn.pane.HTML(f"<h2 style='margin:4px 0'>{escape(self.spec.title)}</h2>"
                             f"<div style='color:#57606a'>{escape(str(self.session.path))} · "
                             f"{escape(self.spec.sensor)}</div>", sizing_mode="stretch_width")
        main = pn.Column(
            pn.Row(title, self.case), self.headline,
            pn.Row(pn.pane.Bokeh(self.waterfall, sizing_mode="stretch_width"),
                   pn.Column(pn.pane.HTML("<b>Requirements</b>"), self.requirements, sizing_mode="stretch_width"),
                   sizing_mode="stretch_width"),
            pn.Row(pn.pane.Bokeh(self.snr_fig, sizing_mode="stretch_width"),
                   pn.pane.Bokeh(self.pd_fig, sizing_mode="stretch_width"), sizing_mode="stretch_width"),
            self.extras_note,
            pn.Row(pn.Column(self.interval, pn.pane.Bokeh(self.interval_fig, sizing_mode="stretch_width"),
                             sizing_mode="stretch_width", visible=bool(self.interval.options)),
                   pn.Column(self.output, pn.pane.Bokeh(self.tornado, sizing_mode="stretch_width"),
                             sizing_mode="stretch_width"), sizing_mode="stretch_width"),
            self.timing, sizing_mode="stretch_width")
        return pn.Row(sidebar, main, sizing_mode="stretch_width")

    # --- drawing ------------------------------------------------------------------------------
    def refresh(self) -> None:
        """Evaluate the current point and draw it."""
        t0 = time.perf_counter()
        self.snap = self.session.snapshot(extras=None)
        snap, case = self.snap, self.case.value
        units = {(c, o): self.spec.unit_of(c, o) for c, cs in snap["cases"].items() for o in cs["outputs"]}
        with pn.io.hold():
            self.headline.object = headline_html(snap, self.spec.objective.text, units)
            self.requirements.object = requirements_html(snap["requirements"])
            data = F.waterfall_data(snap["cases"][case]["budget"])
            F.show_waterfall(self.waterfall, data)
            self.budget_source.data = data
            sweep = snap["sweeps"].get(case)
            self.snr_source.data = F.sweep_data(sweep, "snr_db")
            threshold = dict(sweep, outputs={"t": sweep["threshold_db"]}) if sweep and "threshold_db" in sweep else None
            self.threshold_source.data = F.sweep_data(threshold, "t")
            self.pd_source.data = F.sweep_data(sweep, "pd")
            if sweep is not None:
                self.design_snr.location = self.design_pd.location = sweep["design_range_m"] / 1e3
                if sweep.get("required_pd") is not None:
                    self.required_pd.location = sweep["required_pd"]
                if "threshold_db" in sweep:
                    k = int(abs(sweep["range_m"] - sweep["design_range_m"]).argmin())
                    self.required.location = float(sweep["threshold_db"][k])
                    self.required.visible = True
            else:
                self.required.visible = False
            self._draw_tornado()
            self._draw_interval()
            self.update_ms = 1e3 * (time.perf_counter() - t0)
            self.timing.object = (f"<div style='color:#57606a;font-size:12px;margin-top:40px'>server: evaluation "
                                  f"<span data-role='eval-ms'>{snap['eval_ms']:.1f}</span> ms, page update "
                                  f"<span data-role='update-ms'>{self.update_ms:.1f}</span> ms</div>")

    def _draw_interval(self) -> None:
        curve = self.snap["intervals"].get(self.interval.value) if self.interval.value else None
        self.interval_source.data = F.interval_data(curve)
        self.interval_worst.data = F.interval_worst_data(curve)
        if curve is not None:
            self.interval_fig.title.text = F.interval_title(curve)
            self.interval_fig.xaxis.axis_label = f"{curve['parameter']} ({curve['unit']})"
            self.interval_fig.yaxis.axis_label = f"{curve['output']} ({curve['output_unit']})"

    def _draw_tornado(self) -> None:
        if self.snap["elasticity"] is None:
            self.tornado_source.data = F.tornado_data([], [])
            return
        labels = self.session.output_labels()
        row = labels.index(self.output.value)
        data = F.tornado_data([i.name for i in self.session.inputs], self.snap["elasticity"][row])
        self.tornado.y_range.factors = data["input"][::-1]
        self.tornado_source.data = data
        self.tornado.title.text = f"Elasticities of {self.output.value} (dB per dB, % per %)"

    def say(self, text: str, kind: str = "info") -> None:
        colour = {"info": "#1f6feb", "ok": "#1a7f37", "error": "#cf222e"}[kind]
        self.message.object = (f"<div data-role='message' data-kind='{kind}' style='color:{colour};"
                               f"white-space:pre-wrap;font-size:13px'>{escape(text)}</div>") if text else ""

    # --- callbacks ----------------------------------------------------------------------------
    def _on_slider(self, name: str, value) -> None:
        if self._syncing:
            return
        var = self.spec.variables[name]
        real = float(value) if (var.integer or not var.log_scale) else 10.0 ** float(value)
        real = self.session.set_variable(name, real)
        self._sync(lambda: setattr(self.boxes[name], "value", _text(real, var.unit)))
        self.refresh()

    def _on_variable_text(self, name: str, text: str) -> None:
        if self._syncing:
            return
        try:
            value = self.session.type_variable(name, text)
        except USER_ERRORS as exc:
            self.say(str(exc), "error")
            return
        self.say("")
        self._sync(lambda: setattr(self.sliders[name], "value", self._slider_value(name, value)))
        self.refresh()

    def _on_option(self, catalog: str, option: str) -> None:
        if self._syncing:
            return
        self.session.set_option(catalog, option)
        self.refresh()

    def _on_fixed_text(self, name: str, text: str) -> None:
        if self._syncing:
            return
        try:
            self.session.type_fixed(name, text)
        except USER_ERRORS as exc:
            self.say(str(exc), "error")
            return
        self.say("")
        self.refresh()

    def _sync(self, change) -> None:
        self._syncing = True
        try:
            change()
        finally:
            self._syncing = False

    def sync_widgets(self) -> None:
        """Move every widget to the session's current point (after reset or optimisation)."""
        s = self.session

        def move():
            for name in s.variable_names:
                self.sliders[name].value = self._slider_value(name, s.value(name))
                self.boxes[name].value = _text(s.value(name), self.spec.variables[name].unit)
            for catalog, select in self.selects.items():
                select.value = s.catalogs[catalog][s.options[catalog]]
            for name, box in self.fixed_boxes.items():
                box.value = _text(s.value(name), s.input(name).unit)
        self._sync(move)

    def reset(self) -> None:
        self.session.reset()
        self.sync_widgets()
        self.say("reset to the spec's initial design", "info")
        self.refresh()

    def _ask(self, pending, path=None) -> None:
        """Ask before replacing ``path`` (``pending``: what to run once the user confirms);
        ``None`` withdraws the question."""
        self._pending = pending
        self.confirm.visible = pending is not None
        self.confirm_text.object = "" if path is None else f"<b>{escape(str(path))}</b> exists: replace it?"

    async def _on_confirm(self, event=None) -> None:
        pending, self._pending = self._pending, None
        self._ask(None)
        if pending is not None:
            await pending()

    def save(self, replace: bool = False) -> None:
        name = self.save_path.value
        try:
            path = self.session.save(name, replace=replace)
        except FileExists as exc:
            async def again():
                self.save(replace=True)
            self._ask(again, exc.path)
            self.say(f"{exc.path} exists: replace it, or choose another name", "info")
        except USER_ERRORS as exc:
            self.say(str(exc), "error")
        except OSError as exc:
            self.say(f"cannot write {name}: {exc.strerror}", "error")
        else:
            self._ask(None)
            self.say(f"wrote {path.resolve()}", "ok")

    async def _run(self, what: str, job):
        self.progress.visible = self.progress.active = True
        for button in (self.optimize_button, self.report_button, self.reset_button):
            button.disabled = True
        self.say(what, "info")
        t0 = time.perf_counter()
        try:
            return await asyncio.get_running_loop().run_in_executor(None, job), time.perf_counter() - t0
        finally:
            self.progress.visible = self.progress.active = False
            for button in (self.optimize_button, self.report_button, self.reset_button):
                button.disabled = False

    async def _on_optimize(self, event=None) -> None:
        lanes = len(self.session.model.combinations)
        try:
            result, seconds = await self._run(f"optimizing from here: compiling and solving {lanes} lanes "
                                              f"(one per catalog combination) …", self.session.optimize)
        except USER_ERRORS as exc:
            self.say(str(exc), "error")
            return
        self.sync_widgets()
        self.refresh()
        state = "optimum" if result.feasible else "best compromise (infeasible: " + "; ".join(result.unmet) + ")"
        self.say(f"{state}: objective {fmt(result.objective)} in {seconds:.1f} s", "ok" if result.feasible else "error")

    async def _on_report(self, event=None, replace: bool = False) -> None:
        name = self.report_dir.value
        out = self.session.target(name)
        try:
            record, seconds = await self._run(f"writing the report of this point to {out} …",
                                              lambda: self.session.report(name, replace=replace))
        except FileExists as exc:
            self._ask(lambda: self._on_report(replace=True), exc.path)
            self.say(f"{exc.path} exists: replace it, or choose another name", "info")
            return
        except USER_ERRORS as exc:
            self.say(str(exc), "error")
            return
        self.say(f"wrote {Path(record['files']['html']).resolve()} in {seconds:.1f} s", "ok")


__all__ = ["ExplorerPage"]
