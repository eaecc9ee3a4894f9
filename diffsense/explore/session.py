"""The state of one live exploration and everything computed from it, without any display.

:class:`ExplorerSession` holds a spec, its :class:`~diffsense.design.model.DesignModel`, the
report's input vector (:func:`diffsense.report.inputs.design_inputs`) and the compiled
:class:`~diffsense.explore.program.ExplorerProgram`; the current point is that vector plus the
current catalog combination. Every change (a slider, a catalog option, a typed value) updates
the vector, and :meth:`ExplorerSession.snapshot` evaluates it: link budgets, outputs,
requirement rows with their stoplight status, objective, range sweeps and elasticities. The page
(:mod:`diffsense.explore.page`) only draws snapshots.

Typed values are validated by reading the spec with the value written in
(:func:`diffsense.explore.spec_file.checked_spec`), so a bad value raises the
:class:`~diffsense.errors.SpecError` the command line would print for the same spec.
"""

from __future__ import annotations

import copy
import time
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

from diffsense.design.activity import requirement_status as design_status
from diffsense.design.model import DesignModel
from diffsense.design.spec import Spec
from diffsense.errors import SpecError
from diffsense.explore import spec_file
from diffsense.explore.program import ExplorerProgram, range_grid
from diffsense.report.inputs import design_inputs, input_vector
from diffsense.report.jacobian import elasticity_matrix
from diffsense.report.sweeps import budget_rows

#: a met requirement is shown *active* when its slack is at most this, in the model's scaled
#: units (dB, degrees and plain numbers absolute; other units relative to the limit): a design
#: set by hand is not converged onto its limits, so the explorer's tolerance is wider than an
#: optimum's (:data:`diffsense.design.activity.ACTIVE_SLACK`)
ACTIVE_SLACK = 1e-3
#: the output shown as each case's headline, in order of preference
HEADLINE_OUTPUTS = ("snr_db", "sinr_db", "signal_excess_db", "snr_margin_db")


def requirement_status(met: bool, scaled_slack: float) -> str:
    """Stoplight of one requirement: "unmet", "active" (met, slack ≤ :data:`ACTIVE_SLACK`) or "met"
    (:func:`diffsense.design.activity.requirement_status` at the explorer's tolerance)."""
    return design_status(met, scaled_slack, ACTIVE_SLACK)


def _source(spec_or_path) -> Tuple[Path, str]:
    if isinstance(spec_or_path, Spec):
        path = Path(spec_or_path.path)
    else:
        path = Path(spec_or_path)
    try:
        return path, path.read_text()
    except OSError as exc:
        raise SpecError(path, "", f"cannot read the file: {exc.strerror}") from None


def default_output_folder(spec_path) -> Path:
    """Where an exploration writes unless told otherwise: ``<spec name>_explored/`` beside the
    spec file (a folder of its own, so never the spec itself or the user's files beside it)."""
    from diffsense.report.files import safe_name

    spec_path = Path(spec_path)
    return spec_path.parent / f"{safe_name(spec_path.stem)}_explored"


class FileExists(ValueError):
    """The file or report folder asked for exists: the page asks before replacing it."""

    def __init__(self, path: Path):
        self.path = path
        super().__init__(f"{path} exists")


