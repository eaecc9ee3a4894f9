"""A live design explorer: every design variable on a slider, the link budget, SNR and Pd
against range, the stoplight requirements, the objective and the elasticities recomputed as
the sliders move; "optimize from here", "reset to spec", "save as TOML" and "report".

``diffsense explore DESIGN.toml`` serves it as a local web page and
``diffsense.explore(spec_or_path)`` shows it in a Jupyter cell (both with Panel, which needs the
``explore`` extra: ``pip install 'diffsense[explore]'``). :mod:`.session` holds the point and
computes everything the page shows; :mod:`.program` is the compiled program it evaluates;
:mod:`.spec_file` writes the spec with the current point; :mod:`.page`, :mod:`.figures` and
:mod:`.tables` draw; :mod:`.server` serves.
"""

import sys
import types

from diffsense.explore.session import ExplorerSession


def explore(spec_or_path):
    """The explorer of a spec as a Panel object (a Jupyter cell ending with it shows it)."""
    from diffsense.explore.server import explore as _explore

    return _explore(spec_or_path)


__all__ = ["explore", "ExplorerSession"]


class _CallableModule(types.ModuleType):
    """``diffsense.explore`` is both this package and the function :func:`explore`: importing
    the package binds the name ``diffsense.explore`` to it, so calling the package calls the function."""

    def __call__(self, spec_or_path):
        return explore(spec_or_path)


sys.modules[__name__].__class__ = _CallableModule
