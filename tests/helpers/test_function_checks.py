"""The finite-difference gradient checker used by the model-function tables rejects wrong gradients.

Its step shortens near domain edges and its tolerance grows as the step shrinks, so it must still
fail on a gradient that is wrong by a small relative amount, wherever it is evaluated.
"""

import jax.numpy as jnp
import pytest

from diffsense.sensors import radiometer as rm

from helpers.function_checks import check_grad_vs_fd, jitted

CONTRAST = [(0.0, 1.0, 0), (1.0, 400.0, 0), (0.0, 1.0, 0), (1.0, 400.0, 0), (1.0, 300.0, 0)]
POINTS = [[0.3, 100.0, 0.6, 200.0, 50.0], [0.0, 1.0, 0.0, 1.0, 1.0077441], [1.0, 400.0, 0.0, 1.0, 300.0]]


def _scaled(grad_j, factor, index):
    def wrong(*args):
        g = list(grad_j(*args))
        g[index] = g[index] * factor
        return tuple(g)
    return wrong


@pytest.mark.parametrize("args", POINTS)
def test_true_gradient_passes(args):
    fn_j, grad_j = jitted("contrast", rm.brightness_contrast_k, 5)
    check_grad_vs_fd(fn_j, grad_j, args, CONTRAST, rtol=1e-5, term_scale=lambda a: max(a[1], a[3], a[4]))


@pytest.mark.parametrize("args", POINTS)
@pytest.mark.parametrize("factor", [1.001, 0.999, -1.0])
def test_gradient_wrong_by_a_tenth_of_a_percent_fails(args, factor):
    fn_j, grad_j = jitted("contrast", rm.brightness_contrast_k, 5)
    for index in range(5):
        wrong = _scaled(grad_j, factor, index)
        if float(grad_j(*args)[index]) == 0.0:
            continue
        with pytest.raises(AssertionError, match=f"argument {index}"):
            check_grad_vs_fd(fn_j, wrong, args, CONTRAST, rtol=1e-5, term_scale=lambda a: max(a[1], a[3], a[4]))


def test_gradient_of_a_smooth_function_near_a_square_root_edge():
    # sqrt(x) on [0, 1] at x = 1e-7: the central step must shorten, and a 0.1 % error still fails
    fn_j, grad_j = jitted("sqrt", lambda x: jnp.sqrt(x), 1)
    check_grad_vs_fd(fn_j, grad_j, [1e-7], [(0.0, 1.0, 0)], rtol=1e-5)
    with pytest.raises(AssertionError):
        check_grad_vs_fd(fn_j, _scaled(grad_j, 1.001, 0), [1e-7], [(0.0, 1.0, 0)], rtol=1e-5)
