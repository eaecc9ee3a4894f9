"""The five standard tests of a table of scalar model functions, built once for every test module.

A module states its table ``SPECS`` of ``(name, fn, domain, bad[, smooth])`` rows (see
:mod:`helpers.function_checks`) and its tolerances, and adopts the tests with::

    globals().update(function_suite(SPECS, jit_rel=1e-12, vmap_rtol=1e-12, value_floor=1e-300))

Each test is parametrised over the rows, with the row's name as its id:

* ``test_jit_matches_eager`` — jit equals eager (``jit_rel``, ``jit_atol``);
* ``test_vmap_matches_loop`` — vmap equals a loop (``vmap_rtol``; plain broadcasting too when
  ``broadcast``);
* ``test_gradient_matches_central_difference`` — gradient equals finite differences at two
  interior points (``value_floor``);
* ``test_gradient_finite_over_domain`` — hypothesis (30 examples, no deadline) draws a point of
  the domain: the gradient is finite there, and equals finite differences where the row is smooth
  (its fifth entry, True when absent), with the rounding scale ``term_scales[name]`` for rows
  whose value is a difference of larger terms;
* ``test_out_of_domain_raises`` — over the rows that list out-of-domain values: each raises
  DomainError.

A table of one-argument cases ``{name: (fn, args, i, (lo, hi))}`` — ``fn(*args)`` varied in its
argument ``i`` over [lo, hi] — adopts its two tests with ``globals().update(argument_suite(CASES))``.
"""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.function_checks import (
    assert_argument_case,
    assert_argument_gradient_finite,
    assert_gradient_finite,
    assert_gradient_matches_fd,
    assert_jit_matches_eager,
    assert_out_of_domain_raises,
    assert_vmap_matches_loop,
)


def function_suite(specs, *, jit_rel, vmap_rtol, value_floor, jit_atol=0.0, broadcast=False, term_scales=None):
    """``{test name: test function}`` of the five checks over ``specs`` with these tolerances."""
    over_specs = pytest.mark.parametrize("spec", specs, ids=[s[0] for s in specs])
    with_bad = [s for s in specs if s[3]]
    term_scales = dict(term_scales or {})

    @over_specs
    def test_jit_matches_eager(spec):
        assert_jit_matches_eager(spec, rel=jit_rel, atol=jit_atol)

    @over_specs
    def test_vmap_matches_loop(spec):
        assert_vmap_matches_loop(spec, rtol=vmap_rtol, broadcast=broadcast)

    @over_specs
    def test_gradient_matches_central_difference(spec):
        assert_gradient_matches_fd(spec, value_floor=value_floor)

    @over_specs
    @settings(max_examples=30, deadline=None)
    @given(data=st.data())
    def test_gradient_finite_over_domain(spec, data):
        u = [data.draw(st.floats(0.0, 1.0)) for _ in spec[2]]
        smooth = spec[4] if len(spec) > 4 else True
        assert_gradient_finite(spec, u, value_floor=value_floor, smooth=smooth, term_scale=term_scales.get(spec[0]))

    @pytest.mark.parametrize("spec", with_bad, ids=[s[0] for s in with_bad])
    def test_out_of_domain_raises(spec):
        assert_out_of_domain_raises(spec)

    tests = (test_jit_matches_eager, test_vmap_matches_loop, test_gradient_matches_central_difference,
             test_gradient_finite_over_domain, test_out_of_domain_raises)
    return {test.__name__: test for test in tests}


def argument_suite(cases):
    """``{test name: test function}`` over the one-argument ``cases``, parametrised by their sorted
    names: ``test_jit_vmap_and_gradient_match`` (jit and vmap equal eager, the derivative equals a
    central difference: :func:`helpers.function_checks.assert_argument_case`) and
    ``test_gradient_finite_over_domain`` (hypothesis, 30 examples, no deadline: the derivative is
    finite at a drawn point of [lo, hi])."""
    over_names = pytest.mark.parametrize("name", sorted(cases))

    @over_names
    def test_jit_vmap_and_gradient_match(name):
        fn, args, i, _ = cases[name]
        assert_argument_case(fn, args, i)

    @over_names
    @settings(max_examples=30, deadline=None)
    @given(u=st.floats(0.0, 1.0))
    def test_gradient_finite_over_domain(name, u):
        fn, args, i, (lo, hi) = cases[name]
        assert_argument_gradient_finite(fn, args, i, lo, hi, u)

    return {test.__name__: test for test in (test_jit_vmap_and_gradient_match, test_gradient_finite_over_domain)}
