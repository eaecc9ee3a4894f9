"""Design reports: ``build_report(spec, out_dir)`` writes Markdown, HTML, JSON and figures.

Modules, one job each: :mod:`.inputs` (every numeric input of a design as one vector),
:mod:`.batch` (one compiled evaluation with directional derivatives), :mod:`.jacobian`
(derivatives, elasticities, finite-difference check), :mod:`.postoptimal` (shadow prices and
d optimum / d limit), :mod:`.sweeps` (range, false-alarm and coverage data), :mod:`.figures`
(PNG figures), :mod:`.content` (the report's text), :mod:`.render` (Markdown/HTML/JSON) and
:mod:`.build` (the assembly).
"""

from diffsense.report.build import FIGURE_DIR, build_report

__all__ = ["build_report", "FIGURE_DIR"]