class ExplorerSession:
    """One exploration of the spec at ``spec_or_path`` (a TOML path or a loaded
    :class:`~diffsense.design.spec.Spec` read from a file); see the module docstring.

    Everything it writes goes into one folder, ``out_dir`` (default
    :func:`default_output_folder`), fixed when it starts: a file is named by the user, made a
    safe name (:func:`diffsense.report.files.safe_name`) and written there, never elsewhere."""

    def __init__(self, spec_or_path, out_dir=None):
        self.path, text = _source(spec_or_path)
        self.out_dir = Path(out_dir) if out_dir is not None else default_output_folder(self.path)
        self.document = spec_file.read_document(text)
        self.spec = spec_file.checked_spec(self.document, self.path)
        self.model = DesignModel(self.spec)
        self.inputs = design_inputs(self.model, self.model.initial, 0)
        self.program = ExplorerProgram(self.model, self.inputs)
        self.program.start()
        self._index = {inp.name: k for k, inp in enumerate(self.inputs)}
        self.variable_names: List[str] = list(self.model.variable_names)
        self.catalogs: Dict[str, List[str]] = {c: list(self.spec.choices[c].option_names)
                                               for c in self.model.choice_names}
        self.fixed_names: List[str] = [i.name for i in self.inputs if i.kind == "fixed"]
        self.last_eval_ms: Optional[float] = None
        #: the files this exploration wrote (shared by its forks): the only ones it replaces
        self.written: set = set()
        self.reset()

    def fork(self) -> "ExplorerSession":
        """A session on the same spec and compiled program, at the spec's initial point."""
        other = copy.copy(self)
        other.reset()
        return other

    # --- the current point ----------------------------------------------------------------
    def reset(self) -> None:
        """Back to the spec: initial design, first option of every catalog, fixed values as written."""
        self.v = input_vector(self.inputs).copy()
        self.options: Dict[str, int] = {c: 0 for c in self.catalogs}
        self.typed: Dict[str, Tuple[str, str]] = {}  # fixed input name -> (parameter, text)
        self._set_combination()

    def input(self, name: str):
        """The :class:`~diffsense.report.inputs.Input` called ``name``."""
        return self.inputs[self._index[name]]

    def value(self, name: str) -> float:
        """Current value of input ``name`` (its unit)."""
        return float(self.v[self._index[name]])

    @property
    def x(self) -> np.ndarray:
        """The design variables (model order, their units)."""
        return np.array([self.value(n) for n in self.variable_names])

    @property
    def combo_index(self) -> int:
        return self.model.combo_index({c: self.catalogs[c][k] for c, k in self.options.items()})

    def set_variable(self, name: str, value: float) -> float:
        """Move design variable ``name`` to ``value`` (clipped to its bounds, integers rounded);
        returns the value set."""
        var = self.spec.variables[name]
        value = float(np.clip(value, var.lower, var.upper))
        if var.integer:
            value = float(np.clip(round(value), np.ceil(var.lower), np.floor(var.upper)))
        self.v[self._index[name]] = value
        return value

    def set_option(self, catalog: str, option: str) -> None:
        """Pick ``option`` (its name) of ``catalog``."""
        names = self.catalogs[catalog]
        if option not in names:
            raise SpecError(self.path, f"choices.{catalog}", f"no option {option!r}; options: {names}")
        self.options[catalog] = names.index(option)
        self._set_combination()

    def _set_combination(self) -> None:
        row = self.model.combo_table[self.combo_index]
        for j, param in enumerate(self.model.combo_params):
            self.v[self._index[param]] = row[j]

    def type_variable(self, name: str, text: str) -> float:
        """Set design variable ``name`` from typed text ("250 mm"); raise :class:`SpecError`
        (the command line's message) when the value is not a valid initial value."""
        doc = spec_file.copy_document(self.document)
        for fixed, (param, typed) in self.typed.items():
            spec_file.set_fixed(doc, fixed, param, typed)
        doc["variables"][name]["initial"] = spec_file._toml_value(text)
        spec = spec_file.checked_spec(doc, self.path)
        return self.set_variable(name, spec.variables[name].initial)

    def type_fixed(self, name: str, text: str) -> float:
        """Set the fixed input ``name`` from typed text; raise :class:`SpecError` (the command
        line's message) when the spec with that value written in is invalid."""
        inp = self.input(name)
        typed = dict(self.typed)
        typed[name] = (inp.param, text)
        doc = spec_file.copy_document(self.document)
        for fixed, (param, value) in typed.items():
            spec_file.set_fixed(doc, fixed, param, value)
        spec = spec_file.checked_spec(doc, self.path)
        value = float(spec.fixed[inp.cases[0]][inp.param])
        self.typed = typed
        self.v[self._index[name]] = value
        return value

    # --- evaluation -----------------------------------------------------------------------
    def grids(self) -> list:
        """The range grid of every swept range input (m), around its current value."""
        return [range_grid(float(self.v[k]), self.inputs[k].lo, self.inputs[k].hi)
                for k in self.program.sweep_inputs]

    def evaluate(self, extras: bool = True, core: bool = True) -> dict:
        """The compiled programs at the current point (timed: :attr:`last_eval_ms`); without
        ``extras`` only the core (evaluations, requirements, objective); without ``core`` the
        quick evaluation instead (interval requirements NaN)."""
        combo = self.combo_index
        t0 = time.perf_counter()
        out = self.program.core(self.v, combo) if core else self.program.quick(self.v, combo)
        if extras:
            out.update(self.program.extras(self.v, combo, self.grids()))
        self.last_eval_ms = 1e3 * (time.perf_counter() - t0)
        return out

    def prepare_core(self) -> float:
        """Compile the core programs (with the interval requirements' search) by running them at
        the current point; returns the seconds it took."""
        t0 = time.perf_counter()
        self.program.core(self.v, self.combo_index)
        return time.perf_counter() - t0

    def prepare_extras(self) -> float:
        """Compile the extras' program (derivatives) by running the sweeps, interval curves and
        Jacobian at the current point; returns the seconds it took."""
        t0 = time.perf_counter()
        self.program.extras(self.v, self.combo_index, self.grids())
        return time.perf_counter() - t0

    def snapshot(self, extras: Optional[bool] = True) -> dict:
        """Everything the page shows at the current point (plain Python and NumPy values).

        ``extras``: True computes the range sweeps, interval curves and elasticities (compiling
        their program on first use); False leaves them empty (``sweeps`` and ``intervals`` {},
        ``elasticity`` None); None uses only what is compiled: the core once it is (else the
        quick program, whose interval requirements are shown as "pending"), the extras once
        they are."""
        core = True
        if extras is None:
            extras = self.program.extras_ready
            core = self.program.core_ready
        out = self.evaluate(extras, core)
        rows = self.model.requirement_rows(out["requirements"])
        for row, scale, r in zip(rows, self.model.scales, self.model.requirements):
            if not core and r.over:
                row["status"] = "pending"
            else:
                row["status"] = requirement_status(row["met"], row["slack"] / scale)
        cases = {}
        for case, ev in out["evaluations"].items():
            outputs = {k: float(np.asarray(v)) for k, v in ev.values.items() if np.ndim(v) == 0}
            headline = next((n for n in HEADLINE_OUTPUTS if n in outputs), None)
            cases[case] = {"budget": budget_rows(ev), "outputs": outputs, "headline": headline}
        return {"cases": cases, "requirements": rows, "objective": float(out["objective"]),
                "sweeps": self._sweeps(out) if extras else {},
                "intervals": self._intervals(out, rows) if extras else {},
                "elasticity": self._elasticity(out, rows) if extras else None,
                "eval_ms": self.last_eval_ms}

    def _intervals(self, out, rows) -> dict:
        """Per one-parameter interval requirement (by name): its parameter, the grid (parameter's
        unit), the output on it, the limit, the sense and the worst value the search found."""
        curves = {}
        for j in self.program.interval_requirements:
            r, row = self.model.requirements[j], rows[j]
            iv = r.over[0]
            curves[r.name] = {"parameter": iv.parameter, "unit": self.spec.unit_of(r.case, iv.parameter),
                              "output": r.output, "output_unit": row["unit"], "grid": self.program.interval_grids[j],
                              "values": np.asarray(out["intervals"][j], dtype=float), "limit": float(r.limit),
                              "sense": r.sense, "worst_value": float(row["value"]), "status": row["status"]}
        return curves

    def _sweeps(self, out) -> dict:
        grids = dict(zip(self.program.sweep_inputs, self.grids()))
        sweeps = {}
        for case, values in out["sweeps"].items():
            k = self.program.sweep_cases[case]
            data = {"range_m": grids[k], "design_range_m": float(self.v[k]), "outputs": values}
            margin = self.program.margin_outputs[case]
            req = next((r for r in self.model.requirements if r.case == case and r.output == margin), None)
            if req is not None and "snr_db" in values:
                data["threshold_db"] = values["snr_db"] - values[margin] + req.limit
                data["margin_requirement"] = req.name
            pd = next((k for k, i in enumerate(self.inputs) if i.param == "pd" and case in i.cases), None)
            data["required_pd"] = float(self.v[pd]) if pd is not None else None
            sweeps[case] = data
        return sweeps

    def output_labels(self) -> List[str]:
        """Names of the outputs whose elasticities the page offers: each requirement's output
        (``<case>.<output>`` with several cases), then "objective"."""
        several = len(self.spec.scenes) > 1
        return [f"{r.case}.{r.output}" if several else r.output for r in self.model.requirements] + ["objective"]

    def objective_unit(self) -> str:
        """The objective's unit: its one term's unit, or "" for a weighted sum."""
        terms = self.spec.objective.terms
        if len(terms) == 1 and terms[0][0] != "cost":
            name = terms[0][0]
            case, base = name.split(".", 1) if "." in name else (next(iter(self.spec.scenes)), name)
            return self.spec.unit_of(case, base)
        return ""

    def _elasticity(self, out, rows) -> np.ndarray:
        """Elasticities (outputs × inputs, :func:`diffsense.report.jacobian.elasticity_matrix`)."""
        units = [r["unit"] for r in rows] + [self.objective_unit()]
        values = [r["value"] for r in rows] + [float(out["objective"])]
        return elasticity_matrix(out["jacobian"], units, values, [i.unit for i in self.inputs], list(self.v),
                                 [r["output"] for r in rows] + [None], [i.param for i in self.inputs])

    # --- the spec with the current point ----------------------------------------------------
    def document_here(self):
        """The spec's TOML document with the current point (:mod:`diffsense.explore.spec_file`)."""
        initial = {n: (self.value(n), self.spec.variables[n].integer) for n in self.variable_names}
        return spec_file.write_point(self.document, initial=initial, options=self.options, fixed=self.typed)

    def target(self, name: str, suffix: str = "") -> Path:
        """The path in :attr:`out_dir` of a file or folder the user named ``name`` (any text:
        only its last component, made safe, is used; ``suffix`` added unless present)."""
        from diffsense.report.files import safe_name

        base = str(name).replace("\\", "/").rsplit("/", 1)[-1].strip()
        if suffix and base.endswith(suffix):
            base = base[:-len(suffix)]
        return self.out_dir / f"{safe_name(base or 'explored')}{suffix}"

    def save(self, name, replace: bool = False) -> Path:
        """Write the spec with the current point as its initial design to :meth:`target`
        (``name``.toml in the output folder); returns the path.

        An existing file raises :class:`FileExists` unless ``replace`` (the page asks the user
        first); the spec this exploration opened is never written over, whatever ``replace``
        (:class:`~diffsense.report.files.OutputError`); written atomically."""
        from diffsense.report.files import OutputError, write_atomically

        path = self.target(name, ".toml")
        if self.path is not None and path.exists() and Path(self.path).exists() and path.samefile(self.path):
            raise OutputError(f"{path}: refusing to write over the spec this explorer opened; choose another name")
        if path.is_dir():
            raise OutputError(f"{path}: is a folder; give a file name")
        if path.exists() and not replace:
            raise FileExists(path)
        doc = self.document_here()
        spec_file.checked_spec(doc, path)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, doc.as_string().encode("utf-8"))
        self.written.add(path.resolve())
        return path

    def spec_here(self) -> Spec:
        """The spec with the current point as its initial design (validated)."""
        return spec_file.checked_spec(self.document_here(), self.path)

    def optimize(self, n_starts: int = 1, seed: int = 0):
        """Optimise from the current point (it is the first start of every catalog combination;
        ``n_starts`` − 1 Latin-hypercube starts follow) with the current fixed values, then move
        the point to the optimum (with ``reach_goals``, the optimum after buying the goals,
        :mod:`diffsense.design.goals`). Returns the :class:`~diffsense.design.optimizer.DesignOptimum`."""
        from diffsense.design.goals import optimize_with_goals
        from diffsense.design.spec.limits import require_variables

        spec = self.spec_here()
        require_variables(spec)  # a SpecError the page shows: nothing to optimise
        model = DesignModel(spec)
        result, _ = optimize_with_goals(model, n_starts=n_starts, seed=seed)
        chosen = model.combinations[result.combo_index].options
        for catalog, option in chosen.items():
            self.options[catalog] = self.catalogs[catalog].index(option)
        self._set_combination()
        for name, value in zip(model.variable_names, result.x):
            self.set_variable(name, float(value))
        return result

    def report(self, name, replace: bool = False) -> dict:
        """Write the static report of the current point (:func:`diffsense.build_report`, not
        optimised) into the folder :meth:`target` ``name`` of the output folder, with the spec
        of the point beside it; returns its record. A folder that exists raises
        :class:`FileExists` unless ``replace`` (files diffsense did not write there are never
        replaced: :class:`~diffsense.report.files.OutputError`)."""
        from diffsense.report import build_report

        from diffsense.report.build import report_folder
        from diffsense.report.files import safe_name, write_atomically

        out_dir = self.target(name)
        if out_dir.exists() and any(out_dir.iterdir()) and not replace:
            raise FileExists(out_dir)
        spec_path = out_dir / f"{safe_name(self.spec.name)}.toml"  # the spec's name is data, not a path
        folder = report_folder(out_dir, spec_path)  # checked before anything is written
        doc = self.document_here()
        spec_file.checked_spec(doc, spec_path)
        write_atomically(spec_path, doc.as_string().encode("utf-8"))
        self.written.add(spec_path.resolve())
        return build_report(spec_path, folder, optimize=False)


__all__ = ["ExplorerSession", "FileExists", "default_output_folder", "requirement_status", "ACTIVE_SLACK",
           "HEADLINE_OUTPUTS"]
