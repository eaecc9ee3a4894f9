"""Design reports: ``build_report(spec, out_dir)`` writes Markdown, HTML, JSON and figures.

Modules, one job each: :mod:`.inputs` (every numeric input of a design as one vector),
:mod:`.batch` (one compiled evaluation with directional derivatives), :mod:`.jacobian`
(derivatives, elasticities, finite-difference check), :mod:`.postoptimal` (shadow prices and
d optimum / d limit), :mod:`.sweeps` (range, false-alarm and coverage data), :mod:`.figures`
(PNG figures), :mod:`.content` (the report's text), :mod:`.render` (Markdown/HTML/JSON) and
:mod:`.build` (the assembly).

The names are imported on first use, so that the figure modules load without the design
layer (a figure-drawing worker process, :mod:`.drawing`, imports only them).
"""

__all__ = ["build_report", "FIGURE_DIR"]


def __getattr__(name):
    # PEP 562: resolve the public names on first use (an ordinary import)
    if name in __all__:
        from diffsense.report import build as _m

        value = getattr(_m, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'diffsense.report' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
